#include "sable/geometry/convex_hull.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "sable/core/error.hpp"

namespace sable {

namespace {

using Points = std::vector<Eigen::Vector3d>;

// A face's plane: unit outward normal n, and n . x for its points.
struct Face {
  std::array<std::uint32_t, 3> v;
  Eigen::Vector3d n;
  double offset;
  bool alive;
};

Face make_face(const Points& p, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  const Eigen::Vector3d n = (p[b] - p[a]).cross(p[c] - p[a]).normalized();
  return {{a, b, c}, n, n.dot(p[a]), true};
}

double above(const Face& f, const Eigen::Vector3d& x) {
  return f.n.dot(x) - f.offset;
}

// The first tetrahedron: the lowest point in x, the farthest from it, the farthest from their
// line, the farthest from their plane (each the first of equals). `spans` is 1 when the points
// lie within eps of one line, 2 when within eps of one plane (no tetrahedron), else 3.
struct Start {
  std::array<std::uint32_t, 4> corners{};
  int spans = 3;
};

Start first_tetrahedron(const Points& p, double eps) {
  const auto n = static_cast<std::uint32_t>(p.size());
  auto farthest = [&](auto&& measure) {
    std::uint32_t best = 0;
    double far = -1.0;
    for (std::uint32_t k = 0; k < n; ++k)
      if (const double m = measure(p[k]); m > far) {
        far = m;
        best = k;
      }
    return std::pair{best, far};
  };
  // (clang 14 cannot capture structured bindings: plain names.)
  const std::uint32_t i0 = farthest([](const Eigen::Vector3d& x) { return -x.x(); }).first;
  const std::uint32_t i1 =
      farthest([&](const Eigen::Vector3d& x) { return (x - p[i0]).norm(); }).first;
  const Eigen::Vector3d axis = (p[i1] - p[i0]).normalized();
  const auto line =
      farthest([&](const Eigen::Vector3d& x) { return (x - p[i0]).cross(axis).norm(); });
  const std::uint32_t i2 = line.first;
  if (!(line.second > eps)) return {{}, 1};
  const Eigen::Vector3d normal = (p[i1] - p[i0]).cross(p[i2] - p[i0]).normalized();
  const auto plane =
      farthest([&](const Eigen::Vector3d& x) { return std::abs(normal.dot(x - p[i0])); });
  if (!(plane.second > eps)) return {{}, 2};
  return {{i0, i1, i2, plane.first}, 3};
}

// The hull's tolerance: 1e-12 of the points' extent (the largest side of their bounding box);
// NaN when a point is not finite.
double hull_tolerance(const Points& points) {
  Eigen::Vector3d lo = points[0], hi = points[0];
  for (const auto& x : points) {
    if (!x.allFinite()) return std::numeric_limits<double>::quiet_NaN();
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  return 1e-12 * (hi - lo).maxCoeff();
}

// Adds point k to the hull of `faces`: the faces it sees go, and each edge of their horizon
// (an edge of a seen face whose other face is not seen) joins k, keeping its direction so
// that the new faces wind outward as the old ones did.
void add_point(const Points& p, std::uint32_t k, double eps, std::vector<Face>& faces,
               std::vector<std::pair<std::uint32_t, std::uint32_t>>& edges) {
  edges.clear();
  for (Face& f : faces) {
    if (!f.alive || !(above(f, p[k]) > eps)) continue;
    f.alive = false;
    edges.emplace_back(f.v[0], f.v[1]);
    edges.emplace_back(f.v[1], f.v[2]);
    edges.emplace_back(f.v[2], f.v[0]);
  }
  if (edges.empty()) return;  // inside (or within the tolerance of the surface)
  std::vector<std::pair<std::uint32_t, std::uint32_t>> sorted = edges;
  std::sort(sorted.begin(), sorted.end());
  for (const auto& [u, v] : edges)
    if (!std::binary_search(sorted.begin(), sorted.end(), std::pair{v, u}))
      faces.push_back(make_face(p, u, v, k));
}

}  // namespace

bool spans_volume(const std::vector<Eigen::Vector3d>& points) {
  if (points.size() < 4) return false;
  const double eps = hull_tolerance(points);
  return !std::isnan(eps) && first_tetrahedron(points, eps).spans == 3;
}

ConvexHull convex_hull(const std::vector<Eigen::Vector3d>& points, const char* what) {
  if (points.size() < 4)
    throw InputError(
        fmt::format("{}: {} points, expected at least 4 (a solid)", what, points.size()));
  const double eps = hull_tolerance(points);
  if (std::isnan(eps)) throw InputError(fmt::format("{}: a point is not finite", what));
  const Start start = first_tetrahedron(points, eps);
  if (start.spans < 3)
    throw InputError(fmt::format("{}: its {} points lie {}: no volume", what, points.size(),
                                 start.spans == 1 ? "on one line" : "in one plane"));
  const auto& t = start.corners;
  std::vector<Face> faces;
  // Each face of the tetrahedron, turned so that the fourth corner lies below it.
  const std::array<std::array<int, 4>, 4> sides = {
      {{0, 1, 2, 3}, {0, 3, 1, 2}, {0, 2, 3, 1}, {1, 3, 2, 0}}};
  for (const auto& s : sides) {
    Face f = make_face(points, t[s[0]], t[s[1]], t[s[2]]);
    if (above(f, points[t[s[3]]]) > 0.0) f = make_face(points, t[s[0]], t[s[2]], t[s[1]]);
    faces.push_back(f);
  }
  // Farthest from the tetrahedron's centre first (ties by index): a box's corners come before
  // the points on its edges and faces, which then lie within the tolerance of the surface.
  const Eigen::Vector3d centre = (points[t[0]] + points[t[1]] + points[t[2]] + points[t[3]]) / 4.0;
  std::vector<std::uint32_t> order;
  for (std::uint32_t k = 0; k < points.size(); ++k)
    if (std::find(t.begin(), t.end(), k) == t.end()) order.push_back(k);
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return (points[a] - centre).squaredNorm() > (points[b] - centre).squaredNorm();
  });
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
  for (std::uint32_t k : order) add_point(points, k, eps, faces, edges);
  // The vertices the surviving faces use, in input order.
  std::vector<char> used(points.size(), 0);
  for (const Face& f : faces)
    if (f.alive)
      for (std::uint32_t v : f.v) used[v] = 1;
  ConvexHull hull;
  std::vector<std::uint32_t> index(points.size(), 0);
  for (std::uint32_t k = 0; k < points.size(); ++k)
    if (used[k]) {
      index[k] = static_cast<std::uint32_t>(hull.vertices.size());
      hull.vertices.push_back(points[k]);
    }
  for (const Face& f : faces)
    if (f.alive) hull.triangles.push_back({index[f.v[0]], index[f.v[1]], index[f.v[2]]});
  return hull;
}

}  // namespace sable
