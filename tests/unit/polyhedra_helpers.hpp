// Polyhedral grains for the solver tests (test_cd_polyhedra.cpp, test_dem_polyhedra.cpp): boxes
// given by their corners, and the sites and corners of heaps of random hulls.
#pragma once

#include <Eigen/Geometry>
#include <vector>

namespace sable::test {

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
