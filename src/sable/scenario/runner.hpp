// Running a scenario: stages, outputs, snapshots, progress. The physics of one step lives in
// the solver (dem/dem_solver.cpp: DemSolver::step); this file only decides when to stop and
// what to write.
#pragma once

#include <cstdint>
#include <iostream>
#include <optional>
#include <string>

#include "sable/scenario/config.hpp"

namespace sable {

struct RunOptions {
  std::string out_dir;  // overrides [output].dir when non-empty
  int threads = 0;      // 0 = leave OpenMP's default
  std::string resume;   // snapshot to resume from (empty = fresh run)
  std::ostream* log = &std::cerr;
  std::optional<bool> live_progress;  // default: when the log is a terminal
  bool write_outputs = true;          // false: no files at all (tests, `sable check`)
};

struct RunResult {
  std::uint64_t steps = 0;  // global step at the end
  double time = 0.0;        // simulated time at the end (s)
  std::uint64_t state_hash = 0;
  std::size_t grains = 0;
  double kinetic_energy = 0.0;
  double wall_seconds = 0.0;
};

RunResult run_scenario(const ScenarioConfig& cfg, const RunOptions& opt);

// Build the world (grains generated) and report what it holds, without stepping.
std::string describe_scenario(const ScenarioConfig& cfg);

}  // namespace sable
