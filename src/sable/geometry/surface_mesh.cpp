// Surface meshes: welding, the checks that refuse a mesh no contact could use, the topology,
// and the built-in shapes (cylinder, circle, box).
//
// Thresholds, in one place:
// - A triangle is degenerate when its area is at most 1e-12 times its longest edge squared
//   (its height over the longest edge below 2e-12 of that edge): the shape of a sliver, not
//   its size, so that a mesh in millimetres and the same mesh in metres are judged alike.
// - A segment is degenerate when its length is at most 1e-12 times the larger coordinate (in
//   absolute value) of its corners: two corners a few round-offs apart.
// - Welding joins vertices whose coordinates have the same bits, counting -0 and +0 as equal
//   (they are the same point, and a mirrored exporter writes both).
#include "sable/geometry/surface_mesh.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <map>
#include <numbers>
#include <unordered_map>

#include "sable/core/error.hpp"

namespace sable {

namespace {

constexpr double kDegenerate = 1e-12;
// The built-in shapes refuse more elements than this: a mesh wall of 10^8 triangles is a
// typing error, not a wall (and would need gigabytes).
constexpr std::uint64_t kMaxBuiltIn = 100'000'000;

template <int D>
constexpr const char* element_word() {
  return D == 3 ? "triangle" : "segment";
}

template <int D>
std::string point_text(const typename Space<D>::Vec& p) {
  if constexpr (D == 3) {
    return fmt::format("({}, {}, {})", p.x(), p.y(), p.z());
  } else {
    return fmt::format("({}, {})", p.x(), p.y());
  }
}

// The start of every refusal of element `e` (counted from 0) of `source`.
template <int D>
std::string where(const std::string& source, std::size_t e) {
  return fmt::format("{}: {} {} (counted from 1)", clip(source), element_word<D>(), e + 1);
}

// The weld key of a vertex: its coordinates' bits, -0 taken as +0 (adding +0 turns -0 into
// +0 and leaves every other value, NaN included, as it is).
template <int D>
std::array<std::uint64_t, D> weld_key(const typename Space<D>::Vec& p) {
  std::array<std::uint64_t, D> key{};
  for (int i = 0; i < D; ++i) key[i] = std::bit_cast<std::uint64_t>(p[i] + 0.0);
  return key;
}

template <int D>
bool all_finite(const typename Space<D>::Vec& p) {
  for (int i = 0; i < D; ++i)
    if (!std::isfinite(p[i])) return false;
  return true;
}

// Checks the corner indices and coordinates of every element, in order, then welds: the
// mesh's vertices become the distinct used ones, in the order of their first occurrence in
// `vertices`, and the elements are remapped to them.
template <int D>
void weld(SurfaceMesh<D>& mesh, const std::vector<typename Space<D>::Vec>& vertices,
          const std::string& source) {
  const std::size_t nv = vertices.size();
  for (std::size_t e = 0; e < mesh.elements.size(); ++e) {
    for (int k = 0; k < D; ++k) {
      const std::uint32_t v = mesh.elements[e][k];
      if (v >= nv) {
        throw InputError(
            fmt::format("{}: corner {} is vertex {} (counted from 0), but the mesh "
                        "has {} vertices; expected an index below {}",
                        where<D>(source, e), k + 1, v, nv, nv));
      }
      if (!all_finite<D>(vertices[v])) {
        throw InputError(fmt::format("{}: corner {} is at {}; expected finite coordinates",
                                     where<D>(source, e), k + 1, point_text<D>(vertices[v])));
      }
    }
  }
  for (std::size_t v = 0; v < nv; ++v) {
    if (!all_finite<D>(vertices[v])) {
      throw InputError(
          fmt::format("{}: vertex {} (counted from 1), used by no {}, is at {}; "
                      "expected finite coordinates",
                      clip(source), v + 1, element_word<D>(), point_text<D>(vertices[v])));
    }
  }
  // group[v]: the first vertex with v's key; then the used groups are numbered in order.
  std::map<std::array<std::uint64_t, D>, std::uint32_t> first;
  std::vector<std::uint32_t> group(nv);
  for (std::size_t v = 0; v < nv; ++v)
    group[v] =
        first.try_emplace(weld_key<D>(vertices[v]), static_cast<std::uint32_t>(v)).first->second;
  std::vector<std::uint32_t> index(nv, kNoElement);
  for (const auto& el : mesh.elements)
    for (std::uint32_t v : el) index[group[v]] = 0;
  mesh.vertices.clear();
  for (std::size_t v = 0; v < nv; ++v) {
    if (index[v] == kNoElement) continue;
    index[v] = static_cast<std::uint32_t>(mesh.vertices.size());
    mesh.vertices.push_back(vertices[v]);
  }
  for (auto& el : mesh.elements)
    for (std::uint32_t& v : el) v = index[group[v]];
}

// Refuses a 3D triangle whose corners repeat or whose area is at most kDegenerate times its
// longest edge squared (computed on the edges scaled by the longest, so that neither huge
// nor tiny coordinates overflow or underflow).
void check_shape(const SurfaceMesh<3>& mesh, std::size_t e, const std::string& source) {
  const auto& t = mesh.elements[e];
  if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) {
    const std::uint32_t v = t[0] == t[1] || t[0] == t[2] ? t[0] : t[1];
    throw InputError(
        fmt::format("{}: two of its corners are the same point {} (after welding "
                    "equal coordinates); expected three distinct corners",
                    where<3>(source, e), point_text<3>(mesh.vertices[v])));
  }
  const Space<3>::Vec& a = mesh.vertices[t[0]];
  const Space<3>::Vec& b = mesh.vertices[t[1]];
  const Space<3>::Vec& c = mesh.vertices[t[2]];
  const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
  if (!std::isfinite(longest)) {
    throw InputError(
        fmt::format("{}: its corners {}, {} and {} are too far apart for a length "
                    "in double precision; expected a smaller mesh",
                    where<3>(source, e), point_text<3>(a), point_text<3>(b), point_text<3>(c)));
  }
  const double area = 0.5 * ((b - a) / longest).cross((c - a) / longest).norm();
  if (!(area > kDegenerate)) {
    throw InputError(
        fmt::format("{}: corners {}, {} and {} are (nearly) on one line: its area "
                    "is {:.3g} times its longest edge squared; expected more than "
                    "{:g} (a degenerate triangle has no normal)",
                    where<3>(source, e), point_text<3>(a), point_text<3>(b), point_text<3>(c), area,
                    kDegenerate));
  }
}

// Refuses a 2D segment whose ends are the same point or only round-offs apart.
void check_shape(const SurfaceMesh<2>& mesh, std::size_t e, const std::string& source) {
  const auto& s = mesh.elements[e];
  const Space<2>::Vec& a = mesh.vertices[s[0]];
  const Space<2>::Vec& b = mesh.vertices[s[1]];
  if (s[0] == s[1]) {
    throw InputError(
        fmt::format("{}: both ends are the same point {} (after welding equal "
                    "coordinates); expected two distinct ends",
                    where<2>(source, e), point_text<2>(a)));
  }
  const double length = (b - a).norm();
  if (!std::isfinite(length)) {
    throw InputError(
        fmt::format("{}: its ends {} and {} are too far apart for a length in "
                    "double precision; expected a smaller mesh",
                    where<2>(source, e), point_text<2>(a), point_text<2>(b)));
  }
  const double scale = std::max(a.cwiseAbs().maxCoeff(), b.cwiseAbs().maxCoeff());
  if (!(length > kDegenerate * scale)) {
    throw InputError(
        fmt::format("{}: its ends {} and {} are {:.3g} apart, at most {:g} of "
                    "their coordinates; expected a longer segment (a degenerate "
                    "segment has no normal)",
                    where<2>(source, e), point_text<2>(a), point_text<2>(b), length, kDegenerate));
  }
}

// 3D: the edges, each triangle's edges, each edge's triangles and owner; refuses an edge of
// more than two triangles.
void build_edges(SurfaceMesh<3>& mesh, const std::string& source) {
  std::unordered_map<std::uint64_t, std::uint32_t> edge_of;
  edge_of.reserve(mesh.elements.size() * 2);
  mesh.element_edges.resize(mesh.elements.size());
  for (std::size_t e = 0; e < mesh.elements.size(); ++e) {
    const auto& t = mesh.elements[e];
    const auto te = static_cast<std::uint32_t>(e);
    for (std::size_t k = 0; k < 3; ++k) {
      const std::uint32_t a = std::min(t[k], t[(k + 1) % 3]);
      const std::uint32_t b = std::max(t[k], t[(k + 1) % 3]);
      const std::uint64_t key = std::uint64_t{a} << 32 | b;
      const auto [it, added] =
          edge_of.try_emplace(key, static_cast<std::uint32_t>(mesh.edges.size()));
      const std::uint32_t edge = it->second;
      mesh.element_edges[e][k] = edge;
      if (added) {
        mesh.edges.push_back({a, b});
        mesh.edge_elements.push_back({te, kNoElement});
        mesh.edge_owner.push_back(te);
        continue;
      }
      auto& two = mesh.edge_elements[edge];
      if (two[1] != kNoElement) {
        throw InputError(fmt::format(
            "{}: its edge from {} to {} is already shared by triangles {} and {}; expected at "
            "most two triangles on an edge (the surface is non-manifold)",
            where<3>(source, e), point_text<3>(mesh.vertices[a]), point_text<3>(mesh.vertices[b]),
            two[0] + 1, two[1] + 1));
      }
      two[1] = te;
    }
  }
}

// The vertex CSR of `items` (edges in 3D, segments in 2D): each vertex's incident items,
// ascending (filled in ascending item order).
void build_vertex_csr(std::vector<std::uint32_t>& begin, std::vector<std::uint32_t>& items_of,
                      const std::vector<std::array<std::uint32_t, 2>>& items, std::size_t nv) {
  begin.assign(nv + 1, 0);
  for (const auto& it : items)
    for (std::uint32_t v : it) ++begin[v + 1];
  for (std::size_t v = 0; v < nv; ++v) begin[v + 1] += begin[v];
  items_of.assign(begin[nv], 0);
  std::vector<std::uint32_t> next(begin.begin(), begin.end() - 1);
  for (std::size_t i = 0; i < items.size(); ++i)
    for (std::uint32_t v : items[i]) items_of[next[v]++] = static_cast<std::uint32_t>(i);
}

// 2D: refuses a vertex where more than two segments meet (before the CSR is built, so that
// the message names the segment that is one too many).
void check_polyline(const SurfaceMesh<2>& mesh, const std::string& source) {
  std::vector<std::array<std::uint32_t, 2>> seen(mesh.vertices.size(), {kNoElement, kNoElement});
  for (std::size_t e = 0; e < mesh.elements.size(); ++e) {
    for (std::uint32_t v : mesh.elements[e]) {
      auto& two = seen[v];
      if (two[1] != kNoElement) {
        throw InputError(fmt::format(
            "{}: its end {} is already shared by segments {} and {}; expected at most two "
            "segments at a vertex (the polyline is non-manifold)",
            where<2>(source, e), point_text<2>(mesh.vertices[v]), two[0] + 1, two[1] + 1));
      }
      (two[0] == kNoElement ? two[0] : two[1]) = static_cast<std::uint32_t>(e);
    }
  }
}

}  // namespace

template <int D>
SurfaceMesh<D> build_surface(std::vector<typename Space<D>::Vec> vertices,
                             std::vector<typename SurfaceMesh<D>::Element> elements,
                             const std::string& source) {
  if (elements.empty())
    throw InputError(fmt::format("{}: no {}s", clip(source), element_word<D>()));
  if (elements.size() >= kNoElement || vertices.size() >= kNoElement) {
    throw InputError(fmt::format("{}: {} {}s and {} vertices; expected fewer than {} of each",
                                 clip(source), elements.size(), element_word<D>(), vertices.size(),
                                 kNoElement));
  }
  SurfaceMesh<D> mesh;
  mesh.elements = std::move(elements);
  weld<D>(mesh, vertices, source);
  vertices = {};
  for (std::size_t e = 0; e < mesh.elements.size(); ++e) check_shape(mesh, e, source);
  const std::size_t nv = mesh.vertices.size();
  if constexpr (D == 3) {
    build_edges(mesh, source);
    build_vertex_csr(mesh.vertex_edge_begin, mesh.vertex_edges, mesh.edges, nv);
  } else {
    check_polyline(mesh, source);
    build_vertex_csr(mesh.vertex_edge_begin, mesh.vertex_edges, mesh.elements, nv);
  }
  mesh.vertex_owner.assign(nv, kNoElement);
  for (std::size_t e = mesh.elements.size(); e-- > 0;)
    for (std::uint32_t v : mesh.elements[e]) mesh.vertex_owner[v] = static_cast<std::uint32_t>(e);
  return mesh;
}

template SurfaceMesh<2> build_surface<2>(std::vector<Space<2>::Vec>,
                                         std::vector<SurfaceMesh<2>::Element>, const std::string&);
template SurfaceMesh<3> build_surface<3>(std::vector<Space<3>::Vec>,
                                         std::vector<SurfaceMesh<3>::Element>, const std::string&);

namespace {

void check_round_shape(double radius, int facets, const std::string& source) {
  if (!(radius > 0.0) || !std::isfinite(radius))
    throw InputError(
        fmt::format("{}: radius {}; expected a finite number > 0", clip(source), radius));
  if (facets < 3)
    throw InputError(fmt::format("{}: {} facets; expected at least 3", clip(source), facets));
}

// The corner `k` of `facets` on the unit circle: angle 2 pi k / facets.
std::array<double, 2> unit_corner(int k, int facets) {
  const double angle = 2.0 * std::numbers::pi * k / facets;
  return {std::cos(angle), std::sin(angle)};
}

}  // namespace

// The cylinder's frame: w the unit axis, u = w.unitOrthogonal() (Eigen's choice, a fixed
// function of the axis), v = w x u, so that (u, v, w) is right-handed. Corner k of a ring is at
// radius (cos t u + sin t v), t = 2 pi k / facets; ring j (0..segments) at (-length/2 +
// length j / segments) w from the centre. Vertices: the rings in order (ring j, corner k is
// vertex j * facets + k), then the centres of the bottom (-w) and top (+w) caps. Triangles:
// the sides, ring by ring, two per facet, then the bottom fan, then the top fan.
SurfaceMesh<3> cylinder_surface(const Space<3>::Vec& center, const Space<3>::Vec& axis,
                                double radius, double length, int facets, int segments, bool caps,
                                const std::string& source) {
  check_round_shape(radius, facets, source);
  if (!(length > 0.0) || !std::isfinite(length))
    throw InputError(
        fmt::format("{}: length {}; expected a finite number > 0", clip(source), length));
  if (segments < 1)
    throw InputError(fmt::format("{}: {} segments; expected at least 1", clip(source), segments));
  const double axis_norm = axis.norm();
  if (!(axis_norm > 0.0) || !std::isfinite(axis_norm) || !all_finite<3>(center))
    throw InputError(
        fmt::format("{}: axis {} and centre {}; expected a finite non-zero axis and "
                    "a finite centre",
                    clip(source), point_text<3>(axis), point_text<3>(center)));
  const auto f = static_cast<std::uint64_t>(facets);
  const auto s = static_cast<std::uint64_t>(segments);
  if (2 * f * s + 2 * f > kMaxBuiltIn)
    throw InputError(fmt::format("{}: {} facets and {} segments make over {} triangles",
                                 clip(source), facets, segments, kMaxBuiltIn));
  const Space<3>::Vec w = axis / axis_norm;
  const Space<3>::Vec u = w.unitOrthogonal();
  const Space<3>::Vec v = w.cross(u);
  std::vector<Space<3>::Vec> vertices;
  vertices.reserve((s + 1) * f + 2);
  for (int j = 0; j <= segments; ++j) {
    const Space<3>::Vec ring = center + (-0.5 * length + length * j / segments) * w;
    for (int k = 0; k < facets; ++k) {
      const auto [c, sn] = unit_corner(k, facets);
      vertices.push_back(ring + radius * (c * u + sn * v));
    }
  }
  const auto bottom = static_cast<std::uint32_t>(vertices.size());
  vertices.push_back(center - 0.5 * length * w);
  vertices.push_back(center + 0.5 * length * w);
  const auto at = [&](int j, int k) {
    return static_cast<std::uint32_t>(j * facets + (k % facets));
  };
  std::vector<SurfaceMesh<3>::Element> triangles;
  triangles.reserve(2 * f * s + 2 * f);
  for (int j = 0; j < segments; ++j) {
    for (int k = 0; k < facets; ++k) {
      // Along the circle (u to v) then along the axis: the right-hand normal points out.
      triangles.push_back({at(j, k), at(j, k + 1), at(j + 1, k + 1)});
      triangles.push_back({at(j, k), at(j + 1, k + 1), at(j + 1, k)});
    }
  }
  if (caps) {
    for (int k = 0; k < facets; ++k) triangles.push_back({bottom, at(0, k + 1), at(0, k)});
    for (int k = 0; k < facets; ++k)
      triangles.push_back({bottom + 1, at(segments, k), at(segments, k + 1)});
  } else {
    vertices.resize(vertices.size() - 2);
  }
  return build_surface<3>(std::move(vertices), std::move(triangles), source);
}

// Corner k at center + radius (cos t, sin t), t = 2 pi k / facets; segment k joins corners k
// and k + 1: counter-clockwise, so that a segment's normal (its direction turned clockwise,
// (dy, -dx)) points out of the disc.
SurfaceMesh<2> circle_surface(const Space<2>::Vec& center, double radius, int facets,
                              const std::string& source) {
  check_round_shape(radius, facets, source);
  if (!all_finite<2>(center))
    throw InputError(fmt::format("{}: centre {}; expected finite coordinates", clip(source),
                                 point_text<2>(center)));
  if (static_cast<std::uint64_t>(facets) > kMaxBuiltIn)
    throw InputError(
        fmt::format("{}: {} facets; expected at most {}", clip(source), facets, kMaxBuiltIn));
  std::vector<Space<2>::Vec> vertices;
  std::vector<SurfaceMesh<2>::Element> segments;
  for (int k = 0; k < facets; ++k) {
    const auto [c, s] = unit_corner(k, facets);
    vertices.push_back(center + radius * Space<2>::Vec(c, s));
    segments.push_back(
        {static_cast<std::uint32_t>(k), static_cast<std::uint32_t>((k + 1) % facets)});
  }
  return build_surface<2>(std::move(vertices), std::move(segments), source);
}

// Vertex i of the box has coordinate d at hi where bit d of i is set, at lo where it is not.
// 3D: each face a quad of two triangles, wound counter-clockwise seen from outside, in the
// order -x, +x, -y, +y, -z, +z. 2D: the four sides counter-clockwise from lo.
template <int D>
SurfaceMesh<D> box_surface(const typename Space<D>::Vec& lo, const typename Space<D>::Vec& hi,
                           const std::string& source) {
  using Vec = typename Space<D>::Vec;
  if (!all_finite<D>(lo) || !all_finite<D>(hi) || !(lo.array() < hi.array()).all())
    throw InputError(
        fmt::format("{}: box from {} to {}; expected finite corners with lo < hi "
                    "in every coordinate",
                    clip(source), point_text<D>(lo), point_text<D>(hi)));
  std::vector<Vec> vertices;
  for (int i = 0; i < (1 << D); ++i) {
    Vec p;
    for (int d = 0; d < D; ++d) p[d] = (i >> d & 1) != 0 ? hi[d] : lo[d];
    vertices.push_back(p);
  }
  std::vector<typename SurfaceMesh<D>::Element> elements;
  if constexpr (D == 3) {
    constexpr std::uint32_t quads[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                           {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    for (const auto& q : quads) {
      elements.push_back({q[0], q[1], q[2]});
      elements.push_back({q[0], q[2], q[3]});
    }
  } else {
    elements = {{0, 1}, {1, 3}, {3, 2}, {2, 0}};
  }
  return build_surface<D>(std::move(vertices), std::move(elements), source);
}

template SurfaceMesh<2> box_surface<2>(const Space<2>::Vec&, const Space<2>::Vec&,
                                       const std::string&);
template SurfaceMesh<3> box_surface<3>(const Space<3>::Vec&, const Space<3>::Vec&,
                                       const std::string&);

}  // namespace sable
