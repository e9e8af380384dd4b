// Run-time guards shared by every solver: a non-finite or runaway grain stops the run.
#pragma once

#include <fmt/format.h>
#include <cmath>

#include "sable/core/error.hpp"
#include "sable/world/world.hpp"

namespace sable {

// Throws SimulationError naming the step and the first offending grain (by stable id).
template <int D>
void check_grain_states(const World<D>& w) {
  const auto& p = w.particles;
  const double vmax2 = w.max_speed * w.max_speed;
  for (std::size_t k = 0; k < p.size(); ++k) {
    const double v2 = p.v[k].squaredNorm();
    const bool finite =
        std::isfinite(v2) && std::isfinite(Space<D>::rot_norm2(p.w[k])) && p.x[k].allFinite();
    if (v2 <= vmax2 && finite) continue;
    throw SimulationError(fmt::format(
        "step {}: grain id {} has {} (speed {:.4g} m/s, max_speed {:.4g} m/s); the time step "
        "may be too large for the contact stiffness, or grains were inserted overlapping",
        w.step, p.id[k].index, finite ? "run away" : "a non-finite state", std::sqrt(v2),
        w.max_speed));
  }
}

}  // namespace sable
