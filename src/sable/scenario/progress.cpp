#include "sable/scenario/progress.hpp"

#include <fmt/format.h>

namespace sable {

bool ProgressReporter::due(std::uint64_t step) const {
  if (!live_) return log_interval_ > 0 && step % log_interval_ == 0;
  // Live: look at the clock every 64 steps only, and redraw at most twice a second.
  return step % 64 == 0 && Clock::now() - last_ > std::chrono::milliseconds(500);
}

void ProgressReporter::report(const ProgressSample& s) {
  if (s.step == last_step_ && s.step != 0) return;  // already reported this step
  const auto now = Clock::now();
  const double dt_wall = std::chrono::duration<double>(now - last_).count();
  const double rate = dt_wall > 0.0 ? static_cast<double>(s.step - last_step_) / dt_wall : 0.0;
  std::string eta = "?";
  if (s.stage_total > s.stage_step && rate > 0.0) {
    const auto secs = static_cast<long>(static_cast<double>(s.stage_total - s.stage_step) / rate);
    eta = fmt::format("{:02d}:{:02d}:{:02d}", secs / 3600, (secs / 60) % 60, secs % 60);
  }
  const std::string line = fmt::format(
      "[{}] step {} t={:.5g} s KE={:.4g} J contacts={} {:.0f} steps/s ({:.3g} grain-steps/s) "
      "ETA {}",
      s.stage, s.step, s.time, s.kinetic_energy, s.contacts, rate,
      rate * static_cast<double>(s.grains), eta);
  if (live_) {
    out_ << '\r' << line << "\x1b[K" << std::flush;
    line_open_ = true;
  } else {
    out_ << line << '\n' << std::flush;
  }
  last_ = now;
  last_step_ = s.step;
}

void ProgressReporter::finish_line() {
  if (line_open_) out_ << '\n' << std::flush;
  line_open_ = false;
}

void ProgressReporter::message(const std::string& text) {
  finish_line();
  out_ << text << '\n' << std::flush;
}

}  // namespace sable
