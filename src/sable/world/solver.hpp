// The narrow interface every time stepper implements (DEM now, contact dynamics next).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "sable/core/phase_timer.hpp"

namespace sable {

struct StepDiagnostics {
  double max_overlap_ratio = 0.0;  // largest overlap / smaller radius seen in the last step
  std::size_t touching = 0;        // contacts carrying force in the last step (grain + wall)
  // Implicit solvers (contact dynamics): the last step's iterations and whether they converged.
  int iterations = 0;
  double residual = 0.0;
  bool converged = true;
  // DEM: near-list remakes since the solver started (dem/near_list.hpp; a resumed run starts
  // again from 0), a running count, not per step.
  std::uint64_t near_remakes = 0;
};

// A wall the solver moves as a rigid body with one translational degree of freedom along its
// normal, under a constant applied force: a stress-controlled wall with rigid grains
// (loading/servo.hpp), whose velocity (Wall::velocity) is then an unknown of the step.
struct WallBody {
  std::size_t wall = 0;    // index into World::walls: a plane wall
  double force = 0.0;      // N, along the wall's normal: pushing into the grains
  double mass = 0.0;       // kg, > 0
  double max_speed = 0.0;  // m/s: the wall's speed is capped there (0: no cap)
};

class Solver {
 public:
  virtual ~Solver() = default;
  virtual std::string_view name() const = 0;
  // Prepare a fresh world (neighbour lists, initial forces). Not called when resuming: the
  // snapshot already holds the lists, history and forces of the step it was taken at.
  virtual void initialize() = 0;
  // Advance the world by one time step.
  virtual void step() = 0;
  virtual const StepDiagnostics& diagnostics() const = 0;
  virtual const PhaseTimers& timers() const = 0;
  // Stress-controlled walls. A solver that moves them itself as bodies under a force (contact
  // dynamics: rigid grains give a velocity servo no stiffness to act on) says so here and is
  // given them before each step; for the others (DEM) the runner sets their velocities.
  virtual bool moves_wall_bodies() const { return false; }
  // The walls to move as bodies from the next step on; replaces the last list (empty: none).
  virtual void set_wall_bodies(const std::vector<WallBody>& /*bodies*/) {}
  // Solver-specific columns of the CSV time series (e.g. NLGS iterations and residual).
  virtual std::vector<std::string> diagnostic_columns() const { return {}; }
  virtual void diagnostic_values(std::vector<double>& /*row*/) const {}
};

}  // namespace sable
