// A mesh wall: a surface of triangles (3D) or segments (2D) that grains touch from either side.
//
// Contact with a mesh is contact with the surface it describes, resolved feature by feature:
// for a grain centre c, a feature (face, edge, vertex) gives a contact only where c lies in its
// region, where the feature holds the nearest surface point among its neighbours. Then:
//   - over a flat part, one contact whether c is above a face, a shared edge or a shared
//     vertex (a coplanar edge's region is a plane, and the faces' regions stop exactly there);
//   - beside a convex edge (facets at an angle), one contact, on the edge;
//   - in a concave corner, one contact per face (an edge there has no region of its own).
// The tests use the same numbers on both sides of every border between regions: face t
// needs its three edge functions e_tk(c) = (c - corner_k) . u_tk (u_tk the unit in-plane
// normal of edge k, into t) above `tol`; edge E needs e_tk(c) <= tol on each of its
// triangles and c's projection strictly inside E; vertex V needs c's projection on each of
// its edges at or beyond V. A region's border thus belongs to exactly one side whatever the
// round-off, so no grain gets two contacts, or none, on a flat mesh.
//
// A feature's contact is kept in the list entry of its owner, its element of lowest index
// (geometry/surface_mesh.hpp): each element entry answers for its face and the edges and
// vertices it owns, at most one of them at a time. The body frame's origin is the centre of
// the mesh's bounding box at the start, so that the rebuild test's bound on how far a turning
// mesh moved (angle times the largest vertex distance from the origin) is tight.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>

#include "sable/geometry/surface_mesh.hpp"
#include "sable/geometry/wall_feature.hpp"

namespace sable {

template <int D>
struct MeshShape {
  using Vec = typename Space<D>::Vec;
  using Matrix = typename Space<D>::Matrix;
  static constexpr const char* kName = "mesh";
  static constexpr bool kBounded = true;  // its elements are binned in the grains' cells

  MeshShape() = default;
  // The mesh as placed at the start (world coordinates); `origin` receives the body frame's
  // origin, the wall's starting point.
  MeshShape(SurfaceMesh<D> mesh, Vec& origin);

  std::uint32_t elements() const { return static_cast<std::uint32_t>(surface_->size()); }
  const SurfaceMesh<D>& surface() const { return *surface_; }
  // World positions of the vertices at the current pose.
  const std::vector<Vec>& vertices() const { return x_; }
  // The largest distance of a vertex from the body origin (m).
  double extent() const { return extent_; }

  // Broad phase: element e's bounding box, and the exact distance from x to element e.
  void element_box(std::uint32_t e, Vec& lo, Vec& hi) const;
  double element_distance(const Vec& x, std::uint32_t e) const;
  // The feature element e answers for at grain centre x (see the file comment).
  WallFeature<D> contact(const Vec& point, const Vec& x, std::uint32_t e) const;
  // The same, and where e answers for no feature at x, `margin`: how far x may move (less
  // round-off) before it may (0 where it answers for one).
  WallFeature<D> contact(const Vec& point, const Vec& x, std::uint32_t e, double& margin) const;
  // The nearest surface point over all elements (for checks outside the time loop: initial
  // overlaps, the analysis of a snapshot). Unsigned: n points from the surface to x.
  double distance(const Vec& point, const Vec& x, Vec& n) const;
  void place(const Matrix& r, const Vec& point);
  // Whether x lies inside the solid a closed surface bounds (its winding number about x,
  // summed from the elements' signed solid angles, 2D: angles, is not 0); false for an open
  // surface. For placing grains around a body, not in the time loop: O(elements).
  bool encloses(const Vec& x) const;
  bool closed() const { return closed_; }
  // Whether x lies within `margin` of the bounding box of the current vertices.
  bool near(const Vec& x, double margin) const {
    return ((x.array() >= lo_.array() - margin) && (x.array() <= hi_.array() + margin)).all();
  }

  // False when no point of element e lies within r of x: the cheap test that spares the
  // feature regions of the elements a grain only nears. A point p of the element within r of
  // x lies within s = sqrt(r^2 - h^2) of x's projection on the element's plane (h: x's height
  // above it); each side function of the element (in-plane unit normal u_k into it, so
  // u_k . p >= o_k on the element) then exceeds -s at x, u_k being normal to the plane. On a
  // fine flat mesh that keeps the one to six elements under a grain's contact cap; `tol_`
  // keeps it on the safe side of round-off.
  bool may_touch(const Vec& x, double r, std::uint32_t e) const {
    const double h = height(e, x);
    const double s2 = r * r - h * h;
    if (!(s2 > 0.0)) return false;
    const double s = -std::sqrt(s2) - tol_;
    for (int k = 0; k < D; ++k)
      if (edge_function(e, k, x) < s) return false;
    return true;
  }

  // What may_touch computes at x for element e: its height above the plane, then its D side
  // functions. Kept at a reference position x0, they bound the test at any x within d of x0
  // (may_touch_within): the plane and the sides are unit-normal, so each value moves by at
  // most d. `slack` covers the round-off of both evaluations and tol_.
  std::array<double, D + 1> reach_values(const Vec& x, std::uint32_t e) const {
    std::array<double, D + 1> v;
    v[0] = height(e, x);
    for (int k = 0; k < D; ++k) v[static_cast<std::size_t>(k) + 1] = edge_function(e, k, x);
    return v;
  }
  // False only where may_touch(x, r, e) is false for every x within d of the place the
  // values were taken at.
  static bool may_touch_within(const std::array<double, D + 1>& v, double d, double r,
                               double slack) {
    const double h = std::abs(v[0]) - d - slack;  // the least |height| within d
    if (h >= r) return false;
    const double h_min = std::max(0.0, h);
    const double s = std::sqrt(r * r - h_min * h_min) + 2.0 * slack;  // the widest cap
    for (std::size_t k = 1; k <= static_cast<std::size_t>(D); ++k)
      if (v[k] + d < -s) return false;
    return true;
  }
  // The regions' border width (1e-12 of the mesh's size).
  double tolerance() const { return tol_; }

  // The element's unit normal (3D: right-hand rule; 2D: the segment's direction turned +90
  // degrees) at the current pose.
  const Vec& element_normal(std::uint32_t e) const { return reach_[e].normal; }

 private:
  // From the packed record (Reach): c's signed height above element t's plane, and its side
  // function k (>= 0 on the element's side of its edge or end k). Every test of an element's
  // plane or sides goes through these two, so the bound, the cap test and the regions all see
  // the same numbers.
  double height(std::uint32_t t, const Vec& c) const {
    return reach_[t].normal.dot(c) - reach_[t].height;
  }
  double edge_function(std::uint32_t t, int k, const Vec& c) const {
    const Reach& q = reach_[t];
    return q.side[static_cast<std::size_t>(k)].dot(c) - q.offset[static_cast<std::size_t>(k)];
  }
  // The two vertices of edge `edge` (3D) or of segment `edge` (2D).
  std::array<std::uint32_t, 2> ends_of(std::uint32_t edge) const {
    if constexpr (D == 3) {
      return surface_->edges[edge];
    } else {
      return {surface_->elements[edge][0], surface_->elements[edge][1]};
    }
  }
  // The region tests; where they fail, `margin` is how far the failing test is past its border.
  bool edge_region(std::uint32_t edge, const Vec& c, WallFeature<D>& f, double& margin) const;
  // c's projection on `edge`, one of v's, lies beyond v: v's region excludes c.
  bool beside_vertex(std::uint32_t v, std::uint32_t edge, const Vec& c, double& margin) const;
  bool vertex_region(std::uint32_t v, const Vec& c, WallFeature<D>& f, double& margin) const;
  void point_feature(const Vec& c, const Vec& p, std::uint32_t e, WallFeature<D>& f) const;
  void derive();

  std::shared_ptr<const SurfaceMesh<D>> surface_;  // body frame; shared by copies
  std::vector<Vec> x_;                             // vertices at the current pose
  // Per element, what may_touch and the face test read, packed: the plane n . x = height, its
  // D sides (3D: edges; 2D: the segment's ends) u_k . x >= offset_k, u_k unit and in-plane.
  struct Reach {
    Vec normal;
    double height;
    std::array<Vec, D> side;
    std::array<double, D> offset;
  };
  std::vector<Reach> reach_;
  std::vector<Vec> dir_;  // unit direction of each edge (3D) or segment (2D), first to second
  double tol_ = 0.0;      // 1e-12 of the mesh's size: the regions' borders
  double extent_ = 0.0;
  bool closed_ = false;
  Vec lo_ = Vec::Zero(), hi_ = Vec::Zero();  // bounding box of the current vertices
};

}  // namespace sable
