// Convex polyhedra for contact detection (geometry/convex_polyhedron.hpp) and their narrow
// phase (geometry/polyhedron_contact.hpp): exact manifolds where the answer is known (a cube
// on a slab, a cube on a turned cube, equal cubes stacked flush, a tetrahedron on its vertex,
// edge and face, crossed edges), and random pairs against brute-force references that share
// no code with it (polyhedron_reference.hpp).
//
// Tolerances. Hand-built cases: 1e-12 (coordinates of order 1, a few roundings each).
// Random shapes have radii of order 1: 1e-9 of the sum of the two radii, far above the
// rounding of the sums compared (~1e-15), far below any real difference (a phantom or
// missed contact, a wrong axis).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "polyhedron_reference.hpp"
#include "sable/core/error.hpp"
#include "sable/geometry/convex_hull.hpp"
#include "sable/geometry/convex_polyhedron.hpp"
#include "sable/geometry/polyhedron_contact.hpp"

using namespace sable;
using namespace sable::test;

namespace {

using Kind = PolyhedronContactKind;
const Quat kI = Quat::Identity();

// The manifold's points in world coordinates.
std::vector<Vec> points_of(const PolyhedronContact& c) {
  std::vector<Vec> p;
  for (int k = 0; k < c.count; ++k) p.push_back(c.points[k].position);
  return p;
}

// Each expected point matched by one reported point within tol (same count).
void expect_same_points(const PolyhedronContact& c, const std::vector<Vec>& want, double tol) {
  ASSERT_EQ(c.count, static_cast<int>(want.size()));
  for (const Vec& w : want) {
    const auto got = points_of(c);
    const bool found =
        std::any_of(got.begin(), got.end(), [&](const Vec& g) { return (g - w).norm() <= tol; });
    EXPECT_TRUE(found) << "no point at " << w.transpose();
  }
}

// ---------------------------------------------------------------------------------------
// ConvexPolyhedron

// A cube's hull (12 triangles) merges into 6 square faces and 12 edges; each face's normal
// is an axis, its offset the half side; each edge joins two faces whose loops hold it in
// opposite directions. The face centre listed first becomes a vertex of the hull (it starts
// the first tetrahedron) and must go: a flat vertex is no corner. Exact: the coordinates are
// multiples of 1/2.
TEST(ConvexPolyhedron, CubeHasSixSquareFaces) {
  std::vector<Vec> points = {Vec(-0.5, 0.0, 0.0)};  // the centre of the x = -1/2 face
  for (const Vec& v : box_corners(-kHalf, kHalf)) points.push_back(v);
  const ConvexHull hull = convex_hull(points, "cube");
  ASSERT_EQ(hull.vertices.size(), 9u);  // the flat vertex is in the hull
  const ConvexPolyhedron cube(hull, "cube");
  EXPECT_EQ(cube.vertices().size(), 8u);
  ASSERT_EQ(cube.face_count(), 6u);
  EXPECT_EQ(cube.edges().size(), 12u);
  EXPECT_DOUBLE_EQ(cube.radius(), std::sqrt(0.75));
  for (std::size_t f = 0; f < cube.face_count(); ++f) {
    EXPECT_EQ(cube.face(f).size(), 4u);
    const Vec& n = cube.normals()[f];
    EXPECT_EQ(n.cwiseAbs().maxCoeff(), 1.0) << n.transpose();
    EXPECT_EQ(cube.offsets()[f], 0.5);
    for (std::uint32_t v : cube.face(f)) EXPECT_EQ(n.dot(cube.vertices()[v]), 0.5);
  }
  for (const auto& e : cube.edges()) {
    EXPECT_LT(e.v0, e.v1);
    auto runs = [&](std::uint32_t f, std::uint32_t from, std::uint32_t to) {
      const auto loop = cube.face(f);
      for (std::size_t i = 0; i < loop.size(); ++i)
        if (loop[i] == from && loop[(i + 1) % loop.size()] == to) return true;
      return false;
    };
    EXPECT_TRUE(runs(e.face0, e.v0, e.v1));
    EXPECT_TRUE(runs(e.face1, e.v1, e.v0));
  }
}

// The merge tolerance is relative: on a 2 mm cube, a point 1e-11 of the side above the top
// face's centre (a hull vertex: the hull's tolerance is 1e-12) folds the top by less than the
// tolerance, and the top stays one square (the point flat, no corner); 1e-6 of the side is a
// real fold: 4 triangles and an apex, 9 faces and 9 corners.
TEST(ConvexPolyhedron, MergeToleranceIsRelativeToTheSize) {
  const double a = 2e-3;
  for (const double lift : {1e-11, 1e-6}) {
    std::vector<Vec> points = box_corners(Vec::Zero(), Vec(a, a, a));
    points.emplace_back(a / 2, a / 2, a * (1 + lift));
    const ConvexHull hull = convex_hull(points, "cube");
    ASSERT_EQ(hull.vertices.size(), 9u);
    const ConvexPolyhedron cube(hull, "cube");
    EXPECT_EQ(cube.face_count(), lift < 1e-9 ? 6u : 9u) << lift;
    EXPECT_EQ(cube.vertices().size(), lift < 1e-9 ? 8u : 9u) << lift;
  }
}

// A random hull (all its faces triangles): V - E + F = 2, each face's loop counterclockwise
// about its normal (the loop's vector area along the normal is positive), and every vertex on
// or below every face's plane (exactly: the offset is the highest vertex).
TEST(ConvexPolyhedron, RandomHullIsConsistent) {
  std::mt19937_64 gen(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Vec> points;
  for (int k = 0; k < 40; ++k) points.push_back(draw3([&] { return u(gen); }).normalized());
  const ConvexPolyhedron p(convex_hull(points), "ball");
  EXPECT_EQ(p.vertices().size() + p.face_count(), p.edges().size() + 2);
  for (std::size_t f = 0; f < p.face_count(); ++f) {
    const auto loop = p.face(f);
    Vec area = Vec::Zero();
    for (std::size_t i = 0; i < loop.size(); ++i)
      area += p.vertices()[loop[i]].cross(p.vertices()[loop[(i + 1) % loop.size()]]);
    EXPECT_GT(area.dot(p.normals()[f]), 0.0);
    EXPECT_NEAR(p.normals()[f].norm(), 1.0, 1e-15);
    for (const Vec& v : p.vertices()) EXPECT_LE(p.normals()[f].dot(v), p.offsets()[f]);
  }
}

// Degenerate input is refused, the shape named: too few vertices, an open surface, a
// surface wound inward (not convex seen from its normals).
TEST(ConvexPolyhedron, DegenerateInputIsRefused) {
  ConvexHull cube = convex_hull(box_corners(-kHalf, kHalf));
  ConvexHull open = cube;
  open.triangles.pop_back();
  try {
    ConvexPolyhedron(open, "grain shape 'brick'");
    FAIL() << "an open surface was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("grain shape 'brick'"), std::string::npos) << e.what();
  }
  ConvexHull inward = cube;
  for (auto& t : inward.triangles) std::swap(t[1], t[2]);
  EXPECT_THROW(ConvexPolyhedron(inward, "inward"), InputError);
  ConvexHull few = cube;
  few.vertices.resize(3);
  EXPECT_THROW(ConvexPolyhedron(few, "few"), InputError);
}

// ---------------------------------------------------------------------------------------
// Hand-built contacts

// A unit cube resting face down on a larger slab, overlapping it by 1e-3: the slab's top face
// is the reference (a face of A wins a tie with B's), the cube's bottom face the incident
// one, inside the slab's top: exactly the cube's 4 bottom corners, each 1e-3 deep, normal +z.
// Again after one rigid motion of both (the same answer, turned). 1e-12: a few roundings.
TEST(PolyhedronContact, CubeRestingFaceDownOnASlab) {
  const ConvexPolyhedron slab = box(Vec(-2, -2, -1), Vec(2, 2, 0)), cube = box(-kHalf, kHalf);
  const Vec at(0.3, -0.2, 0.5 - 1e-3);
  const Quat turn(Eigen::AngleAxisd(0.8, Vec(1, -2, 3).normalized()));
  const Vec shift(3.0, -1.0, 2.0);
  for (const bool moved : {false, true}) {
    const Quat q = moved ? turn : kI;
    const Vec s = moved ? shift : Vec::Zero();
    const PolyhedronContact c = polyhedron_contact(slab, s, q, cube, q * at + s, q, 0.0);
    EXPECT_EQ(c.kind, Kind::kFaceA);
    EXPECT_NEAR(c.separation, -1e-3, 1e-12);
    EXPECT_NEAR((c.normal - q * Vec::UnitZ()).norm(), 0.0, 1e-12);
    std::vector<Vec> want;
    for (const Vec& v : box_corners(-kHalf, kHalf))
      if (v.z() < 0) want.push_back(q * (v + at) + s);
    expect_same_points(c, want, 1e-12);
    for (int k = 0; k < c.count; ++k) EXPECT_NEAR(c.points[k].gap, -1e-3, 1e-12);
  }
}

// A unit cube on another turned 45 degrees about z, overlapping by 1e-3: the overlap is a
// regular octagon (8 clipped points), reduced to 4. Each lies inside both squares (1e-12),
// 1e-3 deep, and the 4 spread over at least half the octagon's area 2 (sqrt 2 - 1) (the rule
// keeps a quadrilateral of 2 R^2 = 0.586 of the octagon's circumradius R; 0.414 is half).
TEST(PolyhedronContact, CubeOnCubeTurned45Degrees) {
  const ConvexPolyhedron cube = box(-kHalf, kHalf);
  const Quat q(Eigen::AngleAxisd(std::numbers::pi / 4, Vec::UnitZ()));
  const PolyhedronContact c =
      polyhedron_contact(cube, Vec::Zero(), kI, cube, Vec(0, 0, 1 - 1e-3), q, 0.0);
  EXPECT_EQ(c.kind, Kind::kFaceA);
  EXPECT_NEAR((c.normal - Vec::UnitZ()).norm(), 0.0, 1e-12);
  ASSERT_EQ(c.count, 4);
  for (const Vec& p : points_of(c)) {
    EXPECT_LE(p.head<2>().cwiseAbs().maxCoeff(), 0.5 + 1e-12) << p.transpose();
    const Vec local = q.conjugate() * p;
    EXPECT_LE(local.head<2>().cwiseAbs().maxCoeff(), 0.5 + 1e-12) << p.transpose();
    EXPECT_NEAR(p.z(), 0.5 - 1e-3, 1e-12);
  }
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(c.points[k].gap, -1e-3, 1e-12);
  // The quadrilateral's area (the points in convex order around their centre).
  auto p = points_of(c);
  const Vec mid = (p[0] + p[1] + p[2] + p[3]) / 4;
  std::sort(p.begin(), p.end(), [&](const Vec& u, const Vec& v) {
    return std::atan2(u.y() - mid.y(), u.x() - mid.x()) <
           std::atan2(v.y() - mid.y(), v.x() - mid.x());
  });
  double area = 0.0;
  for (int k = 0; k < 4; ++k) area += (p[k] - mid).cross(p[(k + 1) % 4] - mid).z() / 2;
  EXPECT_GE(area, 0.5 * 2 * (std::sqrt(2.0) - 1));
}

// Equal cubes stacked flush, overlapping by 1e-3: the incident face's corners lie exactly on
// the reference face's side planes, and stay (a corner on a side plane is inside): 4 points
// at the upper cube's bottom corners, each 1e-3 deep. Exact but for the 1e-3 (1e-12).
TEST(PolyhedronContact, EqualCubesStackedFlush) {
  const ConvexPolyhedron cube = box(-kHalf, kHalf);
  const Vec at(0.0, 0.0, 1 - 1e-3);
  const PolyhedronContact c = polyhedron_contact(cube, Vec::Zero(), kI, cube, at, kI, 0.0);
  EXPECT_EQ(c.kind, Kind::kFaceA);
  EXPECT_NEAR((c.normal - Vec::UnitZ()).norm(), 0.0, 1e-12);
  std::vector<Vec> want;
  for (const Vec& v : box_corners(-kHalf, kHalf))
    if (v.z() < 0) want.push_back(v + at);
  expect_same_points(c, want, 1e-12);
  for (int k = 0; k < c.count; ++k) EXPECT_NEAR(c.points[k].gap, -1e-3, 1e-12);
}

// A regular tetrahedron dipping 1e-3 into a slab on a vertex, an edge and a face: 1, 2 and 3
// points, at those corners, each 1e-3 deep, the slab's face the reference, normal +z (margin
// 0: the corners above the slab are no contact). Swapped (the tetrahedron as A), the normal
// is -z (from A to B), and on a vertex or an edge the same points come from B's face (A's
// tilted faces lose by far). 1e-12: a few roundings of order-1 values.
TEST(PolyhedronContact, TetrahedronOnVertexEdgeAndFace) {
  const ConvexPolyhedron slab = box(Vec(-2, -2, -1), Vec(2, 2, 0));
  const auto corners = tetra_corners();
  const ConvexPolyhedron tetra(convex_hull(corners), "tetrahedron");
  const double deep = 1e-3;
  struct Case {
    Vec down;  // the body direction turned to -z
    std::vector<int> touching;
  };
  const std::vector<Case> cases = {
      {corners[0], {0}}, {corners[0] + corners[1], {0, 1}}, {-corners[0], {1, 2, 3}}};
  for (const Case& k : cases) {
    const Quat q = Quat::FromTwoVectors(k.down, -Vec::UnitZ());
    const double low = (q * corners[k.touching[0]]).z();
    const Vec at(0.1, 0.2, -low - deep);
    const bool face_down = k.touching.size() == 3;
    for (const bool swapped : {false, true}) {
      const PolyhedronContact c =
          swapped ? polyhedron_contact(tetra, at, q, slab, Vec::Zero(), kI, 0.0)
                  : polyhedron_contact(slab, Vec::Zero(), kI, tetra, at, q, 0.0);
      // Swapped face down, the tetrahedron's face ties with the slab's and wins as A's: the
      // points are then the slab's, under the corners.
      const bool from_a = !swapped || face_down;
      EXPECT_EQ(c.kind, from_a ? Kind::kFaceA : Kind::kFaceB);
      EXPECT_NEAR(c.separation, -deep, 1e-12);
      EXPECT_NEAR((c.normal - (swapped ? -1.0 : 1.0) * Vec::UnitZ()).norm(), 0.0, 1e-12);
      std::vector<Vec> want;
      for (int i : k.touching)
        want.push_back(q * corners[i] + at + (swapped && face_down ? deep : 0.0) * Vec::UnitZ());
      expect_same_points(c, want, 1e-12);
      for (int i = 0; i < c.count; ++i) EXPECT_NEAR(c.points[i].gap, -deep, 1e-12);
    }
  }
}

// Apart but within the margin: the tetrahedron's face 1e-4 above the slab gives its 3
// corners, each with gap +1e-4, when the margin is 2e-4; none when it is 5e-5, the separation
// still reported. Margins below 0 are refused.
TEST(PolyhedronContact, NearContactWithinTheMargin) {
  const ConvexPolyhedron slab = box(Vec(-2, -2, -1), Vec(2, 2, 0));
  const auto corners = tetra_corners();
  const ConvexPolyhedron tetra(convex_hull(corners), "tetrahedron");
  const Quat q = Quat::FromTwoVectors(-corners[0], -Vec::UnitZ());
  const Vec at(0.0, 0.0, -(q * corners[1]).z() + 1e-4);
  const PolyhedronContact near = polyhedron_contact(slab, Vec::Zero(), kI, tetra, at, q, 2e-4);
  EXPECT_NEAR(near.separation, 1e-4, 1e-12);
  ASSERT_EQ(near.count, 3);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(near.points[i].gap, 1e-4, 1e-12);
  const PolyhedronContact far = polyhedron_contact(slab, Vec::Zero(), kI, tetra, at, q, 5e-5);
  EXPECT_NEAR(far.separation, 1e-4, 1e-12);
  EXPECT_EQ(far.count, 0);
  EXPECT_THROW(polyhedron_contact(slab, Vec::Zero(), kI, tetra, at, q, -1e-9), InputError);
}

// Crossed edges: a cube turned 45 degrees about x (its top an edge along x) under one turned
// 45 degrees about y (its bottom an edge along y), overlapping by 1e-3, and the pair then
// moved and turned as one. The faces are 45 degrees off: an edge pair wins, its normal
// e_A x e_B (+z before the motion), one point midway between the edges, gap -1e-3. 1e-12.
TEST(PolyhedronContact, CrossedEdges) {
  const ConvexPolyhedron cube = box(-kHalf, kHalf);
  const double deep = 1e-3, h = std::sqrt(0.5);
  const Quat qa(Eigen::AngleAxisd(std::numbers::pi / 4, Vec::UnitX()));
  const Quat qb(Eigen::AngleAxisd(std::numbers::pi / 4, Vec::UnitY()));
  const Vec xb(0.05, -0.1, 2 * h - deep);
  const Quat turn(Eigen::AngleAxisd(1.1, Vec(0.3, 1, -0.4).normalized()));
  const Vec shift(-2.0, 0.5, 1.0);
  const PolyhedronContact c =
      polyhedron_contact(cube, shift, turn * qa, cube, turn * xb + shift, turn * qb, 0.0);
  EXPECT_EQ(c.kind, Kind::kEdgeEdge);
  EXPECT_NEAR(c.separation, -deep, 1e-12);
  const Vec edge_a = turn * Vec::UnitX(), edge_b = turn * Vec::UnitY();
  EXPECT_NEAR((c.normal - edge_a.cross(edge_b)).norm(), 0.0, 1e-12);
  ASSERT_EQ(c.count, 1);
  EXPECT_NEAR((c.points[0].position - (turn * Vec(0.05, 0.0, h - deep / 2) + shift)).norm(), 0.0,
              1e-12);
  EXPECT_NEAR(c.points[0].gap, -deep, 1e-12);
}

// Look-ahead points (ManifoldMotion): a cube balanced on a corner over a slab, its corner
// touching, margin 1.2 (side 2: the corner's three neighbours 2 / sqrt(3) = 1.155 up, within
// it). The manifold is the incident face round the corner, clipped: the corner and the two
// neighbours on that face. Falling at 2 per unit time over h = 1, the third neighbour (on no
// incident face) would cross the slab within the step: it becomes a look-ahead point with
// the slab's normal and its present gap 2 / sqrt(3) (1e-12: a few roundings of order-1
// values). Without the motion there is none.
TEST(PolyhedronContact, LookAheadAddsTheCornerAFallBringsDown) {
  const ConvexPolyhedron slab = box(Vec(-5, -5, -1), Vec(5, 5, 0));
  const ConvexPolyhedron cube = box(Vec(-1, -1, -1), Vec(1, 1, 1));
  const Quat q = Quat::FromTwoVectors(Vec(-1, -1, -1).normalized(), Vec(0, 0, -1));
  const Vec at(0.2, -0.1, std::sqrt(3.0));
  const PolyhedronContact still = polyhedron_contact(slab, Vec::Zero(), kI, cube, at, q, 1.2);
  ASSERT_EQ(still.kind, Kind::kFaceA);
  ASSERT_EQ(still.count, 3);
  EXPECT_EQ(still.ahead, 0);
  ManifoldMotion fall;
  fall.v_b = Vec(0, 0, -2);
  fall.x_b = at;
  fall.h = 1.0;
  const PolyhedronContact c = polyhedron_contact(slab, Vec::Zero(), kI, cube, at, q, 1.2, fall);
  ASSERT_EQ(c.count, 3);
  ASSERT_EQ(c.ahead, 1);
  for (int t = 0; t < 3; ++t)
    EXPECT_NEAR((c.points[t].position - still.points[t].position).norm(), 0.0, 1e-12);
  const PolyhedronContactPoint& p = c.points[3];
  EXPECT_NEAR(p.gap, 2.0 / std::sqrt(3.0), 1e-12);
  EXPECT_NEAR(p.position.z(), p.gap, 1e-12);
  EXPECT_NEAR((c.normal_of(3) - Vec::UnitZ()).norm(), 0.0, 1e-12);
  int corners = 0;  // it is a corner of the cube, and none of the manifold's
  for (const Vec& v : cube.vertices()) corners += ((q * v + at) - p.position).norm() <= 1e-12;
  EXPECT_EQ(corners, 1);
  for (int t = 0; t < 3; ++t) EXPECT_GT((c.points[t].position - p.position).norm(), 1.0);
}

// Counts failures of one kind; reports the first few in full.
struct Tally {
  const char* what;
  int count = 0;
  void fail(int pair, const std::string& detail) {
    if (count++ < 5) ADD_FAILURE() << what << ", pair " << pair << ": " << detail;
  }
};

// The manifold against the reference solids: 1 to 4 points when separation <= margin (none
// beyond), each gap within the margin and no deeper than the chosen axis allows, each face
// contact's point on the incident solid's surface with the gap its height over the reference
// face's plane, an edge pair's gap the separation. And the deepest point is never left out:
// when the incident solid's lowest vertex along the normal lies over the reference face
// (its foot on the face's plane inside the reference solid, by more than tol), a point of the
// manifold is as deep (the corner that would otherwise sink unconstrained; `deepest` counts
// the pairs where this was checked).
void check_manifold(const PolyhedronContact& c, const Solid& a, const Solid& b, double margin,
                    double tol, double slack, int pair, Tally& bad, int& deepest) {
  if (c.separation > margin) {
    if (c.count != 0) bad.fail(pair, "points beyond the margin");
    return;
  }
  if (c.count < 1 || c.count > 4) return bad.fail(pair, "count " + std::to_string(c.count));
  const bool face_a = c.kind == Kind::kFaceA;
  const Solid& incident = face_a ? b : a;
  const Solid& reference = face_a ? a : b;
  const Vec out = face_a ? c.normal : Vec(-c.normal);  // the reference face's outward normal
  double top = -kInf;
  for (const Vec& x : reference.v) top = std::max(top, out.dot(x));
  for (int k = 0; k < c.count; ++k) {
    const auto& [x, gap] = c.points[k];
    if (gap > margin + tol || gap < c.separation - slack - tol)
      bad.fail(pair, fmt::format("gap {:.17g} for separation {:.17g}", gap, c.separation));
    if (c.kind == Kind::kEdgeEdge) {
      if (gap != c.separation) bad.fail(pair, "edge gap is not the separation");
      continue;
    }
    double height = -kInf;  // over the incident solid's surface: 0 on it
    for (std::size_t t = 0; t < incident.tris.size(); ++t)
      height = std::max(height, incident.n[t].dot(x) - incident.h[t]);
    if (std::abs(height) > tol) bad.fail(pair, "point off the incident surface");
    if (std::abs(out.dot(x) - top - gap) > tol) bad.fail(pair, "gap is not the height");
  }
  if (c.kind == Kind::kEdgeEdge) return;
  std::size_t low = 0;
  for (std::size_t k = 1; k < incident.v.size(); ++k)
    if (out.dot(incident.v[k]) < out.dot(incident.v[low])) low = k;
  const double depth = out.dot(incident.v[low]) - top;
  const Vec foot = incident.v[low] - depth * out;
  double inside = -kInf;  // the foot's height over the reference solid's surface
  for (std::size_t t = 0; t < reference.tris.size(); ++t)
    if (std::abs(reference.n[t].dot(out) - 1.0) > 1e-9)  // the face's own plane holds the foot
      inside = std::max(inside, reference.n[t].dot(foot) - reference.h[t]);
  if (!(inside < -tol)) return;
  ++deepest;
  double least = kInf;
  for (int k = 0; k < c.count; ++k) least = std::min(least, c.points[k].gap);
  if (std::abs(least - depth) > tol)
    bad.fail(pair, fmt::format("deepest point {:.17g} left out (least gap {:.17g})", depth, least));
}

// ---------------------------------------------------------------------------------------
// Random pairs

// Under AddressSanitizer (CI's asan-ubsan build runs the unit tests) the narrow phase and the
// references run about 50 times slower: there the random tests take 1 % of their pairs,
// enough to run every path under the sanitizers; the release build takes them all.
#if defined(__SANITIZE_ADDRESS__)
constexpr int kShare = 100;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr int kShare = 100;
#else
constexpr int kShare = 1;
#endif
#else
constexpr int kShare = 1;
#endif

// 10^5 random pairs (64 shapes of 8 to 30 vertices, random poses, centres 0.25 to 1.05 radii
// sums apart; every 10th overlapping pair moved out along its best axis by its depth, to
// touch) against the unpruned axes. Zero disagreements: overlapping (reference below -tol),
// the separation is minus the reference's depth within tol, and the normal's own separation
// (measured on the reference solids) is within the axis preference of it, and it is the
// reference's axis within 1e-9 wherever no other axis comes within the preference; apart
// (above tol), the separation is > 0 and is a separation along an axis: no more than the
// reference's best (the full test's axes are a subset of its axes) or than the one measured
// along the contact's own normal (the GJK pre-test's axis, which may see more of the distance
// than any face or edge axis; RandomPairsMatchTheExactDistance checks the distance itself);
// touching (within tol), within 2 tol of 0. The manifold (margin 0.02 of the radii's
// sum, so that near contacts build one too): check_manifold. The counts of each case are
// checked too, so that every case is exercised.
TEST(PolyhedronContact, RandomPairsMatchTheUnprunedAxes) {
  const auto shapes = random_shapes(64, 2009);
  std::mt19937_64 gen(42);
  const int kPairs = 100000 / kShare;
  Tally sign{"apart or overlapping, not as the reference"}, depth{"penetration depth"},
      lower{"separation above the reference's and its own normal's"}, normal{"normal"},
      manifold{"manifold"};
  int overlapping = 0, apart = 0, touching = 0, strict = 0, edge_edge = 0, deepest = 0;
  std::vector<std::pair<double, Vec>> all;
  for (int i = 0; i < kPairs; ++i) {
    Pair p = random_pair(shapes, gen);
    const Solid a = posed(p.a->hull, p.xa, p.qa);
    Solid b = posed(p.b->hull, p.xb, p.qb);
    const double scale = p.a->poly.radius() + p.b->poly.radius(), tol = 1e-9 * scale;
    const double slack =
        PolyhedronContact::kAxisPreference * std::min(p.a->poly.radius(), p.b->poly.radius());
    const double guard = slack + tol, margin = 0.02 * scale;
    if (i % 10 == 0) {
      const double seed = separation_along(a, b, contact(p, margin).normal);
      const AxisAnswer before = unpruned_axes(a, b, seed, guard, all);
      if (before.best < 0) {
        p.xb -= before.best * before.axis;
        b = posed(p.b->hull, p.xb, p.qb);
      }
    }
    const PolyhedronContact c = contact(p, margin);
    // The separation along the narrow phase's normal, measured on the solids: a true value
    // along a candidate axis, so it may set the floor under which the reference skips axes.
    const double along = separation_along(a, b, c.normal);
    const AxisAnswer ref = unpruned_axes(a, b, std::isfinite(along) ? along : -kInf, guard, all);
    const double s = c.separation;
    const std::string got = fmt::format("separation {:.17g}, reference {:.17g}", s, ref.best);
    if (ref.best < -tol) {
      ++overlapping;
      if (!(s <= 0.0)) sign.fail(i, got);
      if (!(std::abs(s - ref.best) <= tol)) depth.fail(i, got);
      if (ref.best - ref.second > guard) {
        ++strict;
        if (!((c.normal - ref.axis).norm() <= 1e-9)) normal.fail(i, "not the best axis");
      }
    } else if (ref.best > tol) {
      ++apart;
      if (!(s > 0.0)) sign.fail(i, got);
      if (!(s <= std::max(ref.best, along) + tol)) lower.fail(i, got);
    } else {
      ++touching;
      if (!(std::abs(s) <= 2 * tol)) sign.fail(i, got);
    }
    if (!(along >= s - slack - tol && along <= s + tol && std::abs(c.normal.norm() - 1) < 1e-12))
      normal.fail(i, fmt::format("its own separation {:.17g}, {}", along, got));
    check_manifold(c, a, b, margin, tol, slack, i, manifold, deepest);
    edge_edge += c.kind == Kind::kEdgeEdge;
  }
  EXPECT_EQ(sign.count, 0);
  EXPECT_EQ(depth.count, 0);
  EXPECT_EQ(lower.count, 0);
  EXPECT_EQ(normal.count, 0);
  EXPECT_EQ(manifold.count, 0);
  EXPECT_EQ(overlapping + apart + touching, kPairs);
  // Every case is there in numbers. The release build's 10^5 pairs: 54,057 overlapping (51,533
  // of them with one best axis), 39,901 apart, 6,042 touching; 54,392 edge-pair normals.
  EXPECT_GT(overlapping, kPairs / 3);
  EXPECT_GT(apart, kPairs / 5);
  EXPECT_GT(touching, kPairs / 50);
  EXPECT_GT(strict, overlapping / 2);
  EXPECT_GT(edge_edge, kPairs / 20);
  EXPECT_GT(deepest, kPairs / 10);
}

// A few thousand random pairs (every 5th overlapping one moved to touch) against the exact
// distance: > tol apart, the separation is > 0 and at most the distance (a lower bound);
// meeting (distance 0), the separation is <= tol; touching, within 2 tol of 0 and the
// distance within tol. Zero disagreements. Margin 0.
TEST(PolyhedronContact, RandomPairsMatchTheExactDistance) {
  const auto shapes = random_shapes(64, 2013);
  std::mt19937_64 gen(7);
  const int kPairs = kShare == 1 ? 3000 : 300;
  Tally bad{"separation against the exact distance"};
  int apart = 0, meeting = 0, touching = 0;
  std::vector<std::pair<double, Vec>> all;
  for (int i = 0; i < kPairs; ++i) {
    Pair p = random_pair(shapes, gen);
    const Solid a = posed(p.a->hull, p.xa, p.qa);
    Solid b = posed(p.b->hull, p.xb, p.qb);
    bool touch = false;
    if (i % 5 == 0) {
      const AxisAnswer ref = unpruned_axes(a, b, -kInf, 0.0, all);
      if (ref.best < 0) {
        p.xb -= ref.best * ref.axis;
        b = posed(p.b->hull, p.xb, p.qb);
        touch = true;
      }
    }
    const double tol = 1e-9 * (p.a->poly.radius() + p.b->poly.radius());
    const double d = exact_distance(a, b), s = contact(p, 0.0).separation;
    const std::string got = fmt::format("separation {:.17g}, distance {:.17g}", s, d);
    if (touch) {
      ++touching;
      if (!(std::abs(s) <= 2 * tol && d <= tol)) bad.fail(i, got);
    } else if (d > tol) {
      ++apart;
      if (!(s > 0.0 && s <= d + tol)) bad.fail(i, got);
    } else {
      ++meeting;
      if (!(d == 0.0 && s <= tol)) bad.fail(i, got);
    }
  }
  EXPECT_EQ(bad.count, 0);
  // The release build's 3,000 pairs: 1,169 apart, 1,422 meeting, 409 touching.
  EXPECT_GT(apart, kPairs / 5);
  EXPECT_GT(meeting, kPairs / 3);
  EXPECT_GT(touching, kPairs / 20);
}

// The same call twice gives the same bits (no hidden state, no dependence on memory), over
// random pairs with a margin so that manifolds are built.
TEST(PolyhedronContact, Deterministic) {
  const auto shapes = random_shapes(16, 5);
  std::mt19937_64 gen(3);
  auto bits = [](double x) { return std::bit_cast<std::uint64_t>(x); };
  for (int i = 0; i < 500; ++i) {
    const Pair p = random_pair(shapes, gen);
    const PolyhedronContact c = contact(p, 0.1), d = contact(p, 0.1);
    ASSERT_EQ(bits(c.separation), bits(d.separation));
    for (int k = 0; k < 3; ++k) ASSERT_EQ(bits(c.normal[k]), bits(d.normal[k]));
    ASSERT_EQ(c.kind, d.kind);
    ASSERT_EQ(c.feature_a, d.feature_a);
    ASSERT_EQ(c.feature_b, d.feature_b);
    ASSERT_EQ(c.count, d.count);
    for (int j = 0; j < c.count; ++j) {
      ASSERT_EQ(bits(c.points[j].gap), bits(d.points[j].gap));
      for (int k = 0; k < 3; ++k)
        ASSERT_EQ(bits(c.points[j].position[k]), bits(d.points[j].position[k]));
    }
  }
}

}  // namespace
