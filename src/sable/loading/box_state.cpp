#include "sable/loading/box_state.hpp"

#include <cmath>
#include <numbers>

#include "sable/loading/servo.hpp"

namespace sable {

template <int D>
std::optional<BoxState<D>> measure_box(const World<D>& w) {
  BoxState<D> b;
  std::array<bool, D> has_lo{}, has_hi{};
  for (std::size_t k = 0; k < w.walls.size(); ++k) {
    const Wall<D>& wall = w.walls[k];
    const int d = wall.facing_axis();
    if (d < 0) continue;
    const double x = wall.point[d];
    if (wall.normal()[d] > 0.0 && (!has_lo[d] || x > b.lo[d])) {
      b.lo[d] = x;
      b.lo_wall[d] = k;
      has_lo[d] = true;
    } else if (wall.normal()[d] < 0.0 && (!has_hi[d] || x < b.hi[d])) {
      b.hi[d] = x;
      b.hi_wall[d] = k;
      has_hi[d] = true;
    }
  }
  for (int d = 0; d < D; ++d)
    if (!has_lo[d] || !has_hi[d]) return std::nullopt;
  const double depth = D == 2 ? w.thickness : 1.0;
  b.volume = depth;
  for (int d = 0; d < D; ++d) {
    b.volume *= std::max(b.hi[d] - b.lo[d], 0.0);
    b.stress[d] = 0.5 * (wall_normal_stress(w, b.lo_wall[d]) + wall_normal_stress(w, b.hi_wall[d]));
  }
  // A polyhedral grain's own volume (its bounding sphere's would overstate the fraction by the
  // sphere's excess, 2 to 4 times for the usual rock shapes).
  const auto& p = w.particles;
  for (std::size_t k = 0; k < p.size(); ++k) {
    const double r = p.radius[k];
    if (D == 3 && p.polyhedron(k))
      b.grain_volume += w.shapes[p.shape_index[k]].volume;
    else
      b.grain_volume +=
          D == 3 ? 4.0 / 3.0 * std::numbers::pi * r * r * r : std::numbers::pi * r * r * depth;
  }
  b.solid_fraction = b.volume > 0.0 ? b.grain_volume / b.volume : 0.0;
  return b;
}

template <int D>
typename Space<D>::Vec box_strain(const BoxState<D>& now, const BoxState<D>& reference) {
  const typename Space<D>::Vec l0 = reference.extent();
  return (l0 - now.extent()).cwiseQuotient(l0);
}

#define SABLE_BOX_STATE(D)                                          \
  template std::optional<BoxState<D>> measure_box(const World<D>&); \
  template typename Space<D>::Vec box_strain(const BoxState<D>&, const BoxState<D>&);
SABLE_BOX_STATE(2)
SABLE_BOX_STATE(3)
#undef SABLE_BOX_STATE

}  // namespace sable
