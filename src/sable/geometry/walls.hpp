// Walls: rigid boundaries with a prescribed velocity and their own material.
//
// A wall answers one question for the contact kernel: for a round grain at x with radius r,
// what are the outward normal n (pointing from the wall into the grain), the overlap
// delta = r - distance, and the wall's velocity at the contact point. That is the same
// ContactGeometry a grain-grain pair produces, so a single kernel serves both.
// Triangle meshes will join as another kind answering the same question.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "sable/core/material.hpp"
#include "sable/core/space.hpp"

namespace sable {

enum class WallKind : std::uint8_t {
  kPlane,           // infinite plane (a line in 2D): point + unit normal into the grains
  kCylinderInside,  // inside of a cylinder with axis along z (3D only)
};

template <int D>
struct Wall {
  using Vec = typename Space<D>::Vec;
  std::string name;
  WallKind kind = WallKind::kPlane;
  MaterialIndex material = 0;
  Vec point = Vec::Zero();     // plane: a point on it; cylinder: a point on the axis
  Vec normal = Vec::Zero();    // plane: unit normal pointing into the grains
  double radius = 0.0;         // cylinder radius
  Vec velocity = Vec::Zero();  // prescribed translation velocity (m/s)
  // Accumulated over the last force evaluation: force exerted BY the grains ON the wall.
  Vec force = Vec::Zero();

  // Signed distance from the wall surface to a point, positive on the grains' side, and the
  // unit normal there (pointing into the grains' side).
  double distance(const Vec& x, Vec& n) const {
    if (kind == WallKind::kPlane) {
      n = normal;
      return (x - point).dot(normal);
    }
    // Cylinder inside, axis z through `point`.
    Vec radial = x - point;
    if constexpr (D == 3) radial.z() = 0.0;
    const double rho = radial.norm();
    if (rho > 0.0) {
      n = -radial / rho;
    } else {
      n = Vec::Zero();
      n.x() = 1.0;  // on the axis every direction is as far; pick one deterministically
    }
    return radius - rho;
  }

  // The coordinate axis a plane wall faces (its normal is +-e_axis), or -1 for a cylinder or
  // a tilted plane: the walls that bound a box sample and that a servo can drive.
  int facing_axis() const {
    if (kind != WallKind::kPlane) return -1;
    for (int d = 0; d < D; ++d)
      if (std::abs(std::abs(normal[d]) - 1.0) < 1e-12) return d;
    return -1;
  }
};

}  // namespace sable
