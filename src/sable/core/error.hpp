// Errors that reach the user. Every message names where the problem is (file, key, line) and
// what was expected; the CLI prints `what()` and exits non-zero.
#pragma once

#include <stdexcept>
#include <string>

namespace sable {

// Bad input: a scenario, snapshot, data file or command-line value that cannot be used.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The simulation itself went wrong (NaN, runaway grain, lost grain). Carries the step.
class SimulationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace sable
