// Brute-force references for the narrow phase between convex polyhedra
// (tests/unit/test_polyhedron_contact.cpp), and the shapes and poses it draws (the plane's
// narrow phase, tests/unit/test_polyhedron_plane.cpp, draws them too). The references read
// the hull's triangles posed in the world and share no code with the narrow phase: no merged
// faces, no Gauss map, no clipping.
#pragma once

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>
#include <utility>
#include <vector>

#include "sable/geometry/convex_hull.hpp"
#include "sable/geometry/convex_polyhedron.hpp"
#include "sable/geometry/polyhedron_contact.hpp"

namespace sable::test {

using Vec = Eigen::Vector3d;
using Quat = Eigen::Quaterniond;
constexpr double kInf = std::numeric_limits<double>::infinity();

// Three draws in order (a constructor's arguments are evaluated in an unspecified order, which
// differs between compilers: the same seed would give other shapes under clang and gcc).
template <typename Draw>
Vec draw3(Draw&& draw) {
  Vec v;
  for (int k = 0; k < 3; ++k) v[k] = draw();
  return v;
}

// ---------------------------------------------------------------------------------------
// The references

struct Solid {
  std::vector<Vec> v;  // world
  std::vector<std::array<std::uint32_t, 3>> tris;
  std::vector<Vec> n;     // each triangle's outward unit normal
  std::vector<double> h;  // and its plane's offset, n . x = h
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;  // each once
  Eigen::ArrayXd x, y, z;    // v by coordinate, for projections in packets
  Vec centre = Vec::Zero();  // the vertices' mean: inside
  double inradius = kInf;    // the ball of this radius about the centre is inside
};

inline Solid posed(const ConvexHull& hull, const Vec& x, const Quat& q) {
  Solid s;
  for (const Vec& v : hull.vertices) s.v.push_back(q * v + x);
  s.tris = hull.triangles;
  for (const auto& t : s.tris) {
    const Vec n = (s.v[t[1]] - s.v[t[0]]).cross(s.v[t[2]] - s.v[t[0]]).normalized();
    s.n.push_back(n);
    s.h.push_back(n.dot(s.v[t[0]]));
    for (int k = 0; k < 3; ++k)
      if (t[k] < t[(k + 1) % 3]) s.edges.emplace_back(t[k], t[(k + 1) % 3]);
  }
  const auto n = static_cast<Eigen::Index>(s.v.size());
  s.x.resize(n);
  s.y.resize(n);
  s.z.resize(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    s.x[k] = s.v[k].x();
    s.y[k] = s.v[k].y();
    s.z[k] = s.v[k].z();
    s.centre += s.v[k] / static_cast<double>(n);
  }
  for (std::size_t t = 0; t < s.tris.size(); ++t)
    s.inradius = std::min(s.inradius, s.h[t] - s.n[t].dot(s.centre));
  return s;
}

// Separation along the unit axis n, from a to b: min over b of n . x - max over a of n . x.
inline double separation_along(const Solid& a, const Solid& b, const Vec& n) {
  double hi = -kInf, lo = kInf;
  for (const Vec& x : a.v) hi = std::max(hi, n.dot(x));
  for (const Vec& x : b.v) lo = std::min(lo, n.dot(x));
  return lo - hi;
}

// The unpruned separating-axis test: every triangle normal of either solid and every cross
// product of an edge of each (all pairs, no Gauss map), each both ways. For overlapping solids
// the largest separation is minus the penetration depth (each face of A - B is among the
// axes, and no axis can do better than the best face). `second` bounds the separation along
// every axis not parallel to the best one (1e-6): when it is below the best by more than
// `guard`, the best axis is the answer; when not, two axes may tie.
//
// Only to save time (10^5 pairs of ~2,900 edge pairs each), an axis is skipped when it
// provably stays below `floor` - `guard`, `floor` being a separation already known along some
// axis (a true value, never above the largest). Along a unit axis n, the separation is at
// most n . (w_B - w_A) for any point w_B of B and w_A of A: with w the centres c (the
// vertices' mean), each with a ball of radius r inside, both ways it is at most
// |n . (c_B - c_A)| - r_A - r_B, and for all the axes across one edge e_A of A (n normal to
// e_A) at most |(c_B - c_A) x e_A| / |e_A| - r_A - r_B; then with w among the two edges'
// ends and the vertices of each solid farthest each way along c_B - c_A. A skipped axis's
// bound stands in for its separation in `second`.
struct AxisAnswer {
  double best = -kInf, second = -kInf;
  Vec axis = Vec::Zero();
};

// The separation along n both ways (from A to B, then from B to A along -n).
inline void both_ways(const Solid& a, const Solid& b, const Vec& n,
                      std::vector<std::pair<double, Vec>>& all) {
  using Projection = Eigen::Array<double, Eigen::Dynamic, 1, Eigen::ColMajor, 64, 1>;
  const Projection pa = n.x() * a.x + n.y() * a.y + n.z() * a.z;
  const Projection pb = n.x() * b.x + n.y() * b.y + n.z() * b.z;
  all.emplace_back(pb.minCoeff() - pa.maxCoeff(), n);
  all.emplace_back(pa.minCoeff() - pb.maxCoeff(), -n);
}

// The witnesses' bound along n (both ways): the two edges' ends, the balls, the extremes.
inline double witness_bound(const Solid& a, const Solid& b, const Vec& n, const Vec& pa,
                            const Vec& pb, const std::array<Vec, 4>& far) {
  const double ca = n.dot(a.centre), cb = n.dot(b.centre);
  const double lo_a = std::min({n.dot(pa), ca - a.inradius, n.dot(far[0]), n.dot(far[1])});
  const double hi_a = std::max({n.dot(pa), ca + a.inradius, n.dot(far[0]), n.dot(far[1])});
  const double lo_b = std::min({n.dot(pb), cb - b.inradius, n.dot(far[2]), n.dot(far[3])});
  const double hi_b = std::max({n.dot(pb), cb + b.inradius, n.dot(far[2]), n.dot(far[3])});
  return std::max(lo_b - hi_a, lo_a - hi_b);
}

inline AxisAnswer unpruned_axes(const Solid& a, const Solid& b, double floor, double guard,
                                std::vector<std::pair<double, Vec>>& all) {
  all.clear();
  for (const Vec& n : a.n) both_ways(a, b, n, all);
  for (const Vec& n : b.n) both_ways(a, b, n, all);
  for (const auto& [s, n] : all) floor = std::max(floor, s);
  const Vec d = b.centre - a.centre;
  const double inner = a.inradius + b.inradius, cut = floor - guard;
  auto extreme = [&](const Solid& s, double sign) {
    std::size_t k = 0;
    for (std::size_t i = 1; i < s.v.size(); ++i)
      if (sign * d.dot(s.v[i]) > sign * d.dot(s.v[k])) k = i;
    return s.v[k];
  };
  const std::array<Vec, 4> far = {extreme(a, 1), extreme(a, -1), extreme(b, 1), extreme(b, -1)};
  double skipped = -kInf;
  for (const auto& [i, j] : a.edges) {
    const Vec ea = a.v[j] - a.v[i], g = d.cross(ea);  // n . d = e_B . g / |e_A x e_B|
    if (const double row = g.norm() / ea.norm() - inner; row < cut) {
      skipped = std::max(skipped, row);
      continue;
    }
    for (const auto& [k, l] : b.edges) {
      const Vec eb = b.v[l] - b.v[k];
      const Vec axis = ea.cross(eb);
      const double len2 = axis.squaredNorm(), along_d = std::abs(eb.dot(g));
      if (!(len2 > 0.0)) continue;
      // The ball's bound, |n . d| - inner < cut, first without the square root.
      if (cut + inner > 0.0 && along_d * along_d < (cut + inner) * (cut + inner) * len2) {
        skipped = std::max(skipped, along_d / std::sqrt(len2) - inner);
        continue;
      }
      const Vec n = axis / std::sqrt(len2);
      if (const double bound = witness_bound(a, b, n, a.v[i], b.v[k], far); bound < cut)
        skipped = std::max(skipped, bound);
      else
        both_ways(a, b, n, all);
    }
  }
  AxisAnswer r;
  for (const auto& [s, n] : all)
    if (s > r.best) {
      r.best = s;
      r.axis = n;
    }
  r.second = skipped;
  for (const auto& [s, n] : all)
    if ((n - r.axis).norm() > 1e-6) r.second = std::max(r.second, s);
  return r;
}

inline double point_segment(const Vec& x, const Vec& a, const Vec& b) {
  const double t = std::clamp((x - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
  return (x - a - t * (b - a)).norm();
}

// The minimum of |p0 + s u - q0 - t v| over the unit square: the lines' closest pair when it
// falls inside, else on the square's boundary, where it is an end's distance to the other
// segment.
inline double segment_segment(const Vec& p0, const Vec& p1, const Vec& q0, const Vec& q1) {
  double d = std::min({point_segment(p0, q0, q1), point_segment(p1, q0, q1),
                       point_segment(q0, p0, p1), point_segment(q1, p0, p1)});
  const Vec u = p1 - p0, v = q1 - q0, r = p0 - q0;
  const double uu = u.dot(u), vv = v.dot(v), uv = u.dot(v), den = uu * vv - uv * uv;
  if (den > 1e-14 * uu * vv) {
    const double s = (uv * v.dot(r) - vv * u.dot(r)) / den,
                 t = (uu * v.dot(r) - uv * u.dot(r)) / den;
    if (s >= 0 && s <= 1 && t >= 0 && t <= 1) d = std::min(d, (r + s * u - t * v).norm());
  }
  return d;
}

// x's projection on the triangle's plane inside the triangle (seen along n)?
inline bool over_triangle(const Vec& x, const Vec& a, const Vec& b, const Vec& c, const Vec& n) {
  return (b - a).cross(x - a).dot(n) >= 0 && (c - b).cross(x - b).dot(n) >= 0 &&
         (a - c).cross(x - c).dot(n) >= 0;
}

inline double point_triangle(const Solid& s, std::size_t t, const Vec& x) {
  const Vec &a = s.v[s.tris[t][0]], &b = s.v[s.tris[t][1]], &c = s.v[s.tris[t][2]];
  if (over_triangle(x, a, b, c, s.n[t])) return std::abs(s.n[t].dot(x) - s.h[t]);
  return std::min({point_segment(x, a, b), point_segment(x, b, c), point_segment(x, c, a)});
}

inline bool segment_crosses(const Solid& s, std::size_t t, const Vec& p, const Vec& q) {
  const double dp = s.n[t].dot(p) - s.h[t], dq = s.n[t].dot(q) - s.h[t];
  if (dp * dq > 0 || dp == dq) return false;
  const Vec x = p + (q - p) * (dp / (dp - dq));
  return over_triangle(x, s.v[s.tris[t][0]], s.v[s.tris[t][1]], s.v[s.tris[t][2]], s.n[t]);
}

inline bool inside(const Solid& s, const Vec& x) {
  for (std::size_t t = 0; t < s.tris.size(); ++t)
    if (s.n[t].dot(x) > s.h[t]) return false;
  return true;
}

// The Euclidean distance between the two solids: 0 when they meet (a vertex of one inside
// the other, or an edge of one through a triangle of the other: two convex solids that meet
// do one or the other), else the least vertex-triangle distance either way and edge-edge
// distance (the closest pair of two disjoint polytopes is one of those).
inline double exact_distance(const Solid& a, const Solid& b) {
  for (const Vec& x : a.v)
    if (inside(b, x)) return 0.0;
  for (const Vec& x : b.v)
    if (inside(a, x)) return 0.0;
  for (int side = 0; side < 2; ++side) {
    const Solid& s = side ? a : b;
    const Solid& o = side ? b : a;
    for (const auto& [i, j] : o.edges)
      for (std::size_t t = 0; t < s.tris.size(); ++t)
        if (segment_crosses(s, t, o.v[i], o.v[j])) return 0.0;
  }
  double d = kInf;
  for (std::size_t t = 0; t < b.tris.size(); ++t)
    for (const Vec& x : a.v) d = std::min(d, point_triangle(b, t, x));
  for (std::size_t t = 0; t < a.tris.size(); ++t)
    for (const Vec& x : b.v) d = std::min(d, point_triangle(a, t, x));
  for (const auto& [i, j] : a.edges)
    for (const auto& [k, l] : b.edges)
      d = std::min(d, segment_segment(a.v[i], a.v[j], b.v[k], b.v[l]));
  return d;
}

// ---------------------------------------------------------------------------------------
// Shapes built by hand

// The box [lo, hi]'s corners, corner k with bit 0, 1, 2 of k choosing hi's x, y, z.
inline std::vector<Vec> box_corners(const Vec& lo, const Vec& hi) {
  std::vector<Vec> v;
  for (int k = 0; k < 8; ++k)
    v.emplace_back(k & 1 ? hi.x() : lo.x(), k & 2 ? hi.y() : lo.y(), k & 4 ? hi.z() : lo.z());
  return v;
}
inline ConvexPolyhedron box(const Vec& lo, const Vec& hi) {
  return ConvexPolyhedron(convex_hull(box_corners(lo, hi), "box"), "box");
}
inline const Vec kHalf(0.5, 0.5, 0.5);  // the unit cube about the origin: box(-kHalf, kHalf)

// A regular tetrahedron about the origin, corner k at tetra_corners()[k].
inline std::vector<Vec> tetra_corners() {
  const double s = 0.5;
  return {Vec(s, s, s), Vec(s, -s, -s), Vec(-s, s, -s), Vec(-s, -s, s)};
}

// ---------------------------------------------------------------------------------------
// Random shapes and poses (std::mt19937_64, seeded: every run sees the same pairs).

struct Shape {
  ConvexHull hull;
  ConvexPolyhedron poly;
};

// 8 to 30 points on the unit sphere, or on an ellipsoid of semi-axes in [0.5, 1.5].
inline std::vector<Shape> random_shapes(int count, std::uint64_t seed) {
  std::mt19937_64 gen(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Shape> shapes;
  for (int s = 0; s < count; ++s) {
    const int n = 8 + static_cast<int>(gen() % 23);
    const Vec axes = s % 2 ? draw3([&] { return 0.5 + u(gen); }) : Vec::Ones();
    std::vector<Vec> points;
    for (int k = 0; k < n; ++k) {
      const double z = 2 * u(gen) - 1, phi = 2 * std::numbers::pi * u(gen);
      const double r = std::sqrt(1 - z * z);
      points.push_back(Vec(r * std::cos(phi), r * std::sin(phi), z).cwiseProduct(axes));
    }
    ConvexHull hull = convex_hull(points, "random shape");
    ConvexPolyhedron poly(hull, "random shape");
    shapes.push_back({std::move(hull), std::move(poly)});
  }
  return shapes;
}

inline Quat random_rotation(std::mt19937_64& gen) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double u1 = u(gen), a = 2 * std::numbers::pi * u(gen), b = 2 * std::numbers::pi * u(gen);
  return Quat(std::sqrt(u1) * std::cos(b), std::sqrt(1 - u1) * std::sin(a),
              std::sqrt(1 - u1) * std::cos(a), std::sqrt(u1) * std::sin(b));
}

inline Vec random_direction(std::mt19937_64& gen) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Vec v;
  do v = draw3([&] { return u(gen); });
  while (v.squaredNorm() > 1.0 || v.squaredNorm() < 1e-6);
  return v.normalized();
}

// A random pair: A anywhere in [-5, 5]^3 (far from the origin: the narrow phase must work
// relative to A), B at a centre distance of 0.25 to 1.05 times the sum of the radii (from
// deep overlap to apart).
struct Pair {
  const Shape* a;
  const Shape* b;
  Vec xa, xb;
  Quat qa, qb;
};
inline Pair random_pair(const std::vector<Shape>& shapes, std::mt19937_64& gen) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Pair p;
  p.a = &shapes[gen() % shapes.size()];
  p.b = &shapes[gen() % shapes.size()];
  p.qa = random_rotation(gen);
  p.qb = random_rotation(gen);
  p.xa = draw3([&] { return 10 * u(gen) - 5; });
  const double reach = p.a->poly.radius() + p.b->poly.radius();
  const Vec towards = random_direction(gen);
  p.xb = p.xa + towards * reach * (0.25 + 0.8 * u(gen));
  return p;
}

inline PolyhedronContact contact(const Pair& p, double margin) {
  return polyhedron_contact(p.a->poly, p.xa, p.qa, p.b->poly, p.xb, p.qb, margin);
}

}  // namespace sable::test
