// Polyhedral grains for the solver tests (test_cd_polyhedra.cpp, test_dem_polyhedra.cpp): boxes
// given by their corners, and the sites and corners of heaps of random hulls.
#pragma once

#include <Eigen/Geometry>
#include <vector>

#include "sable/world/world.hpp"

namespace sable::test {

// An empty World for grains of size `side` near the origin: cell lists over [-0.2, 0.2]^3 m
// with a skin of skin_share * side, gravity 9.81 m/s^2 along -z, step dt. The caller adds
// materials and the model.
inline World<3> polyhedra_world(double side, double dt, double skin_share = 0.2) {
  World<3> w;
  w.neighbors.skin = skin_share * side;
  w.neighbors.domain_lo.setConstant(-0.2);
  w.neighbors.domain_hi.setConstant(0.2);
  w.gravity = Eigen::Vector3d(0.0, 0.0, -9.81);
  w.dt = dt;
  return w;
}

// The corners of the box [lo, hi], turned by q about `about`.
inline std::vector<Eigen::Vector3d> box_points(
    const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
    const Eigen::Quaterniond& q = Eigen::Quaterniond::Identity(),
    const Eigen::Vector3d& about = Eigen::Vector3d::Zero()) {
  std::vector<Eigen::Vector3d> v;
  for (int k = 0; k < 8; ++k)
    v.push_back(about + q * (Eigen::Vector3d(k & 1 ? hi.x() : lo.x(), k & 2 ? hi.y() : lo.y(),
                                             k & 4 ? hi.z() : lo.z()) -
                             about));
  return v;
}

// Site k of a heap: an nx x nx lattice of layers `pitch` apart, the lowest layer r above z = 0,
// centred on the z axis.
inline Eigen::Vector3d heap_site(int k, int nx, double r, double pitch) {
  const int column = k % nx, row = k / nx % nx, layer = k / (nx * nx);
  return {pitch * (column - 0.5 * nx), pitch * (row - 0.5 * nx), r + pitch * layer};
}

// `corners` points on the ellipsoid of semi-axes `axes` about `centre`, each the direction of
// three draws of `draw` (uniform in [-1, 1]), in that order.
template <typename Draw>
std::vector<Eigen::Vector3d> ellipsoid_points(const Eigen::Vector3d& centre,
                                              const Eigen::Vector3d& axes, int corners,
                                              Draw&& draw) {
  std::vector<Eigen::Vector3d> points;
  for (int c = 0; c < corners; ++c) {
    Eigen::Vector3d d;
    for (int i = 0; i < 3; ++i) d[i] = draw();
    points.push_back(centre + axes.cwiseProduct(d.normalized()));
  }
  return points;
}

}  // namespace sable::test
