// The inside of a cylinder (a circle in 2D): a point on its axis (the wall's `point`), its
// radius and, in 3D, its unit axis (along z unless it was turned). The grains are inside;
// infinite along the axis, so not binned.
#pragma once

#include "sable/geometry/wall_feature.hpp"

namespace sable {

template <int D>
struct CylinderShape {
  using Vec = typename Space<D>::Vec;
  static constexpr const char* kName = "cylinder";
  static constexpr bool kBounded = false;  // tested against every grain, not binned

  double radius = 0.0;
  Vec axis = axis_z(), body_axis = axis_z();  // unit; unused in 2D

  explicit CylinderShape(double r = 0.0) : radius(r) {}

  std::uint32_t elements() const { return 1; }
  // Signed distance from the surface to x, positive inside, and the normal towards the axis.
  double distance(const Vec& point, const Vec& x, Vec& n) const {
    Vec radial = x - point;
    // Along z this removes the z component exactly (x * 0 and z * 1 round to nothing).
    if constexpr (D == 3) radial -= radial.dot(axis) * axis;
    const double rho = radial.norm();
    if (rho > 0.0) {
      n = -radial / rho;
    } else {
      n = Vec::Zero();
      n.x() = 1.0;  // on the axis every direction is as far; pick one deterministically
    }
    return radius - rho;
  }
  WallFeature<D> contact(const Vec& point, const Vec& x, std::uint32_t) const {
    WallFeature<D> f;
    f.dist = distance(point, x, f.n);
    return f;
  }
  void place(const typename Space<D>::Matrix& r, const Vec&) {
    if constexpr (D == 3) axis = (r * body_axis).normalized();
  }

 private:
  static Vec axis_z() {
    Vec a = Vec::Zero();
    a[D - 1] = D == 3 ? 1.0 : 0.0;
    return a;
  }
};

}  // namespace sable
