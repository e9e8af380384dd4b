// Running a scenario: stages, outputs, snapshots, progress. The physics of one step lives in
// the solver (dem/dem_solver_impl.hpp: DemSolver::step); this file only decides when to stop and
// what to write.
#pragma once

#include <csignal>
#include <cstdint>
#include <iostream>
#include <optional>
#include <string>

#include "sable/scenario/config.hpp"
#include "sable/world/domain.hpp"

namespace sable {

struct RunOptions {
  std::string out_dir;  // overrides [output].dir when non-empty
  int threads = 0;      // 0 = leave OpenMP's default
  std::string resume;   // snapshot to resume from (empty = fresh run)
  std::ostream* log = &std::cerr;
  std::optional<bool> live_progress;  // default: when the log is a terminal
  bool write_outputs = true;          // false: no files at all (tests, `sable check`)
  // Output folder and resume rules (scenario/output_folder.hpp, scenario/resume_changes.hpp).
  bool overwrite = false;       // delete the folder's conflicting outputs instead of refusing
  bool accept_changes = false;  // resume although the scenario's physics changed
  // Set (to a signal number) by a signal handler: the run stops after the current step,
  // writes snapshots/interrupted_step_N.h5 and returns with RunResult::interrupted_by set.
  const volatile std::sig_atomic_t* stop = nullptr;
  // Under MPI: makes each process's Domain (apps/sable/launch_mpi.cpp); null: a serial run.
  const DomainMaker* domains = nullptr;
};

struct RunResult {
  std::uint64_t steps = 0;  // global step at the end
  double time = 0.0;        // simulated time at the end (s)
  std::uint64_t state_hash = 0;
  std::size_t grains = 0;
  double kinetic_energy = 0.0;
  double wall_seconds = 0.0;
  int interrupted_by = 0;     // the signal that stopped the run early, 0 if it ran to the end
  std::string last_snapshot;  // the snapshot written when it stopped (interrupted runs)
};

RunResult run_scenario(const ScenarioConfig& cfg, const RunOptions& opt);

// Build the world (grains generated) and report what it holds, without stepping.
std::string describe_scenario(const ScenarioConfig& cfg);

}  // namespace sable
