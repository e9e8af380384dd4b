// Run-time guards shared by every solver: a non-finite or runaway grain stops the run.
#pragma once

#include <fmt/format.h>
#include <cmath>

#include "sable/core/error.hpp"
#include "sable/world/world.hpp"

namespace sable {

// Throws SimulationError naming the step and the first offending grain (by stable id).
template <int D>
bool grain_state_ok(const World<D>& w, std::size_t k) {
  const auto& p = w.particles;
  const double v2 = p.v[k].squaredNorm();
  return v2 <= w.max_speed * w.max_speed && std::isfinite(Space<D>::rot_norm2(p.w[k])) &&
         p.x[k].allFinite();
}

// Throws SimulationError naming the step and the first offending grain (by stable id). The
// scan for a bad grain runs in parallel; the rare report is made serially, so the grain named
// is always the first one whatever the number of threads.
template <int D>
void check_grain_states(const World<D>& w) {
  const auto& p = w.particles;
  const auto n = static_cast<std::ptrdiff_t>(p.size());
  int bad = 0;
#pragma omp parallel for schedule(static) reduction(| : bad) if (n >= 4096)
  for (std::ptrdiff_t k = 0; k < n; ++k)
    bad |= grain_state_ok(w, static_cast<std::size_t>(k)) ? 0 : 1;
  if (!bad) return;
  for (std::size_t k = 0; k < p.size(); ++k) {
    if (grain_state_ok(w, k)) continue;
    const double v2 = p.v[k].squaredNorm();
    const bool finite =
        std::isfinite(v2) && std::isfinite(Space<D>::rot_norm2(p.w[k])) && p.x[k].allFinite();
    throw SimulationError(fmt::format(
        "step {}: grain id {} has {} (speed {:.4g} m/s, max_speed {:.4g} m/s); the time step "
        "may be too large for the contact stiffness, or grains were inserted overlapping",
        w.step, p.id[k].index, finite ? "run away" : "a non-finite state", std::sqrt(v2),
        w.max_speed));
  }
}

}  // namespace sable
