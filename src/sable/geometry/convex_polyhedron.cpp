#include "sable/geometry/convex_polyhedron.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <tuple>

#include "sable/core/error.hpp"

namespace sable {

namespace {

using Triangles = std::vector<std::array<std::uint32_t, 3>>;
constexpr std::uint32_t kNone = ~std::uint32_t{0};

// For each triangle t and each of its sides k (the edge t[k] -> t[k + 1]), the triangle on
// the other side: the one holding the reversed edge. A closed surface wound consistently
// holds every directed edge once and its reverse once.
std::vector<std::uint32_t> find_twins(const Triangles& tris, std::size_t n_vertices,
                                      const char* what) {
  std::vector<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>> directed;
  for (std::uint32_t t = 0; t < tris.size(); ++t)
    for (std::uint32_t k = 0; k < 3; ++k) {
      const std::uint32_t u = tris[t][k], v = tris[t][(k + 1) % 3];
      if (u >= n_vertices || v >= n_vertices || u == v)
        throw InputError(fmt::format("{}: triangle {} names vertices {}, {}, {} of {}", what, t,
                                     tris[t][0], tris[t][1], tris[t][2], n_vertices));
      directed.emplace_back(u, v, t);
    }
  std::sort(directed.begin(), directed.end());
  std::vector<std::uint32_t> twin(3 * tris.size(), kNone);
  for (std::size_t i = 0; i < directed.size(); ++i) {
    const auto [u, v, t] = directed[i];
    if (i + 1 < directed.size() && std::get<0>(directed[i + 1]) == u &&
        std::get<1>(directed[i + 1]) == v)
      throw InputError(
          fmt::format("{}: the edge {}-{} bounds two triangles the same way: not a "
                      "closed surface wound outward",
                      what, u, v));
    const auto it =
        std::lower_bound(directed.begin(), directed.end(), std::tuple{v, u, std::uint32_t{0}});
    if (it == directed.end() || std::get<0>(*it) != v || std::get<1>(*it) != u)
      throw InputError(
          fmt::format("{}: the edge {}-{} has no twin: not a closed surface", what, u, v));
    const std::uint32_t k = tris[t][0] == u ? 0 : tris[t][1] == u ? 1 : 2;
    twin[3 * t + k] = std::get<2>(*it);
  }
  return twin;
}

// Which face each triangle belongs to. Seeds in order of decreasing area (the largest
// triangle's normal is the most accurate; ties by index); a face grows from its seed across
// shared edges to every triangle whose three corners lie within `tol` of the seed's plane.
// Measuring against the seed's plane, not a neighbour's, keeps a long chain of slight folds
// from merging into one bent face.
std::vector<std::uint32_t> merge_triangles(const std::vector<Eigen::Vector3d>& p,
                                           const Triangles& tris,
                                           const std::vector<std::uint32_t>& twin, double tol,
                                           const char* what) {
  const auto n = static_cast<std::uint32_t>(tris.size());
  std::vector<Eigen::Vector3d> cross(n);
  std::vector<std::uint32_t> order(n);
  for (std::uint32_t t = 0; t < n; ++t) {
    cross[t] = (p[tris[t][1]] - p[tris[t][0]]).cross(p[tris[t][2]] - p[tris[t][0]]);
    order[t] = t;
  }
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return cross[a].squaredNorm() > cross[b].squaredNorm();
  });
  std::vector<std::uint32_t> face(n, kNone), stack;
  std::uint32_t faces = 0;
  for (std::uint32_t seed : order) {
    if (face[seed] != kNone) continue;
    if (!(cross[seed].norm() > 0.0))
      throw InputError(fmt::format("{}: triangle {} has no area", what, seed));
    const Eigen::Vector3d normal = cross[seed].normalized();
    const double offset = normal.dot(p[tris[seed][0]]);
    face[seed] = faces;
    stack.assign(1, seed);
    while (!stack.empty()) {
      const std::uint32_t t = stack.back();
      stack.pop_back();
      for (std::uint32_t k = 0; k < 3; ++k) {
        const std::uint32_t u = twin[3 * t + k];
        if (face[u] != kNone) continue;
        const bool flat = std::all_of(tris[u].begin(), tris[u].end(), [&](std::uint32_t v) {
          return std::abs(normal.dot(p[v]) - offset) <= tol;
        });
        if (!flat) continue;
        face[u] = faces;
        stack.push_back(u);
      }
    }
    ++faces;
  }
  return face;
}

// Each face's boundary as one loop of hull vertices, counterclockwise seen from outside: the
// sides of its triangles whose twin lies in another face, followed head to tail. Throws when
// they do not make exactly one loop (a face that is not one polygon).
std::vector<std::vector<std::uint32_t>> face_loops(const Triangles& tris,
                                                   const std::vector<std::uint32_t>& twin,
                                                   const std::vector<std::uint32_t>& face,
                                                   std::uint32_t faces, const char* what) {
  std::vector<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>> sides;  // face, u, v
  for (std::uint32_t t = 0; t < tris.size(); ++t)
    for (std::uint32_t k = 0; k < 3; ++k)
      if (face[twin[3 * t + k]] != face[t])
        sides.emplace_back(face[t], tris[t][k], tris[t][(k + 1) % 3]);
  std::sort(sides.begin(), sides.end());
  std::vector<std::vector<std::uint32_t>> loops(faces);
  auto first = sides.begin();
  for (std::uint32_t f = 0; f < faces; ++f) {
    auto last = first;
    while (last != sides.end() && std::get<0>(*last) == f) ++last;
    const auto count = static_cast<std::size_t>(last - first);
    if (count == 0)
      throw InputError(fmt::format("{}: face {} has no boundary: not a solid", what, f));
    std::vector<std::uint32_t>& loop = loops[f];
    std::uint32_t at = std::get<1>(*first);
    do {
      const auto it = std::lower_bound(first, last, std::tuple{f, at, std::uint32_t{0}});
      const bool one =
          it != last && std::get<1>(*it) == at && (it + 1 == last || std::get<1>(*(it + 1)) != at);
      if (!one || loop.size() >= count)
        throw InputError(fmt::format(
            "{}: face {} (triangles within the merge tolerance of one plane) is not one polygon",
            what, f));
      loop.push_back(at);
      at = std::get<2>(*it);
    } while (at != loop.front());
    if (loop.size() != count)
      throw InputError(fmt::format("{}: face {} has more than one boundary loop", what, f));
    first = last;
  }
  return loops;
}

// Newell's normal of a closed loop: twice its vector area, whatever its shape; about the
// first corner, so that a loop far from the origin loses no digits.
Eigen::Vector3d loop_normal(const std::vector<Eigen::Vector3d>& p,
                            std::span<const std::uint32_t> loop) {
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  for (std::size_t i = 1; i + 1 < loop.size(); ++i)
    n += (p[loop[i]] - p[loop[0]]).cross(p[loop[i + 1]] - p[loop[0]]);
  return n;
}

}  // namespace

ConvexPolyhedron::ConvexPolyhedron(const ConvexHull& hull, const char* what) {
  const std::vector<Eigen::Vector3d>& p = hull.vertices;
  if (p.size() < 4 || hull.triangles.size() < 4)
    throw InputError(
        fmt::format("{}: {} vertices and {} triangles, expected a closed solid "
                    "(at least 4 of each)",
                    what, p.size(), hull.triangles.size()));
  Eigen::Vector3d lo = p[0], hi = p[0];
  for (const auto& x : p) {
    if (!x.allFinite()) throw InputError(fmt::format("{}: a vertex is not finite", what));
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  tolerance_ = kMergeTolerance * (hi - lo).maxCoeff();
  const std::vector<std::uint32_t> twin = find_twins(hull.triangles, p.size(), what);
  const std::vector<std::uint32_t> face_of =
      merge_triangles(p, hull.triangles, twin, tolerance_, what);
  const auto faces = 1 + *std::max_element(face_of.begin(), face_of.end());
  const auto loops = face_loops(hull.triangles, twin, face_of, faces, what);
  // A corner joins three faces or more; a hull vertex on one face, or on an edge between two
  // faces, is flat and goes.
  std::vector<std::uint32_t> joins(p.size(), 0), index(p.size(), kNone);
  for (const auto& loop : loops)
    for (std::uint32_t v : loop) ++joins[v];
  for (std::uint32_t v = 0; v < p.size(); ++v)
    if (joins[v] >= 3) {
      index[v] = static_cast<std::uint32_t>(vertices_.size());
      vertices_.push_back(p[v]);
      radius_ = std::max(radius_, p[v].norm());
    }
  start_.push_back(0);
  for (std::uint32_t f = 0; f < faces; ++f) {
    for (std::uint32_t v : loops[f])
      if (index[v] != kNone) corners_.push_back(index[v]);
    start_.push_back(static_cast<std::uint32_t>(corners_.size()));
    const std::size_t n = start_[f + 1] - start_[f];
    if (n < 3 || n > kMaxFaceCorners)
      throw InputError(
          fmt::format("{}: face {} has {} corners, expected 3 to {}", what, f, n, kMaxFaceCorners));
    const Eigen::Vector3d normal = loop_normal(vertices_, face(f));
    if (!(normal.norm() > 0.0)) throw InputError(fmt::format("{}: face {} has no area", what, f));
    normals_.push_back(normal.normalized());
  }
  check_convex(what);
  build_edges(what);
}

// Every face's corners lie on its plane, and every vertex below it, within a few merge
// tolerances (a best-fit plane through triangles merged within one tolerance of a seed's
// plane is off by about two); the offset is then the highest vertex, so that the plane
// supports the solid exactly.
void ConvexPolyhedron::check_convex(const char* what) {
  for (std::size_t f = 0; f < normals_.size(); ++f) {
    const Eigen::Vector3d& n = normals_[f];
    constexpr double kInf = std::numeric_limits<double>::infinity();
    double low = kInf, high = -kInf, top = -kInf;
    for (std::uint32_t v : face(f)) {
      low = std::min(low, n.dot(vertices_[v]));
      high = std::max(high, n.dot(vertices_[v]));
    }
    for (const auto& x : vertices_) top = std::max(top, n.dot(x));
    if (high - low > 4 * tolerance_ || top - high > 4 * tolerance_)
      throw InputError(fmt::format(
          "{}: not convex: a vertex stands {:.3g} above the plane of face {} (its corners "
          "{:.3g} apart), more than 4 merge tolerances ({:.3g})",
          what, top - high, f, high - low, 4 * tolerance_));
    offsets_.push_back(top);
  }
}

// The edges from the faces' loops: each side of a loop once in each direction, in two faces.
void ConvexPolyhedron::build_edges(const char* what) {
  std::vector<std::tuple<std::uint32_t, std::uint32_t, bool, std::uint32_t>> sides;
  for (std::uint32_t f = 0; f < normals_.size(); ++f) {
    const auto loop = face(f);
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const std::uint32_t a = loop[i], b = loop[(i + 1) % loop.size()];
      sides.emplace_back(std::min(a, b), std::max(a, b), a > b, f);
    }
  }
  std::sort(sides.begin(), sides.end());
  for (std::size_t i = 0; i < sides.size(); i += 2) {
    const auto& [v0, v1, back0, f0] = sides[i];
    const bool paired = i + 1 < sides.size() && std::get<0>(sides[i + 1]) == v0 &&
                        std::get<1>(sides[i + 1]) == v1 && !back0 && std::get<2>(sides[i + 1]);
    if (!paired)
      throw InputError(
          fmt::format("{}: the edge {}-{} of the merged faces has no twin", what, v0, v1));
    edges_.push_back({v0, v1, f0, std::get<3>(sides[i + 1])});
  }
  // Euler's formula for a sphere-like solid: a last check that the faces close up.
  const auto euler = static_cast<long>(vertices_.size()) - static_cast<long>(edges_.size()) +
                     static_cast<long>(normals_.size());
  if (euler != 2)
    throw InputError(fmt::format("{}: {} corners, {} edges, {} faces: V - E + F = {}, not 2", what,
                                 vertices_.size(), edges_.size(), normals_.size(), euler));
}

}  // namespace sable
