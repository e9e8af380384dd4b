// Convex hulls (geometry/convex_hull.hpp): exact counts where the answer is known, the
// defining property (every point on or below every face), a closed surface wound outward,
// and the mass properties of a random hull against an independent formula.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>
#include <vector>

#include "sable/core/error.hpp"
#include "sable/core/rng.hpp"
#include "sable/geometry/convex_hull.hpp"
#include "sable/geometry/polyhedron_mass.hpp"

using namespace sable;

namespace {

std::vector<Eigen::Vector3d> on_sphere(int n, std::uint64_t seed, const Eigen::Vector3d& axes) {
  Rng rng(seed);
  std::vector<Eigen::Vector3d> p;
  for (int k = 0; k < n; ++k) {
    const double z = rng.uniform(-1.0, 1.0), phi = rng.uniform(0.0, 2 * std::numbers::pi);
    const double r = std::sqrt(1 - z * z);
    p.push_back(Eigen::Vector3d(r * std::cos(phi), r * std::sin(phi), z).cwiseProduct(axes));
  }
  return p;
}

// Closed and wound outward: every directed edge appears once, its reverse once.
void expect_closed_and_outward(const ConvexHull& h) {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
  for (const auto& t : h.triangles)
    for (int k = 0; k < 3; ++k) edges.emplace_back(t[k], t[(k + 1) % 3]);
  std::sort(edges.begin(), edges.end());
  EXPECT_EQ(std::adjacent_find(edges.begin(), edges.end()), edges.end()) << "an edge twice";
  for (const auto& [u, v] : edges)
    EXPECT_TRUE(std::binary_search(edges.begin(), edges.end(), std::pair{v, u}))
        << "edge " << u << "-" << v << " has no twin";
}

// Every input point lies on or below the plane of every face (the hull's definition), to
// the construction's tolerance (1e-12 of the extent; 1e-11 here for the plane's rounding).
void expect_contains(const ConvexHull& h, const std::vector<Eigen::Vector3d>& points,
                     double extent) {
  for (const auto& t : h.triangles) {
    const Eigen::Vector3d a = h.vertices[t[0]], b = h.vertices[t[1]], c = h.vertices[t[2]];
    const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
    for (const auto& x : points) EXPECT_LE(n.dot(x - a), 1e-11 * extent);
  }
}

// Points on a sphere are all extreme: a hull of n vertices, 2n - 4 triangles (Euler), closed,
// containing every point, its volume just under the sphere's.
TEST(ConvexHull, PointsOnASphereAreAllVertices) {
  const int n = 200;
  const auto points = on_sphere(n, 7, Eigen::Vector3d::Ones());
  const ConvexHull h = convex_hull(points);
  EXPECT_EQ(h.vertices.size(), static_cast<std::size_t>(n));
  EXPECT_EQ(h.triangles.size(), static_cast<std::size_t>(2 * n - 4));
  expect_closed_and_outward(h);
  expect_contains(h, points, 2.0);
  const double v = polyhedron_mass(h.vertices, h.triangles).volume, ball = 4 * std::numbers::pi / 3;
  EXPECT_LT(v, ball);
  EXPECT_GT(v, 0.9 * ball);  // 200 points: the inscribed hull misses a few % of the ball
}

// A cube's corners among its face centres, edge midpoints and inner points: the hull is the
// cube, 8 corners and 12 triangles (coplanar points are not vertices), volume a^3 exactly.
TEST(ConvexHull, CubeWithPointsOnItsFacesAndInside) {
  const double a = 2e-3;
  std::vector<Eigen::Vector3d> points;
  Rng rng(3);
  for (int k = 0; k < 20; ++k)
    points.emplace_back(rng.uniform(0, a), rng.uniform(0, a), rng.uniform(0, a));
  for (int i = 0; i <= 2; ++i)
    for (int j = 0; j <= 2; ++j)
      for (int l = 0; l <= 2; ++l) points.emplace_back(i * a / 2, j * a / 2, l * a / 2);
  const ConvexHull h = convex_hull(points, "cube");
  EXPECT_EQ(h.vertices.size(), 8u);
  EXPECT_EQ(h.triangles.size(), 12u);
  for (const auto& v : h.vertices)
    for (int d = 0; d < 3; ++d) EXPECT_TRUE(v[d] == 0.0 || v[d] == a) << v.transpose();
  expect_closed_and_outward(h);
  const PolyhedronMass m = polyhedron_mass(h.vertices, h.triangles);
  EXPECT_NEAR(m.volume, a * a * a, 1e-12 * a * a * a);
}

// A random hull's mass properties (polyhedron_mass, by the divergence theorem) against
// tetrahedra from its centroid, each with the exact second moment of a tetrahedron,
// V / 20 (sum v v^T + (sum v)(sum v)^T) over its corners: two independent sums, 1e-12.
TEST(ConvexHull, RandomHullMassMatchesTetrahedra) {
  const auto points = on_sphere(60, 11, Eigen::Vector3d(1.0e-3, 0.7e-3, 0.5e-3));
  const ConvexHull h = convex_hull(points, "ellipsoid hull");
  const PolyhedronMass m = polyhedron_mass(h.vertices, h.triangles);
  Eigen::Vector3d o = Eigen::Vector3d::Zero();
  for (const auto& v : h.vertices) o += v;
  o /= static_cast<double>(h.vertices.size());
  double volume = 0.0;
  Eigen::Vector3d first = Eigen::Vector3d::Zero();
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();  // integral of x x^T about o
  for (const auto& t : h.triangles) {
    const Eigen::Vector3d a = h.vertices[t[0]] - o, b = h.vertices[t[1]] - o,
                          c = h.vertices[t[2]] - o;
    const double vt = a.dot(b.cross(c)) / 6;  // the tetrahedron (o, a, b, c)
    const Eigen::Vector3d s = a + b + c;
    volume += vt;
    first += vt * s / 4;
    second +=
        vt / 20 * (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
  }
  const Eigen::Vector3d c = first / volume;
  const Eigen::Matrix3d cov = second - volume * c * c.transpose();
  const Eigen::Matrix3d inertia = cov.trace() * Eigen::Matrix3d::Identity() - cov;
  EXPECT_NEAR(m.volume, volume, 1e-12 * volume);
  EXPECT_NEAR((m.centroid - (o + c)).norm(), 0.0, 1e-12 * 1e-3);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      EXPECT_NEAR(m.inertia(i, j), inertia(i, j), 1e-12 * inertia.cwiseAbs().maxCoeff());
  // Below the ellipsoid's own volume and inertia, as an inscribed solid must be.
  EXPECT_LT(m.volume, 4 * std::numbers::pi / 3 * 1.0e-3 * 0.7e-3 * 0.5e-3);
}

// The same points, the same hull, bit for bit.
TEST(ConvexHull, Deterministic) {
  const auto points = on_sphere(80, 5, Eigen::Vector3d(1.0, 2.0, 3.0));
  const ConvexHull a = convex_hull(points), b = convex_hull(points);
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.vertices, b.vertices);
}

// No volume: refused, the shape named.
TEST(ConvexHull, FlatOrTooFewPointsAreRefused) {
  const std::vector<Eigen::Vector3d> flat = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 3, 0}};
  try {
    convex_hull(flat, "grain shape 'tile'");
    FAIL() << "a flat set was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("grain shape 'tile'"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("one plane"), std::string::npos) << e.what();
  }
  EXPECT_THROW(convex_hull({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}), InputError);
  EXPECT_THROW(convex_hull({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}}), InputError);
}

}  // namespace
