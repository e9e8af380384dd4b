// The narrow interface every time stepper implements (DEM now, contact dynamics next).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "sable/dem/phase_timer.hpp"

namespace sable {

struct StepDiagnostics {
  double max_overlap_ratio = 0.0;  // largest overlap / smaller radius seen in the last step
  std::size_t touching = 0;        // contacts carrying force in the last step (grain + wall)
  // Implicit solvers (contact dynamics): the last step's iterations and whether they converged.
  int iterations = 0;
  double residual = 0.0;
  bool converged = true;
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
  // Solver-specific columns of the CSV time series (e.g. NLGS iterations and residual).
  virtual std::vector<std::string> diagnostic_columns() const { return {}; }
  virtual void diagnostic_values(std::vector<double>& /*row*/) const {}
};

}  // namespace sable
