// Progress reporting: a live, rewritten line on a terminal; plain periodic lines otherwise.
#pragma once

#include <chrono>
#include <cstdint>
#include <ostream>
#include <string>

namespace sable {

struct ProgressSample {
  std::string stage;
  std::uint64_t step = 0;         // global step
  std::uint64_t stage_step = 0;   // steps into the stage
  std::uint64_t stage_total = 0;  // steps the stage will take (0 when unknown)
  double time = 0.0;              // simulated time (s)
  double kinetic_energy = 0.0;    // J
  std::size_t contacts = 0;
  std::size_t grains = 0;
};

class ProgressReporter {
 public:
  ProgressReporter(std::ostream& out, bool live, std::uint64_t log_interval)
      : out_(out), live_(live), log_interval_(log_interval) {}
  // Called every step with a cheap predicate; samples are built only when a report is due.
  bool due(std::uint64_t step) const;
  void report(const ProgressSample& s);
  void finish_line();  // end a live line before other messages
  void message(const std::string& text);

 private:
  using Clock = std::chrono::steady_clock;
  std::ostream& out_;
  bool live_;
  std::uint64_t log_interval_;
  Clock::time_point last_ = Clock::now();
  Clock::time_point start_ = Clock::now();
  std::uint64_t last_step_ = 0;
  bool line_open_ = false;
};

}  // namespace sable
