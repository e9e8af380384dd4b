#include "sable/geometry/polyhedron_contact.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <utility>

#include "sable/core/error.hpp"
#include "sable/geometry/manifold_reduction.hpp"

namespace sable {

namespace {

using Vec = Eigen::Vector3d;
using Mat = Eigen::Matrix3d;
using Kind = PolyhedronContactKind;
constexpr double kInf = std::numeric_limits<double>::infinity();

// Everything is computed in A's body frame, where B's points are x = R x_B + t; the results
// turn to the world at the end. Working relative to A keeps the digits of two grains far from
// the origin: t is the difference of their positions, taken first.
struct Relative {
  Mat R;
  Vec t;
  Vec at(const Vec& x_b) const { return R * x_b + t; }
};

// A's pose in the world and the bodies' motion: what the manifold's ranking needs to predict
// the points' gaps (clipping works in A's frame).
struct Posed {
  const Mat& R;
  const Vec& x;
  const ManifoldMotion& motion;
};

struct FaceQuery {
  double separation = -kInf;
  std::uint32_t face = 0;
};

struct EdgeQuery {
  double separation = -kInf;
  std::uint32_t edge_a = 0, edge_b = 0;
  Vec normal = Vec::Zero();  // A's frame, from A to B
};

// A convex polygon with a fixed capacity: clipping never allocates.
template <std::size_t N>
struct Polygon {
  std::array<Vec, N> p;
  std::size_t n = 0;
  void push(const Vec& x) {
    // A convex polygon gains at most one corner per clip; only a polygon made non-convex by
    // rounding could gain more, and then the extra (nearly collinear) points may go.
    if (n < N) p[n++] = x;
  }
};
constexpr std::size_t kClip = 2 * ConvexPolyhedron::kMaxFaceCorners;

// The index of the vertex lowest along m (the first of equals), and its height.
std::pair<std::uint32_t, double> lowest(const std::vector<Vec>& v, const Vec& m) {
  std::uint32_t best = 0;
  double low = kInf;
  for (std::uint32_t k = 0; k < v.size(); ++k)
    if (const double h = m.dot(v[k]); h < low) {
      low = h;
      best = k;
    }
  return {best, low};
}

// A quick look for a separating axis before the full test: GJK (Gilbert, Johnson & Keerthi
// 1988) on the difference set C = B - A, in A's frame, which holds the origin exactly when the
// shapes meet. The separation along a unit axis n is min over C of n.c = B's lowest vertex
// minus A's highest; GJK walks a point v of C to C's point closest to the origin, each step
// adding C's lowest point w along v to a simplex and taking the simplex's point closest to the
// origin (C. Ericson, Real-Time Collision Detection, 2005, sections 5.1.5-5.1.6). Every axis
// v / |v| gives a lower bound of the distance, so one that shows the shapes apart by more than
// the margin settles the pair exactly, whatever the simplex's rounding: the simplex only
// chooses axes. Most of a dense packing's candidates are pairs whose bounding spheres overlap
// without the hulls touching; GJK costs them O(V_A + V_B) a step, a few steps, where the full
// test costs O(F V + E_A E_B) (the edge pairs: 900 for two 12-corner hulls).
struct Simplex {
  std::array<Vec, 4> p = {Vec::Zero(), Vec::Zero(), Vec::Zero(), Vec::Zero()};
  int n = 0;
  void set(std::initializer_list<Vec> points) {
    n = 0;
    for (const Vec& x : points) p[n++] = x;
  }
};

// The point of triangle abc closest to the origin; s becomes the feature holding it.
Vec closest_on_triangle(Simplex& s, const Vec a, const Vec b, const Vec c) {
  const Vec ab = b - a, ac = c - a;
  const double d1 = -ab.dot(a), d2 = -ac.dot(a);
  if (d1 <= 0.0 && d2 <= 0.0) return s.set({a}), a;
  const double d3 = -ab.dot(b), d4 = -ac.dot(b);
  if (d3 >= 0.0 && d4 <= d3) return s.set({b}), b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return s.set({a, b}), Vec(a + d1 / (d1 - d3) * ab);
  const double d5 = -ab.dot(c), d6 = -ac.dot(c);
  if (d6 >= 0.0 && d5 <= d6) return s.set({c}), c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return s.set({a, c}), Vec(a + d2 / (d2 - d6) * ac);
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0)
    return s.set({b, c}), Vec(b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b));
  const double inv = 1.0 / (va + vb + vc);
  s.set({a, b, c});
  return a + ab * (vb * inv) + ac * (vc * inv);
}

// The simplex's point closest to the origin, the simplex reduced to the feature holding it;
// false when the origin is inside a tetrahedron (the shapes meet, or nearly: the full test
// decides).
bool closest_on_simplex(Simplex& s, Vec& v) {
  const std::array<Vec, 4> p = s.p;
  switch (s.n) {
    case 1:
      v = p[0];
      return true;
    case 2: {
      const Vec ab = p[1] - p[0];
      const double t = -p[0].dot(ab), d = ab.squaredNorm();
      if (t <= 0.0) return s.set({p[0]}), v = p[0], true;
      if (t >= d) return s.set({p[1]}), v = p[1], true;
      v = p[0] + (t / d) * ab;
      return true;
    }
    case 3:
      v = closest_on_triangle(s, p[0], p[1], p[2]);
      return true;
    default: {
      // Each face whose plane has the origin and the opposite corner on opposite sides.
      constexpr int kFaces[4][4] = {{0, 1, 2, 3}, {0, 2, 3, 1}, {0, 3, 1, 2}, {1, 3, 2, 0}};
      double best = kInf;
      Simplex kept;
      for (const auto& f : kFaces) {
        const Vec n = (p[f[1]] - p[f[0]]).cross(p[f[2]] - p[f[0]]);
        if (!(-p[f[0]].dot(n) * (p[f[3]] - p[f[0]]).dot(n) < 0.0)) continue;
        Simplex face;
        const Vec q = closest_on_triangle(face, p[f[0]], p[f[1]], p[f[2]]);
        if (q.squaredNorm() < best) {
          best = q.squaredNorm();
          kept = face;
          v = q;
        }
      }
      s = kept;
      return best < kInf;
    }
  }
}

struct QuickAxis {
  double separation = -kInf;
  Vec axis = Vec::UnitZ();  // A's frame, from A to B
};

QuickAxis quick_axis(const ConvexPolyhedron& a, const ConvexPolyhedron& b, const Relative& rel,
                     double margin) {
  constexpr int kSteps = 16;  // GJK ends in a few on hulls of tens of corners
  QuickAxis best;
  Simplex s;
  Vec v = rel.t;  // the centroids' difference: a point of C
  for (int step = 0; step < kSteps; ++step) {
    const double length = v.norm();
    if (!(length > 1e-12 * (a.radius() + b.radius()))) break;  // at the origin: they meet
    const Vec n = v / length;
    const auto [top_a, minus_high_a] = lowest(a.vertices(), -n);
    const auto [low_b, low_b_local] = lowest(b.vertices(), rel.R.transpose() * n);
    const double sep = low_b_local + n.dot(rel.t) + minus_high_a;
    if (sep > best.separation) best = {sep, n};
    // Apart beyond the margin; or v within a millionth of C's closest point (sep <= the
    // distance <= |v|), which is then within the margin: the full test decides.
    if (sep > margin || length - sep <= 1e-6 * length) break;
    s.p[s.n++] = rel.at(b.vertices()[low_b]) - a.vertices()[top_a];
    if (!closest_on_simplex(s, v)) break;
  }
  return best;
}

// Face axes of A: along n_f, B's lowest vertex against A's plane h_f. B's vertices are
// measured in B's frame along R^T n_f, so they need not be turned one by one.
FaceQuery query_faces_a(const ConvexPolyhedron& a, const ConvexPolyhedron& b, const Relative& rel) {
  FaceQuery q;
  for (std::uint32_t f = 0; f < a.face_count(); ++f) {
    const Vec& n = a.normals()[f];
    const double s =
        lowest(b.vertices(), rel.R.transpose() * n).second + n.dot(rel.t) - a.offsets()[f];
    if (s > q.separation) q = {s, f};
  }
  return q;
}

// Face axes of B: along B's normal m = R n_g (A's frame), A's lowest vertex against B's plane,
// which in A's frame is at h_g + m . t.
FaceQuery query_faces_b(const ConvexPolyhedron& a, const ConvexPolyhedron& b, const Relative& rel) {
  FaceQuery q;
  for (std::uint32_t g = 0; g < b.face_count(); ++g) {
    const Vec m = rel.R * b.normals()[g];
    const double s = lowest(a.vertices(), m).second - m.dot(rel.t) - b.offsets()[g];
    if (s > q.separation) q = {s, g};
  }
  return q;
}

// Edge pairs whose Gauss-map arcs cross (the header gives the test): A's arc from a to b,
// B's turned over, from c = -R n_0 to d = -R n_1. The planes of the arcs need no cross
// product: a x b is a positive multiple of A's edge v1 - v0 (face0's loop runs v0 -> v1, so
// face0's interior lies on the left of the edge seen from outside, and a turns towards b
// away from it), and c x d = R (n_0 x n_1) one of B's edge turned into A's frame; the test
// reads only signs. The axis n = e_A x e_B is turned to point out of A at its edge
// (n . (a + b) > 0: n lies on A's arc), so that the edge of A is A's highest point along n and
// the edge of B is B's lowest: the separation is n . (p_B - p_A) for any point of each edge.
EdgeQuery query_edges(const ConvexPolyhedron& a, const ConvexPolyhedron& b, const Relative& rel) {
  EdgeQuery q;
  const double sine2 = PolyhedronContact::kParallelSine * PolyhedronContact::kParallelSine;
  for (std::uint32_t j = 0; j < b.edges().size(); ++j) {
    const ConvexPolyhedron::Edge& eb = b.edges()[j];
    const Vec c = -(rel.R * b.normals()[eb.face0]), d = -(rel.R * b.normals()[eb.face1]);
    const Vec pb = rel.at(b.vertices()[eb.v0]);
    const Vec dir_b = rel.R * (b.vertices()[eb.v1] - b.vertices()[eb.v0]);  // along c x d
    for (std::uint32_t i = 0; i < a.edges().size(); ++i) {
      const ConvexPolyhedron::Edge& ea = a.edges()[i];
      const Vec dir_a = a.vertices()[ea.v1] - a.vertices()[ea.v0];  // along a x b
      const Vec& na = a.normals()[ea.face0];
      const Vec& nb = a.normals()[ea.face1];
      const double cu = c.dot(dir_a), du = d.dot(dir_a), aw = na.dot(dir_b), bw = nb.dot(dir_b);
      // All three signs, then one branch: few pairs pass, so it is well predicted, where a
      // branch per test would miss half the time.
      if (!((cu * du < 0.0) & (aw * bw < 0.0) & (cu * bw > 0.0))) continue;
      Vec n = dir_a.cross(dir_b);
      if (!(n.squaredNorm() > sine2 * dir_a.squaredNorm() * dir_b.squaredNorm())) continue;
      n.normalize();
      if (n.dot(na + nb) < 0.0) n = -n;
      const double s = n.dot(pb - a.vertices()[ea.v0]);
      if (s > q.separation) q = {s, i, j, n};
    }
  }
  return q;
}

// Sutherland-Hodgman against one side plane {x : s . x <= o}. A corner on the plane is kept
// and makes no crossing, so no point comes out twice.
void clip(const Polygon<kClip>& in, const Vec& s, double o, Polygon<kClip>& out) {
  out.n = 0;
  if (in.n == 0) return;
  Vec prev = in.p[in.n - 1];
  double dp = s.dot(prev) - o;
  for (std::size_t k = 0; k < in.n; ++k) {
    const Vec& cur = in.p[k];
    const double dc = s.dot(cur) - o;
    if ((dp < 0.0 && dc > 0.0) || (dp > 0.0 && dc < 0.0))
      out.push(prev + (cur - prev) * (dp / (dp - dc)));
    if (dc <= 0.0) out.push(cur);
    prev = cur;
    dp = dc;
  }
}

// At most 4 of `count` points (positions x, ranked by `rank`: their gaps, or those predicted
// after the step), by the rule of the header (geometry/manifold_reduction.hpp, shared with the
// plane's manifold): all of 4 or fewer; else the deepest, the farthest from it, the largest
// triangle, the most area added outside one side of it. Returns how many, their indices in
// `keep`.
int reduce(const Polygon<kClip>& x, const Vec& n, const std::array<double, kClip>& rank,
           std::array<std::size_t, 4>& keep) {
  if (x.n <= 4) {
    for (std::size_t k = 0; k < x.n; ++k) keep[k] = k;
    return static_cast<int>(x.n);
  }
  return detail::reduce_to_four(
      x.n, [&](std::size_t k) -> const Vec& { return x.p[k]; },
      [&](std::size_t k) { return rank[k]; }, [](std::size_t) { return true; }, n, keep);
}

// The incident face for a reference normal m (in the incident shape's frame, pointing out of
// the reference shape): among the faces round the incident shape's lowest vertex along m (its
// deepest point), the one whose normal is lowest along m. The face most anti-parallel to m
// over the whole shape need not hold that vertex (a sharp corner poking into the reference
// face, with a wide face elsewhere nearly facing it), and clipping such a face would leave
// the deepest point out of the manifold: the corner would sink unconstrained.
std::uint32_t incident_face(const ConvexPolyhedron& s, const Vec& m) {
  const std::uint32_t deepest = lowest(s.vertices(), m).first;
  std::uint32_t best = 0;
  double best_height = std::numeric_limits<double>::infinity();
  for (std::size_t f = 0; f < s.face_count(); ++f) {
    const auto corners = s.face(f);
    if (std::find(corners.begin(), corners.end(), deepest) == corners.end()) continue;
    if (const double h = s.normals()[f].dot(m); h < best_height) {
      best_height = h;
      best = static_cast<std::uint32_t>(f);
    }
  }
  return best;
}

// The incident face clipped by the side planes of the reference face (`ref`, its corners
// counterclockwise about n), then the points within `margin` of the reference plane
// n . x = h, at most 4 of them, into c (A's frame). `poly` holds the incident face on entry;
// `spare` is the other buffer of the ping-pong.
void clip_and_keep(const Polygon<ConvexPolyhedron::kMaxFaceCorners>& ref, const Vec& n, double h,
                   double margin, const Posed& posed, Polygon<kClip>& poly, Polygon<kClip>& spare,
                   PolyhedronContact& c) {
  Polygon<kClip>* in = &poly;
  Polygon<kClip>* out = &spare;
  for (std::size_t i = 0; i < ref.n; ++i) {
    // The side's outward normal: the edge direction x n points away from the face.
    const Vec side = (ref.p[(i + 1) % ref.n] - ref.p[i]).cross(n);
    clip(*in, side, side.dot(ref.p[i]), *out);
    std::swap(in, out);
  }
  std::array<double, kClip> gap;
  std::size_t kept = 0;
  for (std::size_t k = 0; k < in->n; ++k)
    if (const double g = n.dot(in->p[k]) - h; g <= margin) {
      in->p[kept] = in->p[k];
      gap[kept++] = g;
    }
  in->n = kept;
  // The reduction's ranking: the gaps after the step when the caller gave the motion.
  std::array<double, kClip> rank = gap;
  if (kept > 4 && posed.motion.h != 0.0) {
    const Vec n_world = posed.R * n;
    for (std::size_t k = 0; k < kept; ++k)
      rank[k] = posed.motion.predicted(posed.R * in->p[k] + posed.x, n_world, gap[k]);
  }
  std::array<std::size_t, 4> keep{};
  c.count = reduce(*in, n, rank, keep);
  for (int k = 0; k < c.count; ++k) c.points[k] = {in->p[keep[k]], gap[keep[k]]};
}

// Reference face of A, incident face of B (incident_face()).
void face_a_manifold(const ConvexPolyhedron& a, const ConvexPolyhedron& b, const Relative& rel,
                     const FaceQuery& fa, double margin, const Posed& posed, PolyhedronContact& c) {
  const Vec& n = a.normals()[fa.face];
  const Vec m = rel.R.transpose() * n;  // n in B's frame
  c.feature_b = incident_face(b, m);
  Polygon<ConvexPolyhedron::kMaxFaceCorners> ref;
  for (std::uint32_t v : a.face(fa.face)) ref.push(a.vertices()[v]);
  Polygon<kClip> poly, spare;
  for (std::uint32_t v : b.face(c.feature_b)) poly.push(rel.at(b.vertices()[v]));
  clip_and_keep(ref, n, a.offsets()[fa.face], margin, posed, poly, spare, c);
  if (c.count == 0) {
    const std::uint32_t k = lowest(b.vertices(), m).first;
    c.points[0] = {rel.at(b.vertices()[k]), fa.separation};
    c.count = 1;
  }
}

// Reference face of B (its plane in A's frame), incident face of A.
void face_b_manifold(const ConvexPolyhedron& a, const ConvexPolyhedron& b, const Relative& rel,
                     const FaceQuery& fb, double margin, const Posed& posed, PolyhedronContact& c) {
  const Vec n = rel.R * b.normals()[fb.face];
  const double h = b.offsets()[fb.face] + n.dot(rel.t);
  c.feature_a = incident_face(a, n);
  Polygon<ConvexPolyhedron::kMaxFaceCorners> ref;
  for (std::uint32_t v : b.face(fb.face)) ref.push(rel.at(b.vertices()[v]));
  Polygon<kClip> poly, spare;
  for (std::uint32_t v : a.face(c.feature_a)) poly.push(a.vertices()[v]);
  clip_and_keep(ref, n, h, margin, posed, poly, spare, c);
  if (c.count == 0) {
    const std::uint32_t k = lowest(a.vertices(), n).first;
    c.points[0] = {a.vertices()[k], fb.separation};
    c.count = 1;
  }
}

// The midpoint of the closest points of the segments p0 + s u and q0 + t v, s and t in
// [0, 1]. Setting the derivatives of |p0 - q0 + s u - t v|^2 to zero gives the lines' closest
// pair; a t outside [0, 1] is clamped, and s then re-solved for that end (and clamped).
Vec midway(const Vec& p0, const Vec& u, const Vec& q0, const Vec& v) {
  const Vec r = p0 - q0;
  const double uu = u.dot(u), vv = v.dot(v), uv = u.dot(v), ru = r.dot(u), rv = r.dot(v);
  const double den = uu * vv - uv * uv;  // > 0: the edges are not parallel
  double s = den > 0.0 ? std::clamp((uv * rv - ru * vv) / den, 0.0, 1.0) : 0.0;
  double t = (rv + s * uv) / vv;
  if (t < 0.0) {
    t = 0.0;
    s = std::clamp(-ru / uu, 0.0, 1.0);
  } else if (t > 1.0) {
    t = 1.0;
    s = std::clamp((uv - ru) / uu, 0.0, 1.0);
  }
  return 0.5 * (p0 + s * u + q0 + t * v);
}

void edge_manifold(const ConvexPolyhedron& a, const ConvexPolyhedron& b, const Relative& rel,
                   const EdgeQuery& e, PolyhedronContact& c) {
  const ConvexPolyhedron::Edge& ea = a.edges()[e.edge_a];
  const ConvexPolyhedron::Edge& eb = b.edges()[e.edge_b];
  const Vec p0 = a.vertices()[ea.v0], q0 = rel.at(b.vertices()[eb.v0]);
  const Vec mid = midway(p0, a.vertices()[ea.v1] - p0, q0, rel.at(b.vertices()[eb.v1]) - q0);
  c.points[0] = {mid, e.separation};
  c.count = 1;
}

// The look-ahead points (ManifoldMotion in the header), gathered in A's frame: the closing
// vertices over one reference face, kept soonest-closing first in a fixed array.
class LookAhead {
 public:
  LookAhead(const Posed& posed, const PolyhedronContact& c, double margin, double scale)
      : posed_(posed), c_(c), margin_(margin), same_(1e-9 * scale) {}

  // The vertices `v` (A's frame) over the face with corners `corners` (A's frame,
  // counterclockwise about n), n its outward normal, h its plane's offset; the contact's
  // normal from A to B is `towards_b` (n for a face of A, -n for a face of B).
  template <typename Vertices, typename Corners>
  void scan(const Vertices& v, std::size_t nv, const Corners& corners, std::size_t nc, const Vec& n,
            double h, const Vec& towards_b) {
    const Vec n_world = posed_.R * towards_b;
    for (std::size_t k = 0; k < nv; ++k) {
      const Vec y = v(k);
      const double gap = n.dot(y) - h;
      if (!(gap >= 0.0 && gap <= margin_)) continue;
      bool over = true;
      for (std::size_t i = 0; i < nc && over; ++i) {
        const Vec p0 = corners(i);
        over = (corners((i + 1) % nc) - p0).cross(n).dot(y - p0) <= 0.0;
      }
      if (!over) continue;
      const double soon = posed_.motion.predicted(posed_.R * y + posed_.x, n_world, gap);
      if (!(soon < 0.0) || known(y)) continue;
      insert({y, gap}, towards_b, soon);
    }
  }

  // Appends the kept points after the manifold's.
  void finish(PolyhedronContact& c) const {
    for (int t = 0; t < count_; ++t) {
      c.points[c.count + t] = point_[t];
      c.ahead_normal[t] = normal_[t];
    }
    c.ahead = count_;
  }

 private:
  bool known(const Vec& y) const {
    for (int t = 0; t < c_.count; ++t)
      if ((c_.points[t].position - y).norm() <= same_) return true;
    for (int t = 0; t < count_; ++t)
      if ((point_[t].position - y).norm() <= same_) return true;
    return false;
  }
  // Sorted by `soon`, the first of equals first; the latest beyond kMaxAhead drops out.
  void insert(const PolyhedronContactPoint& q, const Vec& n, double soon) {
    int at = count_;
    while (at > 0 && soon_[at - 1] > soon) --at;
    if (at >= PolyhedronContact::kMaxAhead) return;
    for (int t = std::min(count_, PolyhedronContact::kMaxAhead - 1); t > at; --t) {
      point_[t] = point_[t - 1];
      normal_[t] = normal_[t - 1];
      soon_[t] = soon_[t - 1];
    }
    point_[at] = q;
    normal_[at] = n;
    soon_[at] = soon;
    count_ = std::min(count_ + 1, PolyhedronContact::kMaxAhead);
  }

  const Posed& posed_;
  const PolyhedronContact& c_;
  double margin_, same_;
  int count_ = 0;
  std::array<PolyhedronContactPoint, PolyhedronContact::kMaxAhead> point_{};
  std::array<Vec, PolyhedronContact::kMaxAhead> normal_{};
  std::array<double, PolyhedronContact::kMaxAhead> soon_{};
};

void look_ahead(const ConvexPolyhedron& a, const ConvexPolyhedron& b, const Relative& rel,
                const FaceQuery& fa, const FaceQuery& fb, double margin, const Posed& posed,
                PolyhedronContact& c) {
  LookAhead ahead(posed, c, margin, std::min(a.radius(), b.radius()));
  const auto face_a = a.face(fa.face);
  ahead.scan([&](std::size_t k) { return rel.at(b.vertices()[k]); }, b.vertices().size(),
             [&](std::size_t i) { return a.vertices()[face_a[i]]; }, face_a.size(),
             a.normals()[fa.face], a.offsets()[fa.face], a.normals()[fa.face]);
  const auto face_b = b.face(fb.face);
  const Vec n = rel.R * b.normals()[fb.face];
  ahead.scan([&](std::size_t k) { return a.vertices()[k]; }, a.vertices().size(),
             [&](std::size_t i) { return rel.at(b.vertices()[face_b[i]]); }, face_b.size(), n,
             b.offsets()[fb.face] + n.dot(rel.t), Vec(-n));
  ahead.finish(c);
}

}  // namespace

PolyhedronContact polyhedron_contact(const ConvexPolyhedron& a, const Eigen::Vector3d& position_a,
                                     const Eigen::Quaterniond& orientation_a,
                                     const ConvexPolyhedron& b, const Eigen::Vector3d& position_b,
                                     const Eigen::Quaterniond& orientation_b, double margin,
                                     const ManifoldMotion& motion) {
  if (!(margin >= 0.0) || !std::isfinite(margin))
    throw InputError(fmt::format("polyhedron contact: margin {}, expected >= 0", margin));
  const Mat ra = orientation_a.toRotationMatrix();
  const Relative rel{ra.transpose() * orientation_b.toRotationMatrix(),
                     ra.transpose() * (position_b - position_a)};
  PolyhedronContact c;
  if (const QuickAxis q = quick_axis(a, b, rel, margin); q.separation > margin) {
    c.separation = q.separation;
    c.normal = ra * q.axis;
    return c;
  }
  // Shapes apart by more than the margin need no more axes than one that shows it (the
  // separation is then a lower bound of their distance, as the header allows): the face
  // axes, O(F V) each, are tested before the edge pairs, O(E_A E_B), which dominate the cost.
  const FaceQuery fa = query_faces_a(a, b, rel);
  if (fa.separation > margin) {
    c.separation = fa.separation;
    c.feature_a = fa.face;
    c.normal = ra * a.normals()[fa.face];
    return c;
  }
  const FaceQuery fb = query_faces_b(a, b, rel);
  if (fb.separation > margin) {
    c.separation = fb.separation;
    c.kind = Kind::kFaceB;
    c.feature_b = fb.face;
    c.normal = -(ra * (rel.R * b.normals()[fb.face]));
    return c;
  }
  const EdgeQuery e = query_edges(a, b, rel);
  c.separation = std::max({fa.separation, fb.separation, e.separation});
  const double slack = PolyhedronContact::kAxisPreference * std::min(a.radius(), b.radius());
  Vec n;  // A's frame, from A to B
  if (fa.separation >= c.separation - slack) {
    c.kind = Kind::kFaceA;
    c.feature_a = fa.face;
    n = a.normals()[fa.face];
  } else if (fb.separation >= c.separation - slack) {
    c.kind = Kind::kFaceB;
    c.feature_b = fb.face;
    n = -(rel.R * b.normals()[fb.face]);
  } else {
    c.kind = Kind::kEdgeEdge;
    c.feature_a = e.edge_a;
    c.feature_b = e.edge_b;
    n = e.normal;
  }
  c.normal = ra * n;
  if (c.separation > margin) return c;
  switch (c.kind) {
    case Kind::kFaceA:
      face_a_manifold(a, b, rel, fa, margin, {ra, position_a, motion}, c);
      break;
    case Kind::kFaceB:
      face_b_manifold(a, b, rel, fb, margin, {ra, position_a, motion}, c);
      break;
    case Kind::kEdgeEdge:
      edge_manifold(a, b, rel, e, c);
      break;
  }
  if (motion.h != 0.0) look_ahead(a, b, rel, fa, fb, margin, {ra, position_a, motion}, c);
  for (int k = 0; k < c.total(); ++k) c.points[k].position = ra * c.points[k].position + position_a;
  for (int k = 0; k < c.ahead; ++k) c.ahead_normal[k] = ra * c.ahead_normal[k];
  return c;
}

}  // namespace sable
