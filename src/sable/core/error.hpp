// Errors that reach the user. Every message names where the problem is (file, key, line) and
// what was expected; the CLI prints `what()` and exits with the code of the error's kind
// (docs/reliability.md lists them): bad input 2, a failed simulation 1, an output that could
// not be written 3.
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

// An output could not be written (disk full, no permission, file size limit): the message
// names the file and the system's reason. Outputs are written atomically, so every file that
// was complete before the failure still is.
class IoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace sable
