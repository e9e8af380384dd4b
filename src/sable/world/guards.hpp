// Run-time guards shared by every solver: a non-finite or runaway grain stops the run.
#pragma once

#include <fmt/format.h>
#include <cmath>

#include "sable/core/error.hpp"
#include "sable/core/parallel.hpp"
#include "sable/world/world.hpp"

namespace sable {

// A grain's state is sound: finite, and no faster than max_speed; in two halves, the
// velocities and the position.
template <int D>
[[gnu::always_inline]] inline bool motion_ok(const typename Space<D>::Vec& v,
                                             const typename Space<D>::Rot& w, double max_speed) {
  return v.squaredNorm() <= max_speed * max_speed && std::isfinite(Space<D>::rot_norm2(w));
}

// x - x is exactly 0 for a finite x and NaN otherwise: a branch-free test, where Eigen's
// allFinite() branches per component (a fused grain loop spends about 16 % of its perf
// samples in it).
template <int D>
[[gnu::always_inline]] inline bool position_ok(const typename Space<D>::Vec& x) {
  // NOLINTNEXTLINE(misc-redundant-expression): x - x is the finiteness test described above.
  return (x - x).squaredNorm() == 0.0;
}

template <int D>
bool grain_state_ok(const World<D>& w, std::size_t k) {
  const auto& p = w.particles;
  return motion_ok<D>(p.v[k], p.omega[k], w.max_speed) && position_ok<D>(p.x[k]);
}

// Throws SimulationError naming the step and the first offending grain (by stable id). The
// scan for a bad grain runs in parallel; the rare report is made serially, so the grain named
// is always the first one whatever the number of threads.
template <int D>
void check_grain_states(const World<D>& w) {
  const auto& p = w.particles;
  const auto n = static_cast<std::ptrdiff_t>(p.size());
  int bad = 0;
#pragma omp parallel for schedule(static) reduction(| : bad) if (n >= kMinParallelScan)
  for (std::ptrdiff_t k = 0; k < n; ++k)
    bad |= grain_state_ok(w, static_cast<std::size_t>(k)) ? 0 : 1;
  if (!bad) return;
  for (std::size_t k = 0; k < p.size(); ++k) {
    if (grain_state_ok(w, k)) continue;
    const double v2 = p.v[k].squaredNorm();
    const bool finite =
        std::isfinite(v2) && std::isfinite(Space<D>::rot_norm2(p.omega[k])) && p.x[k].allFinite();
    throw SimulationError(fmt::format(
        "step {}: grain id {} has {} (speed {:.4g} m/s, max_speed {:.4g} m/s); the time step "
        "may be too large for the contact stiffness, or grains were inserted overlapping",
        w.step, p.id[k].index, finite ? "run away" : "a non-finite state", std::sqrt(v2),
        w.max_speed));
  }
}

}  // namespace sable
