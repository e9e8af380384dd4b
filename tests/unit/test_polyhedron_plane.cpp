// The narrow phase between a convex polyhedron and a plane wall (geometry/polyhedron_plane.hpp):
// exact manifolds where the answer is known (a cube face down, tilted about an edge, tilted by
// a hair, on a vertex; a tetrahedron on its vertex, edge and face; an octagonal prism whose 8
// bottom corners reduce to 4, as the pair narrow phase reduces them, and keep the one a spin
// brings down first), the same answer after a
// rigid motion of grain and plane together (planes of any normal), random poses against a
// brute-force scan of the vertices, and the refused inputs.
//
// Tolerances. Hand-built cases: 1e-12 (coordinates of order 1, a few roundings each; the
// exact cases say why they are exact). Random poses: the separation, gaps, points and incident
// face bit for bit against the same formulas written out (R v + x with R =
// q.toRotationMatrix(), n . (y - p)), and within 1e-14 of the scale against q * v + x.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "polyhedron_reference.hpp"
#include "sable/core/error.hpp"
#include "sable/geometry/convex_hull.hpp"
#include "sable/geometry/convex_polyhedron.hpp"
#include "sable/geometry/polyhedron_contact.hpp"
#include "sable/geometry/polyhedron_plane.hpp"

using namespace sable;
using namespace sable::test;

namespace {

using Kind = PolyhedronContactKind;
const Quat kI = Quat::Identity();
const Vec kUp = Vec::UnitZ();

// The plane z = 0, its grains above.
PolyhedronContact on_floor(const ConvexPolyhedron& a, const Vec& x, const Quat& q, double margin) {
  return polyhedron_plane_contact(a, x, q, Vec::Zero(), kUp, margin);
}

// The reported points are `want`, in that order (the plane's points come in the order of the
// grain's vertices), each within tol.
void expect_points_in_order(const PolyhedronContact& c, const std::vector<Vec>& want, double tol) {
  ASSERT_EQ(c.count, static_cast<int>(want.size()));
  for (int k = 0; k < c.count; ++k)
    EXPECT_NEAR((c.points[k].position - want[k]).norm(), 0.0, tol)
        << "point " << k << " at " << c.points[k].position.transpose() << ", expected "
        << want[k].transpose();
}

// The world corners of `a` posed by (x, q), in vertex order, whose height is below `cut`.
std::vector<Vec> corners_below(const ConvexPolyhedron& a, const Vec& x, const Quat& q, double cut) {
  std::vector<Vec> out;
  for (const Vec& v : a.vertices())
    if (const Vec y = q * v + x; y.z() < cut) out.push_back(y);
  return out;
}

// ---------------------------------------------------------------------------------------
// Hand-built contacts

// A unit cube face down on z = 0, its centre at height 1/2 + g: its 4 bottom corners, each
// with gap g, whether overlapping (g < 0), touching (g = 0) or hovering within the margin;
// none beyond the margin (the separation still reported). The wall's face is the reference
// (kFaceB), the normal -z exactly, the incident face the cube's bottom. 1e-15: only the
// height 1/2 + g is rounded (once, below 6e-17); the corners (+-1/2), the identity turn and
// the plane are exact.
TEST(PolyhedronPlane, CubeFaceDownGivesItsFourBottomCorners) {
  const ConvexPolyhedron cube = box(-kHalf, kHalf);
  struct Case {
    double g, margin;
    int count;
  };
  for (const Case& k : {Case{-1e-3, 0.0, 4}, Case{0.0, 0.0, 4}, Case{1e-4, 2e-4, 4},
                        Case{1e-4, 5e-5, 0}, Case{-1e-3, 0.5, 4}}) {
    const Vec at(0.3, -0.2, 0.5 + k.g);
    const PolyhedronContact c = on_floor(cube, at, kI, k.margin);
    EXPECT_EQ(c.kind, Kind::kFaceB);
    EXPECT_EQ(c.normal, Vec(-kUp));
    EXPECT_EQ(c.feature_b, 0u);
    EXPECT_NEAR(c.separation, k.g, 1e-15);
    if (k.count == 0) {
      EXPECT_EQ(c.count, 0);
      EXPECT_EQ(c.feature_a, 0u);
      continue;
    }
    EXPECT_EQ(cube.normals()[c.feature_a], Vec(-kUp));
    expect_points_in_order(c, corners_below(cube, at, kI, at.z()), 1e-15);
    for (int i = 0; i < c.count; ++i) EXPECT_NEAR(c.points[i].gap, k.g, 1e-15);
  }
}

// The cube turned by 1e-3 rad about y, which lowers its bottom edge at x = +1/2 (body frame),
// that edge 1e-4 into the floor: its 2 corners with the margin 0; the 4 bottom corners with a
// margin above the other bottom edge's lift (sin 1e-3), each gap the corner's height. 1e-12:
// a few roundings of order-1 values.
TEST(PolyhedronPlane, CubeTiltedAboutAnEdge) {
  const ConvexPolyhedron cube = box(-kHalf, kHalf);
  const double tilt = 1e-3, g = -1e-4;
  const Quat q(Eigen::AngleAxisd(tilt, Vec::UnitY()));
  const Vec at(-1.0, 2.0, 0.5 * (std::sin(tilt) + std::cos(tilt)) + g);
  const PolyhedronContact edge = on_floor(cube, at, q, 0.0);
  EXPECT_NEAR(edge.separation, g, 1e-12);
  expect_points_in_order(edge, corners_below(cube, at, q, 0.0), 1e-12);
  for (int i = 0; i < edge.count; ++i) {
    EXPECT_NEAR(edge.points[i].gap, g, 1e-12);
    EXPECT_NEAR((q.conjugate() * (edge.points[i].position - at)).x(), 0.5, 1e-12);
  }
  const PolyhedronContact face = on_floor(cube, at, q, 2e-3);
  EXPECT_NEAR(face.separation, g, 1e-12);
  expect_points_in_order(face, corners_below(cube, at, q, at.z() - 0.1), 1e-12);
  for (int i = 0; i < face.count; ++i) {
    const Vec body = q.conjugate() * (face.points[i].position - at);
    EXPECT_NEAR(face.points[i].gap, body.x() > 0 ? g : g + std::sin(tilt), 1e-12);
  }
}

// A face down with a tilt of 1e-12 rad (about a skew horizontal axis): still 4 points, not 1,
// overlapping by 1e-6 with margin 0, or hovering 1e-6 over the floor within a margin of 1e-5.
// No axis is preferred here: every corner within the margin is a point, and the tilt moves
// the corners by 1e-12, far inside either.
TEST(PolyhedronPlane, HairlineTiltKeepsTheFourCorners) {
  const ConvexPolyhedron cube = box(-kHalf, kHalf);
  const Quat q(Eigen::AngleAxisd(1e-12, Vec(1, 2, 0).normalized()));
  for (const double g : {-1e-6, 1e-6}) {
    const Vec at(0.1, 0.1, 0.5 + g);
    const PolyhedronContact c = on_floor(cube, at, q, g < 0 ? 0.0 : 1e-5);
    EXPECT_NEAR(c.separation, g, 1e-12);
    expect_points_in_order(c, corners_below(cube, at, q, at.z()), 1e-12);
  }
}

// The cube on a corner (its diagonal vertical, corner 0 at the bottom), sqrt(3)/2 - 1e-3 above
// the floor: 1 point at that corner, separation -1e-3 to 1e-12 of the cube's size (the turn
// rounds the corner's height at 1e-16). Its 3 neighbours stand 1/sqrt(3) higher: still 1 point
// within a margin of 0.5, 4 within 0.6. The incident face is one of the 3 at the corner
// (they tie: rounding picks).
TEST(PolyhedronPlane, CubeOnAVertex) {
  const ConvexPolyhedron cube = box(-kHalf, kHalf);
  const double depth = 1e-3;
  const Quat q = Quat::FromTwoVectors(-Vec::Ones(), -kUp);
  const Vec at(0.1, 0.2, std::sqrt(0.75) - depth);
  ASSERT_EQ(cube.vertices()[0], -kHalf);
  for (const double margin : {0.0, 0.5}) {
    const PolyhedronContact c = on_floor(cube, at, q, margin);
    EXPECT_NEAR(c.separation, -depth, 1e-12);
    expect_points_in_order(c, {q * cube.vertices()[0] + at}, 1e-12);
    EXPECT_NEAR(c.points[0].gap, -depth, 1e-12);
    EXPECT_NEAR(cube.normals()[c.feature_a].sum(), -1.0, 1e-15);
  }
  const PolyhedronContact wide = on_floor(cube, at, q, 0.6);
  expect_points_in_order(wide, corners_below(cube, at, q, 0.6), 1e-12);
}

// A regular tetrahedron dipping 1e-3 into the floor on a vertex, an edge and a face: 1, 2 and
// 3 points at those corners, each 1e-3 deep (margin 0: the corners above the floor are no
// contact); face down, the incident face is that face. 1e-12: a few roundings.
TEST(PolyhedronPlane, TetrahedronOnVertexEdgeAndFace) {
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
    const Quat q = Quat::FromTwoVectors(k.down, -kUp);
    const Vec at(0.1, 0.2, -(q * corners[k.touching[0]]).z() - deep);
    const PolyhedronContact c = on_floor(tetra, at, q, 0.0);
    EXPECT_NEAR(c.separation, -deep, 1e-12);
    std::vector<Vec> want;
    for (int i : k.touching) want.push_back(q * corners[i] + at);
    expect_points_in_order(c, want, 1e-12);
    for (int i = 0; i < c.count; ++i) EXPECT_NEAR(c.points[i].gap, -deep, 1e-12);
    if (k.touching.size() == 3) {
      EXPECT_NEAR((q * tetra.normals()[c.feature_a] + kUp).norm(), 0.0, 1e-12);
    }
  }
}

// The prism over the regular octagon of unit radius (a corner on the x axis), 0.5 high.
ConvexPolyhedron octagonal_prism() {
  std::vector<Vec> points;
  for (const double z : {-0.25, 0.25})
    for (int k = 0; k < 8; ++k) {
      const double t = k * std::numbers::pi / 4;
      points.emplace_back(std::cos(t), std::sin(t), z);
    }
  return ConvexPolyhedron(convex_hull(points, "prism"), "prism");
}

// A prism on a regular octagon (radius 1, height 1/2), face down 1e-3 into the floor and
// tilted by 1e-6 so that its corner at angle 0 is the deepest: its 8 bottom corners are within
// the margin, and the rule keeps 4: the deepest (angle 0), the farthest from it (pi), the
// largest triangle with those (pi/2 or 3 pi/2, tied to rounding), the most area outside it
// (the other): the square of every other corner, in vertex order. The pair narrow phase, the
// prism on a slab whose top is the floor, reduces the same 8 corners to the same 4 (the
// slab's face the reference; its rule is this one). 1e-12: a few roundings.
TEST(PolyhedronPlane, EightCornersReduceToTheSquareOfThePairRule) {
  const ConvexPolyhedron prism = octagonal_prism();
  ASSERT_EQ(prism.vertices().size(), 16u);
  const Quat q(Eigen::AngleAxisd(1e-6, Vec::UnitY()));
  const Vec at(0.4, -0.3, 0.25 - 1e-3);
  const PolyhedronContact c = on_floor(prism, at, q, 0.0);
  std::vector<Vec> want;  // the bottom corners at angles 0, pi/2, pi, 3 pi/2, in vertex order
  for (const Vec& v : prism.vertices())
    if (v.z() < 0 && std::abs(v.x() * v.y()) < 1e-12) want.push_back(q * v + at);
  ASSERT_EQ(want.size(), 4u);
  expect_points_in_order(c, want, 1e-12);
  EXPECT_NEAR(c.separation, (q * Vec(1, 0, -0.25) + at).z(), 1e-12);
  const ConvexPolyhedron slab = box(Vec(-3, -3, -1), Vec(3, 3, 0));
  const PolyhedronContact pair = polyhedron_contact(slab, Vec::Zero(), kI, prism, at, q, 0.0);
  ASSERT_EQ(pair.kind, Kind::kFaceA);
  ASSERT_EQ(pair.count, 4);
  for (const Vec& w : want) {
    int found = 0;
    for (int k = 0; k < 4; ++k) found += (pair.points[k].position - w).norm() <= 1e-12;
    EXPECT_EQ(found, 1) << w.transpose();
  }
}

// With its motion over the step (ManifoldMotion), a manifold of more than 4 points keeps the
// one the grain's spin brings down first. The octagonal prism flat, 0.01 above the plane
// (margin 0.05: all 8 bottom corners within it, equally high); ranked by their present gaps,
// 4 are kept and corner X is not. Turning at w = 20 rad/s (axis horizontal, perpendicular to
// X's arm) over h = 1e-3 s, X comes down by h w |arm| = 0.02: predicted gap -0.01, the lowest,
// so it is kept first; the gaps reported stay the present ones (0.01, exact to 1e-12: one
// rounding of order-1 values). The pair's narrow phase (a slab under the prism) does the
// same. Without it a fast-turning grain in contact dynamics sank by a corner the rule had
// dropped (docs/contact-dynamics.md).
TEST(PolyhedronPlane, SpinBringsDownTheCornerKeptFirst) {
  const ConvexPolyhedron prism = octagonal_prism();
  const Vec at(0.4, -0.3, 0.25 + 0.01);
  const double margin = 0.05, h = 1e-3, w = 20.0;
  const PolyhedronContact still = on_floor(prism, at, kI, margin);
  ASSERT_EQ(still.count, 4);
  Vec x = Vec::Zero();  // a bottom corner the present gaps drop
  for (const Vec& v : prism.vertices()) {
    if (v.z() > 0) continue;
    bool kept = false;
    for (int k = 0; k < 4; ++k) kept |= (still.points[k].position - (v + at)).norm() <= 1e-12;
    if (!kept) x = v + at;
  }
  ASSERT_GT(x.norm(), 0.0);
  const Vec arm = x - at;
  ManifoldMotion motion;
  motion.w_a = w * Vec(-arm.y(), arm.x(), 0.0);  // (w x arm).z = -w |arm|^2 = -w at X
  motion.x_a = at;
  motion.h = h;
  const PolyhedronContact c =
      polyhedron_plane_contact(prism, at, kI, Vec::Zero(), kUp, margin, motion);
  ASSERT_EQ(c.count, 4);
  bool found = false;
  for (int k = 0; k < 4; ++k) {
    found |= (c.points[k].position - x).norm() <= 1e-12;
    EXPECT_NEAR(c.points[k].gap, 0.01, 1e-12);
  }
  EXPECT_TRUE(found) << "corner " << x.transpose() << " left out";
  EXPECT_NEAR(motion.predicted(x, -kUp, 0.01), -0.01, 1e-12);

  const ConvexPolyhedron slab = box(Vec(-3, -3, -1), Vec(3, 3, 0));
  ManifoldMotion on_slab;  // A is the slab, at rest; B the prism
  on_slab.w_b = motion.w_a;
  on_slab.x_b = at;
  on_slab.h = h;
  const PolyhedronContact pair =
      polyhedron_contact(slab, Vec::Zero(), kI, prism, at, kI, margin, on_slab);
  ASSERT_EQ(pair.kind, Kind::kFaceA);
  ASSERT_EQ(pair.count, 4);
  EXPECT_NEAR((pair.points[0].position - x).norm(), 0.0, 1e-12);  // kept first: the deepest
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(pair.points[k].gap, 0.01, 1e-12);
}

// One rigid motion (a turn and a shift) of grain and plane together changes nothing but the
// frame: the same separation and gaps, the same corners (turned and shifted) in the same
// order, the normal the plane's turned, the same incident face where one face is lowest.
// Planes of 20 random normals, the cube on a face, on an
// edge and on a corner, and the tetrahedron on an edge. 1e-12: a few roundings of order-1
// values (the shift is of order 1 too).
TEST(PolyhedronPlane, RigidMotionOfGrainAndPlaneTogether) {
  const ConvexPolyhedron cube = box(-kHalf, kHalf);
  const ConvexPolyhedron tetra(convex_hull(tetra_corners()), "tetrahedron");
  struct Pose {
    const ConvexPolyhedron* shape;
    Quat q;
    double margin;
    bool one_face;  // one face lowest (on a corner or an edge, faces tie: rounding picks)
  };
  const std::vector<Pose> poses = {
      {&cube, kI, 0.0, true},
      {&cube, Quat(Eigen::AngleAxisd(0.3, Vec::UnitX())), 1e-3, true},
      {&cube, Quat::FromTwoVectors(-Vec::Ones(), -kUp), 0.0, false},
      {&tetra, Quat::FromTwoVectors(tetra_corners()[0] + tetra_corners()[1], -kUp), 0.0, false}};
  std::mt19937_64 gen(23);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 20; ++i) {
    const Quat turn = random_rotation(gen);
    const Vec shift = draw3([&] { return u(gen); });
    for (const Pose& pose : poses) {
      double low = kInf;
      for (const Vec& v : pose.shape->vertices()) low = std::min(low, (pose.q * v).z());
      const Vec at(0.2, -0.1, -low - 2e-4);
      const PolyhedronContact c = on_floor(*pose.shape, at, pose.q, pose.margin);
      const Vec n = turn * kUp;
      const PolyhedronContact m = polyhedron_plane_contact(*pose.shape, turn * at + shift,
                                                           turn * pose.q, shift, n, pose.margin);
      EXPECT_EQ(m.normal, Vec(-n));
      EXPECT_NEAR(m.separation, c.separation, 1e-12);
      if (pose.one_face) {
        EXPECT_EQ(m.feature_a, c.feature_a);
      }
      ASSERT_EQ(m.count, c.count) << "turn " << i;
      for (int k = 0; k < c.count; ++k) {
        EXPECT_NEAR((m.points[k].position - (turn * c.points[k].position + shift)).norm(), 0.0,
                    1e-12);
        EXPECT_NEAR(m.points[k].gap, c.points[k].gap, 1e-12);
      }
    }
  }
}

// ---------------------------------------------------------------------------------------
// Random poses

// Whether x lies in the triangle (p, q, r) seen along n, within tol (an area) of each side.
bool in_triangle(const Vec& x, const Vec& p, const Vec& q, const Vec& r, const Vec& n, double tol) {
  const auto area = [&](const Vec& a, const Vec& b, const Vec& c) {
    return (b - a).cross(c - a).dot(n);
  };
  const double s = area(p, q, r) > 0 ? 1.0 : -1.0;
  return s * area(p, q, x) >= -tol && s * area(q, r, x) >= -tol && s * area(r, p, x) >= -tol;
}

auto bits(double v) {
  return std::bit_cast<std::uint64_t>(v);
}
bool same(const Vec& a, const Vec& b) {
  return bits(a.x()) == bits(b.x()) && bits(a.y()) == bits(b.y()) && bits(a.z()) == bits(b.z());
}

// What the random poses exercised.
struct PoseTally {
  std::array<int, 5> by_count{};  // poses with 1 to 4 vertices within the margin; 0: beyond it
  int reduced = 0, three = 0;     // more than 4 within it; reduced to 3 points
  int touching = 0;               // reduced with 2 or 3 vertices at or below the plane
  double worst = 0.0;             // off q * v + x, relative to the scale
};

// The scan of one pose: the checks listed above RandomPosesMatchTheVertexScan.
void check_pose(const ConvexPolyhedron& a, const Vec& x, const Quat& q, const Vec& p, const Vec& n,
                double margin, const std::string& at, PoseTally& t) {
  const PolyhedronContact c = polyhedron_plane_contact(a, x, q, p, n, margin);
  const Eigen::Matrix3d R = q.toRotationMatrix();
  const std::vector<Vec>& v = a.vertices();
  std::vector<Vec> y;
  std::vector<double> gap;
  std::vector<std::size_t> within;
  double low = kInf, low_q = kInf;
  for (std::size_t k = 0; k < v.size(); ++k) {
    y.push_back(R * v[k] + x);
    gap.push_back(n.dot(y[k] - p));
    low = std::min(low, gap[k]);
    low_q = std::min(low_q, n.dot(q * v[k] + x - p));
    if (gap[k] <= margin) within.push_back(k);
  }
  ASSERT_EQ(bits(c.separation), bits(low)) << at;
  const double scale = 1 + x.norm() + p.norm();
  t.worst = std::max(t.worst, std::abs(c.separation - low_q) / scale);
  ASSERT_LE(std::abs(c.separation - low_q), 1e-14 * scale) << at;
  ASSERT_TRUE(same(c.normal, -n)) << at;
  ASSERT_EQ(c.kind, Kind::kFaceB) << at;
  ASSERT_EQ(c.feature_b, 0u) << at;
  if (low > margin) {
    ASSERT_EQ(c.count, 0) << at;
    ASSERT_EQ(c.feature_a, 0u) << at;
    ++t.by_count[0];
    return;
  }
  const Vec m = R.transpose() * n;
  std::uint32_t face = 0;
  for (std::uint32_t f = 1; f < a.face_count(); ++f)
    if (m.dot(a.normals()[f]) < m.dot(a.normals()[face])) face = f;
  ASSERT_EQ(c.feature_a, face) << at;
  // Each point a vertex within the margin, in vertex order, position and gap bit for bit.
  std::vector<std::size_t> kept;
  for (int j = 0; j < c.count; ++j) {
    std::size_t k = kept.empty() ? 0 : kept.back() + 1;
    while (k < v.size() && !same(y[k], c.points[j].position)) ++k;
    ASSERT_LT(k, v.size()) << at << ": point " << j << " is no vertex after the last";
    ASSERT_LE(gap[k], margin) << at;
    ASSERT_EQ(bits(c.points[j].gap), bits(gap[k])) << at;
    kept.push_back(k);
    const double off = (c.points[j].position - (q * v[k] + x)).norm();
    t.worst = std::max(t.worst, off / scale);
    ASSERT_LE(off, 1e-14 * scale) << at;
  }
  if (within.size() <= 4) {
    ASSERT_EQ(kept, within) << at;
    ++t.by_count[within.size()];
    return;
  }
  ++t.reduced;
  // Touching vertices come first (manifold_reduction.hpp): with at most 3 of them, every one
  // is kept.
  std::vector<std::size_t> touching;
  for (std::size_t k : within)
    if (gap[k] <= 0.0) touching.push_back(k);
  if (touching.size() >= 2 && touching.size() <= 3) {
    ++t.touching;
    for (std::size_t k : touching)
      ASSERT_NE(std::find(kept.begin(), kept.end(), k), kept.end())
          << at << ": touching vertex " << k << " left out";
  }
  const auto deepest =
      static_cast<std::size_t>(std::min_element(gap.begin(), gap.end()) - gap.begin());
  ASSERT_NE(std::find(kept.begin(), kept.end(), deepest), kept.end()) << at;
  ASSERT_GE(c.count, 3) << at;
  if (c.count == 3) {
    ++t.three;
    const double r = a.radius();
    for (std::size_t k : within)
      ASSERT_TRUE(in_triangle(y[k], y[kept[0]], y[kept[1]], y[kept[2]], n, 1e-12 * r * r))
          << at << ": vertex " << k << " outside the 3 kept";
  }
}

// 10^4 random poses (64 shapes of 8 to 30 vertices, turned at random anywhere in [-5, 5]^3;
// planes of random normal through a point up to 5 away in the plane, the grain's centre 0.5
// to 1.3 radii above it; margins 0, up to 0.05 radius, or up to half the radius) against a
// scan of the vertices by the formulas written out, R = q.toRotationMatrix():
//  - the separation is the least n . (R v + x - p), bit for bit, and within 1e-14 of the scale
//    (1 + |x| + |p|) of the least n . (q * v + x - p), the world vertex as q * v + x;
//  - the normal is -n bit for bit, the kind kFaceB, feature_b 0; feature_a the face lowest
//    along R^T n (bit for bit) when the manifold is built, else 0;
//  - beyond the margin no point; within it, the vertices with gap <= margin: 4 or fewer all,
//    in vertex order; more, 4 of them (or 3 where every other one lies in their triangle seen
//    along n: the rule then has nothing to add), the deepest among them, every vertex at or
//    below the plane among them when there are 2 or 3 such, in vertex order. Each
//    point is a vertex's R v + x and its gap bit for bit, and within 1e-14 of the scale of
//    q * v + x.
// The counts of each case are checked too, so that every case is exercised.
TEST(PolyhedronPlane, RandomPosesMatchTheVertexScan) {
  const auto shapes = random_shapes(64, 2027);
  std::mt19937_64 gen(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  PoseTally t;
  const int kPoses = 10000;
  for (int i = 0; i < kPoses; ++i) {
    const Shape& s = shapes[gen() % shapes.size()];
    const Quat q = random_rotation(gen);
    const Vec x = draw3([&] { return 10 * u(gen) - 5; });
    const Vec n = random_direction(gen);
    const double r = s.poly.radius();
    const Vec along = draw3([&] { return 10 * u(gen) - 5; });
    const Vec p = x - r * (0.5 + 0.8 * u(gen)) * n + (along - n.dot(along) * n);
    const double margin = i % 3 == 0 ? 0.0 : (i % 3 == 1 ? 0.05 : 0.5) * r * u(gen);
    check_pose(s.poly, x, q, p, n, margin, "pose " + std::to_string(i), t);
    if (HasFatalFailure()) return;
  }
  const std::string counts = fmt::format(
      "beyond the margin {}, 1 to 4 points {} {} {} {}, reduced {} (to 3 points: {}; with 2 or "
      "3 touching: {}), worst against q * v + x {:.3g} of the scale",
      t.by_count[0], t.by_count[1], t.by_count[2], t.by_count[3], t.by_count[4], t.reduced, t.three,
      t.touching, t.worst);
  // Every case is there in numbers. The seeded draw: 4,948 poses beyond the margin; 1,087,
  // 992, 782 and 639 with 1 to 4 vertices within it; 1,552 with more, reduced (5 of them to 3
  // points); the worst point or separation 1.5e-16 of the scale off q * v + x.
  EXPECT_GT(t.by_count[0], kPoses / 5) << counts;
  for (int k = 1; k <= 4; ++k) EXPECT_GT(t.by_count[k], kPoses / 20) << counts;
  EXPECT_GT(t.reduced, kPoses / 10) << counts;
  EXPECT_GT(t.three, 0) << counts;
  EXPECT_GT(t.touching, kPoses / 100) << counts;
}

// ---------------------------------------------------------------------------------------
// Refused input

// A negative or non-finite margin, a plane normal whose length is off 1 by more than 1e-9
// (or not finite, or zero) are refused with an InputError naming what; a normal off by
// 5e-10 is taken as it is.
TEST(PolyhedronPlane, BadMarginOrNormalIsRefused) {
  const ConvexPolyhedron cube = box(-kHalf, kHalf);
  const Vec at(0, 0, 0.5);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const double margin : {-1e-9, -kInf, kInf, nan}) {
    try {
      on_floor(cube, at, kI, margin);
      ADD_FAILURE() << "margin " << margin << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("margin"), std::string::npos) << e.what();
    }
  }
  for (const Vec& n : {Vec(0, 0, 2), Vec(0, 0, 1 + 2e-9), Vec(0, 0, 1 - 2e-9), Vec::Zero().eval(),
                       Vec(0, nan, 1), Vec(0, 0, kInf)}) {
    try {
      polyhedron_plane_contact(cube, at, kI, Vec::Zero(), n, 0.0);
      ADD_FAILURE() << "normal " << n.transpose() << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("normal"), std::string::npos) << e.what();
    }
  }
  const Vec near_unit(0, 0, 1 + 5e-10);
  const PolyhedronContact c = polyhedron_plane_contact(cube, at, kI, Vec::Zero(), near_unit, 0.0);
  EXPECT_EQ(c.normal, Vec(-near_unit));
  EXPECT_EQ(c.count, 4);
}

}  // namespace
