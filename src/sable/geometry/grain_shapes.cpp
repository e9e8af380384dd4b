#include "sable/geometry/grain_shapes.hpp"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <cmath>

#include "sable/core/error.hpp"
#include "sable/geometry/convex_hull.hpp"
#include "sable/geometry/polyhedron_mass.hpp"

namespace sable {

namespace {

// The principal axes of `inertia` as a right-handed rotation (columns: body x, y, z in the
// points' frame) and the moments along them; identity when the tensor is diagonal already.
std::pair<Eigen::Matrix3d, Eigen::Vector3d> principal_axes(const Eigen::Matrix3d& inertia) {
  const double off =
      std::max({std::abs(inertia(0, 1)), std::abs(inertia(0, 2)), std::abs(inertia(1, 2))});
  if (off <= 1e-12 * inertia.trace()) return {Eigen::Matrix3d::Identity(), inertia.diagonal()};
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(inertia);
  Eigen::Matrix3d R = eig.eigenvectors();
  if (R.determinant() < 0.0) R.col(2) = -R.col(2);
  return {R, eig.eigenvalues()};
}

void check_moments(const Eigen::Vector3d& inertia, double volume, const char* what) {
  if (!(volume > 0.0) || !std::isfinite(volume) || !(inertia.minCoeff() > 0.0) ||
      !inertia.allFinite())
    throw InputError(
        fmt::format("{}: volume {} and principal moments ({}, {}, {}) per unit "
                    "density; expected positive finite numbers",
                    what, volume, inertia.x(), inertia.y(), inertia.z()));
}

}  // namespace

ShapePlacement GrainShapes::add(const std::vector<Eigen::Vector3d>& points, const char* what) {
  const ConvexHull hull = convex_hull(points, what);
  const PolyhedronMass m = polyhedron_mass(hull.vertices, hull.triangles, what);
  const auto [R, moments] = principal_axes(m.inertia);
  std::vector<Eigen::Vector3d> body(hull.vertices.size());
  for (std::size_t k = 0; k < body.size(); ++k)
    body[k] = R.transpose() * (hull.vertices[k] - m.centroid);
  ShapePlacement placed;
  placed.index = add_body_frame(body, m.volume, moments, what);
  placed.centroid = m.centroid;
  placed.frame = Eigen::Quaterniond(R).normalized();
  return placed;
}

std::uint32_t GrainShapes::add_body_frame(const std::vector<Eigen::Vector3d>& vertices,
                                          double volume, const Eigen::Vector3d& inertia,
                                          const char* what) {
  check_moments(inertia, volume, what);
  ConvexPolyhedron solid(convex_hull(vertices, what), what);
  shapes_.push_back({vertices, std::move(solid), volume, inertia});
  return static_cast<std::uint32_t>(shapes_.size() - 1);
}

}  // namespace sable
