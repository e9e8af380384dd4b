// Mass properties of closed triangle surfaces (geometry/polyhedron_mass.hpp) against exact
// formulas. Tolerance 1e-12 relative (issue 44): the sums are of a few dozen terms of the
// shape's size, so rounding stays within ~1e-15 of the values compared.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <vector>

#include "sable/core/error.hpp"
#include "sable/geometry/polyhedron_mass.hpp"

using namespace sable;

namespace {

using Tris = std::vector<std::array<std::uint32_t, 3>>;

// The box [0, a] x [0, b] x [0, c]: 8 corners (bit 0: x, bit 1: y, bit 2: z), 12 triangles
// wound outward.
std::vector<Eigen::Vector3d> box_corners(double a, double b, double c) {
  std::vector<Eigen::Vector3d> v;
  for (int k = 0; k < 8; ++k) v.emplace_back(k & 1 ? a : 0.0, k & 2 ? b : 0.0, k & 4 ? c : 0.0);
  return v;
}
const Tris kBoxTriangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6},   // z = 0, z = c
                            {0, 1, 4}, {1, 5, 4}, {2, 6, 3}, {3, 6, 7},   // y = 0, y = b
                            {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};  // x = 0, x = a

void expect_matrix_near(const Eigen::Matrix3d& got, const Eigen::Matrix3d& want, double tol) {
  const double scale = want.cwiseAbs().maxCoeff();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      EXPECT_NEAR(got(i, j), want(i, j), tol * scale) << "(" << i << ", " << j << ")";
}

// A box's exact properties: V = a b c, centre at the half sides, I = V diag(b^2 + c^2,
// c^2 + a^2, a^2 + b^2) / 12 about it.
TEST(PolyhedronMass, BoxMatchesExactFormulas) {
  const double a = 2e-3, b = 3e-3, c = 5e-3;
  const PolyhedronMass m = polyhedron_mass(box_corners(a, b, c), kBoxTriangles);
  const double v = a * b * c;
  EXPECT_NEAR(m.volume, v, 1e-12 * v);
  EXPECT_NEAR((m.centroid - Eigen::Vector3d(a, b, c) / 2).norm(), 0.0, 1e-12 * c);
  const Eigen::Matrix3d want =
      Eigen::Vector3d(b * b + c * c, c * c + a * a, a * a + b * b).asDiagonal() * (v / 12);
  expect_matrix_near(m.inertia, want, 1e-12);
}

// A regular tetrahedron of edge L: V = L^3 / (6 sqrt 2), and by its symmetry an isotropic
// inertia, V L^2 / 20, about its centroid (the mean of its corners).
TEST(PolyhedronMass, RegularTetrahedronIsIsotropic) {
  const double s = 1e-3;  // corners (s,s,s), (s,-s,-s), (-s,s,-s), (-s,-s,s): L = 2 sqrt(2) s
  const std::vector<Eigen::Vector3d> v = {{s, s, s}, {s, -s, -s}, {-s, s, -s}, {-s, -s, s}};
  const Tris t = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
  const PolyhedronMass m = polyhedron_mass(v, t);
  const double L = 2 * std::sqrt(2.0) * s;
  const double vol = L * L * L / (6 * std::sqrt(2.0));
  EXPECT_NEAR(m.volume, vol, 1e-12 * vol);
  EXPECT_NEAR(m.centroid.norm(), 0.0, 1e-12 * s);
  expect_matrix_near(m.inertia, Eigen::Matrix3d::Identity() * (vol * L * L / 20), 1e-12);
}

// Moved and turned: the volume is unchanged, the centroid moves with the shape, and the
// inertia turns as R I R^T (the box far from the origin checks the shift to the centroid).
TEST(PolyhedronMass, RigidMotionTurnsTheInertia) {
  const double a = 2e-3, b = 3e-3, c = 5e-3;
  const PolyhedronMass body = polyhedron_mass(box_corners(a, b, c), kBoxTriangles);
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1.0, -2.0, 0.5).normalized()).toRotationMatrix();
  const Eigen::Vector3d shift(10.0, -4.0, 7.0);  // metres away: 1e3 to 1e4 times the box
  std::vector<Eigen::Vector3d> moved = box_corners(a, b, c);
  for (auto& p : moved) p = R * p + shift;
  const PolyhedronMass m = polyhedron_mass(moved, kBoxTriangles);
  EXPECT_NEAR(m.volume, body.volume, 1e-12 * body.volume);
  // The corners' coordinates carry rounding of ~1e-15 of 10 m: 1e-14 m, under 1e-11 of the box.
  EXPECT_NEAR((m.centroid - (R * body.centroid + shift)).norm(), 0.0, 1e-11 * c);
  expect_matrix_near(m.inertia, R * body.inertia * R.transpose(), 1e-9);
}

// A non-convex solid: an L made of the boxes [0,2]x[0,1]x[0,1] and [0,1]x[1,2]x[0,1] (units
// of 1 mm), its inertia the two boxes' by the parallel-axis theorem.
TEST(PolyhedronMass, NonConvexLShapeIsTheSumOfItsBoxes) {
  const double u = 1e-3;
  // The L's outline in the plane z = 0, counterclockwise from above, extruded to z = u.
  const std::vector<std::array<double, 2>> outline = {{0, 0}, {2 * u, 0}, {2 * u, u},
                                                      {u, u}, {u, 2 * u}, {0, 2 * u}};
  std::vector<Eigen::Vector3d> v;
  for (double z : {0.0, u})
    for (const auto& q : outline) v.emplace_back(q[0], q[1], z);
  Tris t;
  const std::uint32_t n = 6;
  for (std::uint32_t k = 0; k < n; ++k) {  // the sides
    const std::uint32_t k1 = (k + 1) % n;
    t.push_back({k, k1, n + k1});
    t.push_back({k, n + k1, n + k});
  }
  // Bottom (seen from below: clockwise from above) and top, as fans from the reflex corner 3,
  // which sees every other corner.
  for (std::uint32_t k : {4u, 5u, 0u, 1u}) {
    t.push_back({3, k + 1 == n ? 0 : k + 1, k});
    t.push_back({n + 3, n + k, n + (k + 1 == n ? 0 : k + 1)});
  }
  const PolyhedronMass m = polyhedron_mass(v, t, "the L");
  const double v1 = 2 * u * u * u, v2 = u * u * u;
  const Eigen::Vector3d c1(u, u / 2, u / 2), c2(u / 2, 1.5 * u, u / 2);
  const Eigen::Vector3d c = (v1 * c1 + v2 * c2) / (v1 + v2);
  auto box_inertia = [](double vol, double a, double b, double cc) -> Eigen::Matrix3d {
    return Eigen::Vector3d(b * b + cc * cc, cc * cc + a * a, a * a + b * b).asDiagonal() *
           (vol / 12);
  };
  auto shifted = [&](const Eigen::Matrix3d& I, double vol, const Eigen::Vector3d& d) {
    return Eigen::Matrix3d(
        I + vol * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose()));
  };
  const Eigen::Matrix3d want = shifted(box_inertia(v1, 2 * u, u, u), v1, c1 - c) +
                               shifted(box_inertia(v2, u, u, u), v2, c2 - c);
  EXPECT_NEAR(m.volume, v1 + v2, 1e-12 * (v1 + v2));
  EXPECT_NEAR((m.centroid - c).norm(), 0.0, 1e-12 * u);
  expect_matrix_near(m.inertia, want, 1e-12);
}

// Triangles wound inward enclose a negative volume; an open surface or a bad index is
// refused too, the shape named.
TEST(PolyhedronMass, InwardOrBrokenSurfacesAreRefused) {
  Tris inward = kBoxTriangles;
  for (auto& t : inward) std::swap(t[1], t[2]);
  try {
    polyhedron_mass(box_corners(1, 1, 1), inward, "grain shape 'cube'");
    FAIL() << "an inward surface was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("grain shape 'cube'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("counterclockwise"), std::string::npos) << e.what();
  }
  EXPECT_THROW(polyhedron_mass(box_corners(1, 1, 1), {}), InputError);
  EXPECT_THROW(polyhedron_mass(box_corners(1, 1, 1), {{0, 1, 8}}), InputError);
}

}  // namespace
