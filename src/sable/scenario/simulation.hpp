// A scenario being run: the world, its solver, its stages and its outputs, advanced one step
// at a time. `sable run` is `Simulation<D>(cfg, opt).run()`; the Python module drives the same
// object a step, a stage or a run at a time, so both give the same bits.
//
// The stage sequence: a stage is entered (its wall motions set and its water added, at its
// first step only; its stress-controlled walls loaded), then stepped until its rule holds
// (a step count, or a kinetic energy and a wall-stress error checked every check_interval
// steps, with a step cap), then left (its summary line, a VTK frame and the snapshot
// end_of_stage_K.h5). The rule is checked before each step, so a stage whose rule already
// holds takes no step. advance() takes exactly one step, leaving the stages that have ended
// and entering the next first; a stage's end outputs are therefore written when the next
// step is asked for, or by finish_ended_stage().
//
// Under MPI (RunOptions::domains) every process runs this object in step: each builds or
// loads the whole world, keeps its share (Domain::scatter) and steps it; the decisions
// (a stage's end, a warning, a stop on a signal or a failed grain) come from global values;
// outputs gather the whole state on process 0, which alone writes and logs.
#pragma once

#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sable/core/error.hpp"
#include "sable/io/csv.hpp"
#include "sable/io/snapshot.hpp"
#include "sable/io/vtk.hpp"
#include "sable/loading/box_state.hpp"
#include "sable/loading/servo.hpp"
#include "sable/scenario/config.hpp"
#include "sable/scenario/progress.hpp"
#include "sable/scenario/runner.hpp"
#include "sable/world/domain.hpp"
#include "sable/world/solver.hpp"
#include "sable/world/world.hpp"

namespace sable {

template <int D>
class Simulation {
 public:
  // Builds the model (not yet the grains: start() does, or loads opt.resume).
  Simulation(ScenarioConfig cfg, const RunOptions& opt);
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  // The grains generated (or the snapshot loaded), the output folder prepared, the first
  // frame written. Called by the first advance() if not before.
  void start();
  // One step, leaving ended stages and entering the next first. False, with no step taken,
  // once every stage has ended (their end outputs written). A SimulationError (a grain gone
  // non-finite) writes snapshots/crash_step_N.h5 first and propagates.
  bool advance();
  // Leave the current stage if its rule holds now (its end outputs), without stepping.
  void finish_ended_stage();
  bool finished() const { return pos_.stage >= cfg_.stages.size(); }
  // Everything left, as `sable run` does; stops early at opt.stop (interrupted_step_N.h5).
  RunResult run();
  RunResult result() const;

  // Write the current state as a snapshot at `path` (atomically), with its XDMF sidecar
  // beside it (`path` with .xmf). The run's own snapshots keep theirs in OUT/xdmf/.
  void save(const std::string& path) const;

  // Between steps: the walls `name` names (a wall, or a box's six) given a translation
  // velocity, a rotation (about the axis through `point`, rad/s), or a stress target
  // (Pa; the stage's servo settings, its servo_max_velocity replaced by `max_velocity` when
  // > 0, which a stage without stress targets needs) for the rest of the current stage: the
  // next stage's own settings replace them at its start, as a stage's replace the last one's.
  // A name that names no wall throws InputError.
  void set_wall_velocity(const std::string& name, const typename Space<D>::Vec& v);
  void set_wall_rotation(const std::string& name, const typename Space<D>::Vec& point,
                         const typename Space<D>::Vec& axis, double rate);
  void set_wall_stress(const std::string& name, double stress, double max_velocity = 0.0);

  World<D>& world() { return world_; }
  const World<D>& world() const { return world_; }
  const ScenarioConfig& config() const { return cfg_; }
  const RunPosition& position() const { return pos_; }
  const Solver& solver() const { return *solver_; }

 private:
  void save(const std::filesystem::path& path, const std::filesystem::path& sidecar) const;
  void setup();
  std::vector<std::size_t> named_walls(const std::string& name);
  void check_changes(const std::string& snapshot_text);
  void adopt_scenario_steps();
  void open_outputs(bool resuming);
  void enter_stage();
  void leave_stage();
  void one_step();
  void start_stage();
  void wet();
  bool stage_done();
  void load_servo_targets();
  void after_step();
  void write_frame();
  void write_snapshot(const std::string& file);
  void write_csv_row();
  RunResult interrupted();
  SimulationError crashed(const SimulationError& e);
  void agree_after_step(const SimulationError* failure);
  bool stop_requested() const;
  // The whole state (collective under MPI: every process calls it at the same point, and
  // only process 0's copy holds every grain); world_ itself in a serial run.
  const World<D>& whole() const;
  bool root() const { return domain_->rank() == 0; }
  ProgressSample sample() const;
  // Wall clock and phase timers at the start of a stage, for its summary line.
  struct StageClock {
    StageClock(std::uint64_t s, const PhaseTimers& t) : step(s) {
      for (int k = 0; k < static_cast<int>(Phase::kCount); ++k)
        phase_seconds[k] = t.seconds(static_cast<Phase>(k));
    }
    std::uint64_t step;
    std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
    std::array<double, static_cast<int>(Phase::kCount)> phase_seconds{};
  };
  std::string stage_summary(const StageClock& c) const;

  ScenarioConfig cfg_;
  RunOptions opt_;
  std::filesystem::path out_;
  World<D> world_;
  std::unique_ptr<Domain<D>> domain_;  // the grains this process steps (a serial run: all)
  mutable World<D> whole_;             // whole()'s gathered copy, under MPI
  std::ostream quiet_{nullptr};        // the log of processes other than 0: discards
  ProgressReporter progress_;
  std::unique_ptr<Solver> solver_;
  RunPosition pos_;
  std::optional<CsvLog> csv_;
  std::optional<PvdSeries> grains_pvd_, contacts_pvd_, walls_pvd_;
  // Open only in a 3D world with polyhedral grains (a shape table).
  std::optional<PvdSeries> polyhedra_pvd_;
  std::vector<ServoTarget> servo_;         // this stage's stress-controlled walls
  std::optional<BoxState<D>> box_ref_;     // strain reference, if a box
  std::optional<StageClock> stage_clock_;  // set while in a stage
  double servo_max_velocity_ = 0.0;        // set_wall_stress's, for this stage (0: the stage's)
  std::chrono::steady_clock::time_point t0_ = std::chrono::steady_clock::now();
  bool started_ = false;
  double max_overlap_ = 0.0;  // the last step's largest overlap ratio, over every process
  int stop_signal_ = 0;       // under MPI: the signal some process caught, agreed by all
  bool warned_overlap_ = false;
  bool warned_unconverged_ = false;
};

}  // namespace sable
