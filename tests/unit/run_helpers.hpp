// Running a scenario text through the runner, quietly, for end-to-end tests.
#pragma once

#include <sstream>
#include <string>

#include "sable/scenario/config.hpp"
#include "sable/scenario/runner.hpp"

namespace sable::test {

struct QuietRun {
  std::string resume;   // snapshot to resume from, or empty
  bool outputs = true;  // write files (into the scenario's [output].dir)
  int threads = 0;      // 0: OpenMP's default
};

inline RunResult run_text(const std::string& text, const QuietRun& how = {}) {
  const ScenarioConfig cfg = parse_scenario(text, "test.toml");
  RunOptions opt;
  std::ostringstream log;
  opt.log = &log;
  opt.live_progress = false;
  opt.resume = how.resume;
  opt.write_outputs = how.outputs;
  opt.threads = how.threads;
  return run_scenario(cfg, opt);
}

}  // namespace sable::test
