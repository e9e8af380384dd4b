// Surface meshes: the triangles (3D) or segments (2D) of a mesh wall, with the topology that
// contact with them needs.
//
// A grain touching a mesh must feel the surface the mesh describes, not each element apart:
// one contact where the surface is flat across elements, one on a convex edge, one per face in
// a concave corner (geometry/mesh_wall.hpp resolves this). That needs, for every feature
// (face, edge, vertex), who its neighbours are: the edges of each triangle, the triangles on
// each edge, the edges at each vertex. build_surface() welds, checks and derives them once,
// when the wall is made; the contact code only reads them.
//
// Element k of a triangle joins corners k and k+1 (mod 3). In 2D the elements are segments,
// which are their own "edges": there is no face feature, and a vertex joins the segments that
// end there.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "sable/core/space.hpp"

namespace sable {

inline constexpr std::uint32_t kNoElement = ~std::uint32_t{0};

template <int D>
struct SurfaceMesh {
  using Vec = typename Space<D>::Vec;
  // D corners per element (triangle in 3D, segment in 2D), indices into `vertices`.
  using Element = std::array<std::uint32_t, D>;

  std::vector<Vec> vertices;  // in the wall's body frame
  std::vector<Element> elements;

  // --- Topology, derived by build_surface() -------------------------------------------
  // 3D: the unique edges (their two vertices, ascending), each triangle's three edges
  // (edge k joins corners k and k+1), and each edge's triangles (the second kNoElement on the
  // border of an open surface). Empty in 2D, where the elements are the edges.
  std::vector<std::array<std::uint32_t, 2>> edges;
  std::vector<std::array<std::uint32_t, 3>> element_edges;
  std::vector<std::array<std::uint32_t, 2>> edge_elements;
  // Every vertex's incident edges (3D) or segments (2D), ascending, as one CSR array:
  // vertex v's are vertex_edges[vertex_edge_begin[v] .. vertex_edge_begin[v + 1]).
  std::vector<std::uint32_t> vertex_edge_begin, vertex_edges;
  // The owner of each edge (3D) and vertex: its incident element of lowest index. A contact on
  // a shared feature is kept in the owner's list entry (geometry/mesh_wall.hpp).
  std::vector<std::uint32_t> edge_owner, vertex_owner;

  std::size_t size() const { return elements.size(); }
};

// Welds vertices with bit-identical coordinates (-0 and +0 taken as equal), checks the surface
// and derives the topology. Refuses (InputError naming `source` and the element number,
// counted from 1) any non-finite coordinate, an element whose corners repeat or whose area is
// at most 1e-12 of its longest edge squared (in 2D: whose length is at most 1e-12 of its
// largest coordinate), an edge shared by more than two triangles or (2D) a vertex shared by
// more than two segments (non-manifold), and an empty mesh. `source` is how messages name the
// mesh (a file path, or the scenario key of a built-in shape).
template <int D>
SurfaceMesh<D> build_surface(std::vector<typename Space<D>::Vec> vertices,
                             std::vector<typename SurfaceMesh<D>::Element> elements,
                             const std::string& source);

// A closed faceted cylinder (3D): `facets` flat sides round the axis (unit `axis` through
// `center`), `segments` rows of them along the length, its two ends closed by fans of
// triangles (unless caps is false: then an open tube). The facets' corners lie on the circle
// of `radius`. 2 * facets * segments triangles plus 2 * facets for the caps. Triangles wind
// so that their right-hand normals point out of the solid.
SurfaceMesh<3> cylinder_surface(const Space<3>::Vec& center, const Space<3>::Vec& axis,
                                double radius, double length, int facets, int segments, bool caps,
                                const std::string& source);
// The 2D counterpart: a closed polygon of `facets` sides inscribed in the circle, wound
// counter-clockwise (2D meshes' convention: a segment's normal, its direction turned clockwise,
// points out of the solid).
SurfaceMesh<2> circle_surface(const Space<2>::Vec& center, double radius, int facets,
                              const std::string& source);
// The closed surface of the axis-aligned box lo..hi: 12 triangles (4 segments in 2D), normals
// out of the box.
template <int D>
SurfaceMesh<D> box_surface(const typename Space<D>::Vec& lo, const typename Space<D>::Vec& hi,
                           const std::string& source);

}  // namespace sable
