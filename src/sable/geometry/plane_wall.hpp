// A plane wall (a line in 2D): a point on it (the wall's `point`) and a unit normal pointing
// into the grains. Infinite, so not binned: the neighbour list tests it against every grain.
#pragma once

#include "sable/geometry/wall_feature.hpp"

namespace sable {

template <int D>
struct PlaneShape {
  using Vec = typename Space<D>::Vec;
  static constexpr const char* kName = "plane";
  static constexpr bool kBounded = false;  // tested against every grain, not binned

  Vec normal = Vec::Zero();       // unit, into the grains
  Vec body_normal = Vec::Zero();  // the normal at the wall's starting orientation

  explicit PlaneShape(const Vec& unit_normal = Vec::UnitX())
      : normal(unit_normal), body_normal(unit_normal) {}

  std::uint32_t elements() const { return 1; }
  // Signed distance from the plane through `point` to x, positive on the grains' side.
  double distance(const Vec& point, const Vec& x, Vec& n) const {
    n = normal;
    return (x - point).dot(normal);
  }
  WallFeature<D> contact(const Vec& point, const Vec& x, std::uint32_t) const {
    WallFeature<D> f;
    f.dist = distance(point, x, f.n);
    return f;
  }
  // The pose (rotation r from the starting orientation, the wall's point) changed.
  void place(const typename Space<D>::Matrix& r, const Vec&) {
    normal = (r * body_normal).normalized();
  }
};

}  // namespace sable
