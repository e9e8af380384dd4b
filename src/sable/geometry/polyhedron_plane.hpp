// The narrow phase between a convex polyhedral grain (geometry/convex_polyhedron.hpp), posed
// by a position x and a unit quaternion q, and a plane wall: how far apart they are and where
// they touch, in the PolyhedronContact of the pair narrow phase (geometry/
// polyhedron_contact.hpp), the wall standing as B.
//
// Why apart from the pair: a plane is a half-space, {y : n . (y - p) <= 0} its matter, the
// grain on the side n points to. Its one face axis is n, and no axis of the grain or edge pair
// can do better (every other direction sees the half-space unbounded), so the separating-axis
// test reduces to the grain's support along -n: the lowest vertex, exactly. No clipping
// either: the wall's face has no sides, and the grain's vertices within the margin are the
// manifold as they stand.
//
// The world vertices are R v + x, R = q.toRotationMatrix() (as the pair's points are turned),
// each vertex's gap n . (R v + x - p). The result:
//  - separation: the least gap over the vertices (the lowest vertex's height over the plane;
//    > 0 apart, < 0 overlapping by its magnitude), computed vertex by vertex, not bounded;
//  - normal = -n (from the grain, A, to the wall, B); kind = kFaceB (the wall's plane is the
//    reference face); feature_b = 0 (the plane's one face); feature_a = the grain's face whose
//    normal is lowest along n (the incident face, the first of equals), looked for only when
//    the manifold is built (else 0, as in the pair);
//  - when separation <= margin, the manifold: the vertices whose gap is <= margin, each a
//    point at its world vertex (on the grain, as the pair's points lie on the incident face)
//    with its gap. 4 or fewer are all kept; over 4, 4 by the pair's rule (geometry/
//    manifold_reduction.hpp: the deepest, the farthest from it in the plane, the largest
//    triangle, the most area added outside one side of it). The points come in the order of
//    the grain's vertices. A vertex on the plane gives 1 point, an edge 2, a face its corners
//    (reduced to 4).
// There is no axis to prefer and so no flicker of the normal; near a resting face the points
// follow the gaps: a face tilted by less than its overlap (or within the margin) keeps all its
// corners.
//
// Cost per call: one pass over the V vertices (a 3x3 turn and a dot product each), O(F) for
// the incident face when the manifold is built, and only when more than 4 vertices lie within
// the margin, 4 more passes (the reduction reads the vertices posed on the fly). No heap
// allocation, whatever V: nothing is buffered but the points returned.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "sable/geometry/convex_polyhedron.hpp"
#include "sable/geometry/polyhedron_contact.hpp"

namespace sable {

// How far a plane's normal may be from unit length: a normal off by more is a caller's bug.
inline constexpr double kPlaneNormalTolerance = 1e-9;

// Throws InputError when margin is negative or not finite, or plane_normal's length is not 1
// within kPlaneNormalTolerance. The quaternion must be unit.
PolyhedronContact polyhedron_plane_contact(const ConvexPolyhedron& a,
                                           const Eigen::Vector3d& position,
                                           const Eigen::Quaterniond& orientation,
                                           const Eigen::Vector3d& plane_point,
                                           const Eigen::Vector3d& plane_normal, double margin = 0.0,
                                           const ManifoldMotion& motion = {});

}  // namespace sable
