#include "sable/geometry/mesh_wall.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sable {

template <int D>
MeshShape<D>::MeshShape(SurfaceMesh<D> mesh, Vec& origin) {
  Vec lo = mesh.vertices.front(), hi = lo;
  for (const Vec& v : mesh.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  origin = 0.5 * (lo + hi);
  for (Vec& v : mesh.vertices) {
    v -= origin;
    extent_ = std::max(extent_, v.norm());
  }
  tol_ = 1e-12 * std::max((hi - lo).norm(), std::numeric_limits<double>::min());
  if constexpr (D == 3) {
    closed_ = std::all_of(mesh.edge_elements.begin(), mesh.edge_elements.end(),
                          [](const auto& t) { return t[1] != kNoElement; });
  } else {
    closed_ = true;
    for (std::size_t v = 0; v + 1 < mesh.vertex_edge_begin.size(); ++v)
      closed_ = closed_ && mesh.vertex_edge_begin[v + 1] - mesh.vertex_edge_begin[v] == 2;
  }
  surface_ = std::make_shared<const SurfaceMesh<D>>(std::move(mesh));
  place(Matrix::Identity(), origin);
}

template <int D>
void MeshShape<D>::place(const Matrix& r, const Vec& point) {
  const auto& s = *surface_;
  x_.resize(s.vertices.size());
  for (std::size_t v = 0; v < x_.size(); ++v) x_[v] = r * s.vertices[v] + point;
  lo_ = hi_ = x_.front();
  for (const Vec& x : x_) {
    lo_ = lo_.cwiseMin(x);
    hi_ = hi_.cwiseMax(x);
  }
  derive();
}

// Each element's plane and sides (reach_), and the edges' directions at the current pose.
// 3D: side k is edge k's in-plane unit normal into the triangle (edge k joins corners k and
// k+1); 2D: side 0 faces along the segment from its first end, side 1 against it from its
// second.
template <int D>
void MeshShape<D>::derive() {
  const auto& s = *surface_;
  reach_.resize(s.size());
  if constexpr (D == 3) {
    dir_.resize(s.edges.size());
    for (std::size_t e = 0; e < s.edges.size(); ++e)
      dir_[e] = (x_[s.edges[e][1]] - x_[s.edges[e][0]]).normalized();
  } else {
    dir_.resize(s.size());
  }
  for (std::size_t t = 0; t < s.size(); ++t) {
    const auto& c = s.elements[t];
    Reach& q = reach_[t];
    if constexpr (D == 3) {
      q.normal = (x_[c[1]] - x_[c[0]]).cross(x_[c[2]] - x_[c[0]]).normalized();
      for (std::size_t k = 0; k < 3; ++k)
        q.side[k] = q.normal.cross(x_[c[(k + 1) % 3]] - x_[c[k]]).normalized();
    } else {
      dir_[t] = (x_[c[1]] - x_[c[0]]).normalized();
      q.normal = Vec(-dir_[t].y(), dir_[t].x());
      q.side = {dir_[t], Vec(-dir_[t])};
    }
    q.height = q.normal.dot(x_[c[0]]);
    for (std::size_t k = 0; k < static_cast<std::size_t>(D); ++k)
      q.offset[k] = q.side[k].dot(x_[c[k]]);
  }
}

template <int D>
void MeshShape<D>::element_box(std::uint32_t e, Vec& lo, Vec& hi) const {
  const auto& c = surface_->elements[e];
  lo = hi = x_[c[0]];
  for (int k = 1; k < D; ++k) {
    lo = lo.cwiseMin(x_[c[static_cast<std::size_t>(k)]]);
    hi = hi.cwiseMax(x_[c[static_cast<std::size_t>(k)]]);
  }
}

// The closest point of a segment a-b to x.
template <class Vec>
static Vec closest_on_segment(const Vec& a, const Vec& b, const Vec& x) {
  const Vec ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((x - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return a + t * ab;
}

template <int D>
double MeshShape<D>::element_distance(const Vec& x, std::uint32_t e) const {
  const auto& c = surface_->elements[e];
  if constexpr (D == 2) {
    return (x - closest_on_segment(x_[c[0]], x_[c[1]], x)).norm();
  } else {
    // Inside the triangle's prism: the distance to its plane; else to its nearest edge.
    bool inside = true;
    for (int k = 0; k < 3; ++k) inside = inside && edge_function(e, k, x) >= 0.0;
    if (inside) return std::abs((x - x_[c[0]]).dot(reach_[e].normal));
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < 3; ++k)
      best = std::min(best, (x - closest_on_segment(x_[c[k]], x_[c[(k + 1) % 3]], x)).norm());
    return best;
  }
}

// The contact with the surface point p of element e, nearest to c: its normal points from p
// to c (the element's own normal when c lies on p).
template <int D>
void MeshShape<D>::point_feature(const Vec& c, const Vec& p, std::uint32_t e,
                                 WallFeature<D>& f) const {
  const Vec d = c - p;
  f.dist = d.norm();
  f.n = f.dist > 0.0 ? Vec(d / f.dist) : reach_[e].normal;
}

// Edge `edge` (3D) or segment `edge` (2D) holds c's nearest point: c projects strictly inside
// it, and (3D) not into either of its triangles.
template <int D>
bool MeshShape<D>::edge_region(std::uint32_t edge, const Vec& c, WallFeature<D>& f,
                               double& margin) const {
  const auto& s = *surface_;
  if constexpr (D == 3) {  // first the triangles' sides: on a flat mesh, the one that fails
    for (std::uint32_t t : s.edge_elements[edge]) {
      if (t == kNoElement) continue;
      const auto& te = s.element_edges[t];
      const int k = te[0] == edge ? 0 : (te[1] == edge ? 1 : 2);
      const double side = edge_function(t, k, c);
      if (side > tol_) {
        margin = side - tol_;
        return false;
      }
    }
  }
  const auto ends = ends_of(edge);
  const double alpha = (c - x_[ends[0]]).dot(dir_[edge]);
  const double beta = (c - x_[ends[1]]).dot(dir_[edge]);
  if (!(alpha > tol_)) {
    margin = tol_ - alpha;
    return false;
  }
  if (!(beta < -tol_)) {
    margin = beta + tol_;
    return false;
  }
  std::uint32_t owner = edge;
  if constexpr (D == 3) {
    owner = s.edge_owner[edge];
    f.feature = static_cast<std::uint32_t>(s.size()) + edge;
  } else {
    f.feature = edge;
  }
  point_feature(c, x_[ends[0]] + alpha * dir_[edge], owner, f);
  return true;
}

template <int D>
bool MeshShape<D>::beside_vertex(std::uint32_t v, std::uint32_t edge, const Vec& c,
                                 double& margin) const {
  const auto ends = ends_of(edge);
  const double along = (c - x_[v]).dot(dir_[edge]);  // from v, along the edge's direction
  margin = ends[0] == v ? along - tol_ : -tol_ - along;
  return margin > 0.0;
}

// Vertex v holds c's nearest point: c's projection on each of its edges lies at or beyond v.
template <int D>
bool MeshShape<D>::vertex_region(std::uint32_t v, const Vec& c, WallFeature<D>& f,
                                 double& margin) const {
  const auto& s = *surface_;
  for (std::uint32_t k = s.vertex_edge_begin[v]; k < s.vertex_edge_begin[v + 1]; ++k)
    if (beside_vertex(v, s.vertex_edges[k], c, margin)) return false;
  const auto before = static_cast<std::uint32_t>(s.size() + s.edges.size());
  f.feature = before + v;
  point_feature(c, x_[v], s.vertex_owner[v], f);
  return true;
}

template <int D>
WallFeature<D> MeshShape<D>::contact(const Vec& point, const Vec& c, std::uint32_t e) const {
  double margin = 0.0;
  return contact(point, c, e, margin);
}

// Each feature's failing test gives its margin (how far its value is past its border, every
// value moving by at most |dc| as c moves by dc); the element's margin is their least.
template <int D>
WallFeature<D> MeshShape<D>::contact(const Vec&, const Vec& c, std::uint32_t e,
                                     double& margin) const {
  const auto& s = *surface_;
  const auto& corner = s.elements[e];
  WallFeature<D> f;
  margin = std::numeric_limits<double>::infinity();
  double m = 0.0;
  if constexpr (D == 3) {
    const std::array<double, 3> side{edge_function(e, 0, c), edge_function(e, 1, c),
                                     edge_function(e, 2, c)};
    if (side[0] > tol_ && side[1] > tol_ && side[2] > tol_) {
      const double h = height(e, c);
      f.dist = std::abs(h);
      f.n = h >= 0.0 ? reach_[e].normal : Vec(-reach_[e].normal);
      f.feature = e;
      margin = 0.0;
      return f;
    }
    margin = tol_ - std::min({side[0], side[1], side[2]});
    // Edge k's region needs side k at or below tol_ (edge_region tests the very same number).
    for (std::size_t k = 0; k < 3; ++k) {
      const std::uint32_t edge = s.element_edges[e][k];
      if (s.edge_owner[edge] != e) continue;
      if (side[k] > tol_) {
        margin = std::min(margin, side[k] - tol_);
      } else if (edge_region(edge, c, f, m)) {
        margin = 0.0;
        return f;
      } else {
        margin = std::min(margin, m);
      }
    }
  } else {
    if (edge_region(e, c, f, m)) {
      margin = 0.0;
      return f;
    }
    margin = m;
  }
  for (std::size_t k = 0; k < static_cast<std::size_t>(D); ++k) {
    const std::uint32_t v = corner[k];
    if (s.vertex_owner[v] != e) continue;
    bool beside = false;
    if constexpr (D == 3) {  // first the element's own two edges at v (the same tests)
      const auto& te = s.element_edges[e];
      beside = beside_vertex(v, te[k], c, m) || beside_vertex(v, te[(k + 2) % 3], c, m);
    }
    if (!beside && vertex_region(v, c, f, m)) {
      margin = 0.0;
      return f;
    }
    margin = std::min(margin, m);
  }
  f.active = false;
  return f;
}

template <int D>
double MeshShape<D>::distance(const Vec&, const Vec& x, Vec& n) const {
  double best = std::numeric_limits<double>::infinity();
  n = Vec::Zero();
  for (std::uint32_t e = 0; e < elements(); ++e) {
    const WallFeature<D> f = contact(x, x, e);
    if (f.active && f.dist < best) {
      best = f.dist;
      n = f.n;
    }
  }
  return best;
}

template <int D>
bool MeshShape<D>::encloses(const Vec& x) const {
  if (!closed_) return false;
  double total = 0.0;
  for (const auto& e : surface_->elements) {
    if constexpr (D == 3) {
      // Solid angle of the triangle seen from x (Van Oosterom and Strackee, 1983).
      const Vec a = x_[e[0]] - x, b = x_[e[1]] - x, c = x_[e[2]] - x;
      const double la = a.norm(), lb = b.norm(), lc = c.norm();
      const double num = a.dot(b.cross(c));
      const double den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
      total += 2.0 * std::atan2(num, den);
    } else {
      const Vec a = x_[e[0]] - x, b = x_[e[1]] - x;
      total += std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b));
    }
  }
  // 4 pi (2D: 2 pi) inside, 0 outside; the sign follows the winding.
  return std::abs(total) > (D == 3 ? 2.0 : 1.0) * 3.14159265358979323846;
}

template struct MeshShape<2>;
template struct MeshShape<3>;

}  // namespace sable
