// Running a scenario text through the runner, quietly, for end-to-end tests.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "sable/scenario/config.hpp"
#include "sable/scenario/runner.hpp"

namespace sable::test {

struct QuietRun {
  std::string resume;   // snapshot to resume from, or empty
  bool outputs = true;  // write files (into the scenario's [output].dir)
  int threads = 0;      // 0: OpenMP's default
  // Resume under a scenario whose physics differs from the snapshot's (--accept-changes).
  bool accept_changes = false;
  // Delete the folder's outputs that conflict with this run (--overwrite): a resume into the
  // folder of the run it continues meets that run's later snapshots.
  bool overwrite = false;
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
  opt.accept_changes = how.accept_changes;
  opt.overwrite = how.overwrite;
  return run_scenario(cfg, opt);
}

// The whole text of a file ("" if it cannot be read).
inline std::string slurp(const std::filesystem::path& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// A CSV file of numbers (series.csv, an analysis table) as columns by name; `names`, when
// given, gets the header's names in order. A cell that is not a number throws (std::stod).
inline std::map<std::string, std::vector<double>> read_csv_columns(
    const std::filesystem::path& path, std::vector<std::string>* names = nullptr) {
  std::istringstream in(slurp(path));
  std::string line, cell;
  std::getline(in, line);
  std::vector<std::string> header;
  for (std::stringstream h(line); std::getline(h, cell, ',');) header.push_back(cell);
  std::map<std::string, std::vector<double>> cols;
  while (std::getline(in, line)) {
    std::stringstream row(line);
    for (std::size_t c = 0; c < header.size() && std::getline(row, cell, ','); ++c)
      cols[header[c]].push_back(std::stod(cell));
  }
  if (names) *names = header;
  return cols;
}

// Run the `sable` executable with `args`, its stdout and stderr into `log`; returns its exit
// status and puts what it printed in `output`.
inline int run_cli(const std::string& args, const std::filesystem::path& log, std::string& output) {
  const std::string cmd = std::string(SABLE_CLI) + " " + args + " > " + log.string() + " 2>&1";
  const int status = std::system(cmd.c_str());
  output = slurp(log);
  return WEXITSTATUS(status);
}

// 120 disks poured into a 2D box, a "fall" stage then a "settle" stage, by DEM or by CD
// (snapshots at the end of each stage under `out`): a small flowing then settled packing.
inline std::string small_pour_2d(const std::string& out, const std::string& solver) {
  std::ostringstream s;
  const bool cd = solver == "cd";
  s << "[simulation]\ndimension = 2\nseed = 5\nsolver = \"" << solver << "\"\n"
    << (cd ? "dt = 2e-4\n" : "") << "gravity = [0, -9.81]\nthickness = 0.002\n"
    << "[domain]\nlo = [0, 0]\nhi = [0.03, 0.04]\n"
    << "[[material]]\nname = \"g\"\ndensity = 2500.0\nyoung = 5e6\npoisson = 0.45\n"
    << "restitution = 0.3\nfriction = 0.4\n"
    << (cd ? "[cd]\nsweep = \"shuffled\"\ntolerance = 1e-5\nmax_iterations = 500\n" : "")
    << "[[grains]]\ngenerator = \"random\"\nmaterial = \"g\"\n"
    << "radius = { distribution = \"uniform\", mean = 1e-3, spread = 0.2 }\n"
    << "region = { box = { lo = [0, 0], hi = [0.03, 0.04] } }\ncount = 120\n"
    << "[[wall]]\nname = \"box\"\ntype = \"box\"\nmaterial = \"g\"\nlo = [0, 0]\n"
    << "hi = [0.03, 0.04]\n"
    << "[[stage]]\nname = \"fall\"\nsteps = " << (cd ? 150 : 600) << "\n"
    << "[[stage]]\nname = \"settle\"\nsteps = " << (cd ? 600 : 12000) << "\n"
    << "[output]\ndir = \"" << out << "\"\ncsv_interval = 0\nsnapshot_interval = 0\n"
    << "vtk_interval = 0\nlog_interval = 0\n";
  return s.str();
}

}  // namespace sable::test
