// A convex polyhedron as contact detection sees it: its corners, its faces as polygons (a
// cube has 6 square faces, not the 12 triangles of its hull), each face's outward unit normal
// and plane offset, and its edges, each with the two faces it joins. The faces' normals are
// the polyhedron's Gauss map (its points on the unit sphere), the edges its arcs: the narrow
// phase (geometry/polyhedron_contact.hpp) tests the separating axes of two such shapes on it.
//
// Built from a ConvexHull (geometry/convex_hull.hpp), in the body frame of the grain: the
// hull's coplanar triangles merge into one face, and the hull's flat vertices (on a face, or on
// an edge between two corners) are dropped, so that every corner joins at least three faces
// and every edge is a true edge of the solid. Coplanar means within the merge tolerance,
// kMergeTolerance times the shape's extent (the largest side of its bounding box): far above
// the rounding of the coordinates and of the hull's own 1e-12, far below any real fold of a
// grain's surface. Faces that meet at a smaller fold than that are one face, its normal the
// best fit through its corners (Newell's), its plane through the highest corner along it (a
// hull vertex dropped as flat may stand up to the tolerance above it).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "sable/geometry/convex_hull.hpp"

namespace sable {

class ConvexPolyhedron {
 public:
  // Relative to the shape's extent: triangles whose corners lie within this of one plane
  // merge into one face.
  static constexpr double kMergeTolerance = 1e-9;
  // The most corners one face may have: the narrow phase clips a face in a fixed buffer of
  // twice this many points (clipping a convex polygon by a half-plane adds at most one).
  static constexpr std::size_t kMaxFaceCorners = 64;

  struct Edge {
    std::uint32_t v0, v1;        // its corners, v0 < v1
    std::uint32_t face0, face1;  // face0's loop runs v0 -> v1, face1's v1 -> v0
  };

  // Throws InputError, `what` naming the shape, when the hull is not a closed convex surface
  // (fewer than 4 vertices, an index out of range, an edge without its twin, a vertex above a
  // face's plane by more than 4 merge tolerances, a point not finite), or a face has more
  // than kMaxFaceCorners corners.
  explicit ConvexPolyhedron(const ConvexHull& hull, const char* what = "convex polyhedron");

  // The corners, in the order of the hull's vertices.
  const std::vector<Eigen::Vector3d>& vertices() const { return vertices_; }
  std::size_t face_count() const { return normals_.size(); }
  // Face f's corners, counterclockwise seen from outside (along -normal).
  std::span<const std::uint32_t> face(std::size_t f) const {
    return {corners_.data() + start_[f], corners_.data() + start_[f + 1]};
  }
  // Outward unit normals n_f; offsets h_f = max over the vertices of n_f . v, so that every
  // vertex lies on or below every face's plane {x : n_f . x = h_f}.
  const std::vector<Eigen::Vector3d>& normals() const { return normals_; }
  const std::vector<double>& offsets() const { return offsets_; }
  // Each edge once, sorted by (v0, v1).
  const std::vector<Edge>& edges() const { return edges_; }
  // The largest distance of a corner from the body frame's origin.
  double radius() const { return radius_; }
  // The merge tolerance in length: kMergeTolerance times the extent.
  double tolerance() const { return tolerance_; }

 private:
  void check_convex(const char* what);
  void build_edges(const char* what);

  std::vector<Eigen::Vector3d> vertices_;
  std::vector<std::uint32_t> start_;    // face f's corners: corners_[start_[f], start_[f + 1])
  std::vector<std::uint32_t> corners_;  // into vertices_
  std::vector<Eigen::Vector3d> normals_;
  std::vector<double> offsets_;
  std::vector<Edge> edges_;
  double radius_ = 0.0;
  double tolerance_ = 0.0;
};

}  // namespace sable
