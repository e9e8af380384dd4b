// The convex hull of a set of points in 3D, as a closed triangle surface wound outward (what
// geometry/polyhedron_mass.hpp takes): the shape of a convex polyhedral grain made from points
// drawn on a sphere or an ellipsoid, or from a vertex list.
//
// Incremental construction: a first tetrahedron from four extreme points, then each further
// point, farthest from the tetrahedron's centre first; a point outside the current hull
// (farther than the tolerance beyond the plane of some face) removes the faces it sees and
// joins their horizon. Points within the tolerance of the hull count as inside, and a box's
// corners come before the points on its edges and faces: the hull of a cube's corners, edge
// midpoints and face centres is the cube's 8 corners and 12 triangles. A coplanar point that
// comes before the corners around it stays a (flat) vertex: the surface, and its mass
// properties, are the same. O(n^2) in the number of hull vertices: meant for grain shapes (tens to
// a few hundred points), not for point clouds. The result depends only on the points and their
// order (no randomness, no hashing).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

namespace sable {

struct ConvexHull {
  std::vector<Eigen::Vector3d> vertices;                // the extreme points, in input order
  std::vector<std::array<std::uint32_t, 3>> triangles;  // into `vertices`, wound outward
};

// Throws InputError, `what` naming the shape, when the points span no volume (fewer than 4,
// or all within the tolerance of one plane). The tolerance is 1e-12 of the points' extent.
ConvexHull convex_hull(const std::vector<Eigen::Vector3d>& points,
                       const char* what = "convex hull");

// Whether convex_hull(points) has a solid to return: at least 4 finite points, not all within
// its tolerance of one plane. (A generator of random shapes draws again when it is false.)
bool spans_volume(const std::vector<Eigen::Vector3d>& points);

}  // namespace sable
