// The narrow phase between two convex polyhedra (geometry/convex_polyhedron.hpp), A and B,
// each posed by a position x and a unit quaternion q (world = q * body + x): how far apart
// they are, along which normal, and where they touch.
//
// Separating axes. Two convex polyhedra are apart exactly when some plane separates them, and
// then one parallel to a face of their Minkowski difference A - B does; the faces' normals are
// the face normals of A, those of B (turned over), and the cross products e_A x e_B of one
// edge of each whose arcs on the Gauss map cross (D. Gregorius, "The Separating Axis Test
// between Convex Polyhedra", GDC 2013). An edge's arc joins the normals of its two faces; B's
// arcs enter turned over (the Gauss map of -B). Two arcs ab and cd (each shorter than a half
// circle) cross when c and d lie on opposite sides of the plane of a and b, a and b on
// opposite sides of the plane of c and d, and the two crossings of the great circles are the
// same point, not antipodes: with u = a x b and w = c x d, (c.u)(d.u) < 0, (a.w)(b.w) < 0
// and (c.u)(b.w) > 0. Only those pairs are tested: the others are no face of A - B.
//
// The separation along a unit axis n (from A to B) is min over B of n.x - max over A of n.x:
// > 0 apart by at least that much, < 0 overlapping by at least its magnitude. `separation` is
// the largest over the axes tested: for overlapping shapes, minus the penetration depth (the
// shortest translation that parts them); for shapes apart, a lower bound of their distance,
// and > 0 exactly when they are apart. First a GJK walk towards the closest points (a few
// axes at O(V_A + V_B) each) looks for an axis that shows the shapes apart by more than the
// margin; one found settles the pair (its separation and axis are returned, kind and features
// keep their defaults), as it does for most candidates of a dense packing, whose bounding
// spheres overlap while the hulls do not touch. Otherwise the axes are tested faces of A,
// faces of B, then edge pairs, and the test stops at the first family that shows the shapes
// apart by more than the margin (its best axis then gives the normal): for shapes within the
// margin every axis is tested, and the answer is the same as without the early stops. For an
// edge pair the edges themselves are the extreme points along the axis (that is what the
// Gauss-map test says), so each pair costs O(1); a face axis takes the other shape's lowest
// vertex.
//
// Axis preference. Near a resting contact a face axis and an edge axis (or a face of each
// shape) can be equally good within rounding, or nearly so under a slight tilt, and choosing
// by rounding would make the manifold flicker (4 points one step, 1 the next). The normal and
// the manifold are therefore taken from the first of: a face of A, a face of B, an edge pair,
// whose separation is within kAxisPreference times the smaller shape's radius of the largest.
// `separation` stays the largest, whichever is chosen; the chosen axis's own separation may be
// up to that tolerance below it, and the manifold's gaps are measured along the chosen normal.
//
// The manifold, when separation <= margin:
//  - face axis: the reference face is the chosen face, the incident face, among the
//    other shape's faces round its deepest corner along the normal, the most anti-parallel to
//    it (a face most anti-parallel over the whole shape may not hold that corner, which would
//    then sink unconstrained); the incident face is clipped against the side planes of
//    the reference face (Sutherland-Hodgman), and the clipped points within `margin` of the
//    reference plane are kept, each with its gap (its signed distance from the reference
//    plane, along the normal). The points lie on the incident face. Over 4 points, 4 are
//    kept: the deepest; the one farthest from it; the one making the largest triangle with
//    those two; the one adding the most area outside one side of that triangle (areas and
//    distances in the reference plane: geometry/manifold_reduction.hpp, the rule the plane's
//    manifold, geometry/polyhedron_plane.hpp, shares). When no clipped point is kept (the
//    incident face lies beside the reference face: shapes apart across a corner), the
//    manifold is the incident shape's deepest vertex along the normal, its gap the face's
//    separation.
//    A vertex on a face gives 1 point, an edge on a face 2, a face on a face up to 4;
//  - edge pair: one point, midway between the closest points of the two edges, its gap the
//    separation.
//
// Cost per call: for shapes apart beyond the margin, usually a few GJK steps of O(V_A + V_B);
// otherwise O(F_A V_B + F_B V_A + E_A E_B) for V vertices, E edges, F faces (each face
// axis scans the other shape's vertices; every edge pair takes the Gauss-map test), then
// O(k_I k_R) to clip the incident face (k_I corners) by the reference face (k_R). No heap
// allocation: the clipped polygon lives in fixed buffers of 2 kMaxFaceCorners points on the
// stack (about 9 kB in all).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>

#include "sable/geometry/convex_polyhedron.hpp"

namespace sable {

enum class PolyhedronContactKind : std::uint8_t { kFaceA, kFaceB, kEdgeEdge };

struct PolyhedronContactPoint {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // world
  double gap = 0.0;  // signed distance along the normal: > 0 apart, < 0 overlapping
};

struct PolyhedronContact {
  static constexpr int kMaxPoints = 4;
  // Relative to the smaller shape's radius: axes within this of the largest separation are
  // chosen face of A first, then face of B, then edge pair. 1e-4: far above rounding (1e-15),
  // so that exact ties (a cube on a cube) never go by rounding, and a face tilted by about
  // 1e-4 rad keeps its face manifold; the chosen axis's separation is then at most this
  // below the largest, under a tenth of a DEM's usual overlaps (1e-3 to 1e-2 of a radius).
  static constexpr double kAxisPreference = 1e-4;
  // Edge pairs whose directions are parallel within this sine are no axis (two parallel edges
  // make an edge of A - B, not a face): the error it allows is about this fraction of the
  // shapes' size.
  static constexpr double kParallelSine = 1e-8;

  double separation = 0.0;  // the largest over the axes tested (see above)
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // unit, world, from A to B
  PolyhedronContactKind kind = PolyhedronContactKind::kFaceA;
  // kFaceA: the reference face of A and the incident face of B; kFaceB: the incident face of
  // A and the reference face of B; kEdgeEdge: the edges of A and of B (into edges()). The
  // incident face is only looked for when the manifold is built (else it is 0).
  std::uint32_t feature_a = 0, feature_b = 0;
  int count = 0;  // manifold points; 0 when separation > margin
  // Look-ahead points (only with a ManifoldMotion, see there): points[count, count + ahead),
  // each with its own normal ahead_normal[t - count] (world, from A to B).
  static constexpr int kMaxAhead = 4;
  int ahead = 0;
  std::array<PolyhedronContactPoint, kMaxPoints + kMaxAhead> points{};
  std::array<Eigen::Vector3d, kMaxAhead> ahead_normal{};
  int total() const { return count + ahead; }
  const Eigen::Vector3d& normal_of(int t) const {
    return t < count ? normal : ahead_normal[t - count];
  }
};

// How the two bodies move over the coming step of length h (rigid velocity fields
// u_a(x) = v_a + w_a x (x - x_a), u_b likewise), for a caller whose margin holds more than 4
// points: a point's gap after the step is, to first order, gap + h n . (u_b(x) - u_a(x)) (n
// from A to B), and the 4-point reduction ranks the points by that predicted gap instead of
// the present one, so the points kept are those that will touch first. Contact dynamics
// needs it: its margin is the step's reach, a grain turning fast brings a far corner down
// within the step, and a rule that ranked by the present gaps dropped that corner, which then
// sank unconstrained (docs/contact-dynamics.md). The kept points' gaps are their present ones.
// h = 0 (the default): the present gaps rank them.
//
// With the motion, a pair's manifold also gets look-ahead points: one axis's features say
// nothing of the others that the step brings together (two crossed edges give one point, and
// the grains turning about it bring a corner down onto a face; a face manifold's incident face
// does not hold a corner of another face swinging down). For the face of A with the largest
// separation, every vertex of B over it (its foot inside the face), open (gap >= 0, within the
// margin) and closing within the step (predicted gap < 0), and likewise A's vertices over B's
// best face, become points with that face's normal, the ones closing soonest first, up to
// kMaxAhead, skipping any already in the manifold. Each is exact as a constraint: over the
// face, the face's plane is the other grain's surface.
struct ManifoldMotion {
  Eigen::Vector3d v_a = Eigen::Vector3d::Zero(), w_a = Eigen::Vector3d::Zero(),
                  x_a = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_b = Eigen::Vector3d::Zero(), w_b = Eigen::Vector3d::Zero(),
                  x_b = Eigen::Vector3d::Zero();
  double h = 0.0;
  // The gap at world point x, normal n (world, from A to B), after the step.
  double predicted(const Eigen::Vector3d& x, const Eigen::Vector3d& n, double gap) const {
    if (h == 0.0) return gap;
    const Eigen::Vector3d u = v_b + w_b.cross(x - x_b) - v_a - w_a.cross(x - x_a);
    return gap + h * n.dot(u);
  }
};

// Throws InputError when margin is negative or not finite. The quaternions must be unit.
PolyhedronContact polyhedron_contact(const ConvexPolyhedron& a, const Eigen::Vector3d& position_a,
                                     const Eigen::Quaterniond& orientation_a,
                                     const ConvexPolyhedron& b, const Eigen::Vector3d& position_b,
                                     const Eigen::Quaterniond& orientation_b, double margin = 0.0,
                                     const ManifoldMotion& motion = {});

}  // namespace sable
