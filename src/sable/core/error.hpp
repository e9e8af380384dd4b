// Errors that reach the user. Every message names where the problem is (file, key, line) and
// what was expected; the CLI prints `what()` and exits with the code of the error's kind
// (docs/reliability.md lists them): bad input 2, a failed simulation 1, an output that could
// not be written 3.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>

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

// How many characters of an input (a name, a key, a value, a path) a message quotes.
inline constexpr std::size_t kQuoteLimit = 120;

// `text` as quoted in a message: at most `limit` characters, then "... (N characters)" with
// the whole length, so that a hostile 200,000-character name gives a short message. The cut
// never splits a UTF-8 sequence, and control characters (a newline in a name) become '?' so
// that a message stays on its lines.
inline std::string clip(std::string_view text, std::size_t limit = kQuoteLimit) {
  std::size_t end = text.size();
  if (end > limit) {
    end = limit;
    while (end > 0 && (static_cast<unsigned char>(text[end]) & 0xC0) == 0x80) --end;
  }
  std::string out(text.substr(0, end));
  for (char& c : out)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
  if (end < text.size()) out += "... (" + std::to_string(text.size()) + " characters)";
  return out;
}

}  // namespace sable
