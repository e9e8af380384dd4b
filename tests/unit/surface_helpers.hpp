// Shared by the surface-mesh and STL tests: the measures of a mesh (enclosed volume and
// area, face normals) and the checks of its topology against its elements.
#pragma once

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <functional>
#include <string>

#include "sable/core/error.hpp"
#include "sable/geometry/surface_mesh.hpp"

namespace sable::test {

// The right-hand (unnormalized) normal of triangle t: (b - a) x (c - a).
inline Space<3>::Vec face_normal(const SurfaceMesh<3>& m, std::size_t t) {
  const auto& e = m.elements[t];
  const auto& a = m.vertices[e[0]];
  return (m.vertices[e[1]] - a).cross(m.vertices[e[2]] - a);
}

inline Space<3>::Vec face_centroid(const SurfaceMesh<3>& m, std::size_t t) {
  const auto& e = m.elements[t];
  return (m.vertices[e[0]] + m.vertices[e[1]] + m.vertices[e[2]]) / 3.0;
}

// The volume a closed surface encloses, by the divergence theorem about `origin`: the sum of
// the signed tetrahedra (origin, a, b, c), positive for outward normals.
inline double enclosed_volume(const SurfaceMesh<3>& m, const Space<3>::Vec& origin) {
  double v = 0.0;
  for (const auto& e : m.elements) {
    const auto a = m.vertices[e[0]] - origin, b = m.vertices[e[1]] - origin,
               c = m.vertices[e[2]] - origin;
    v += a.dot(b.cross(c)) / 6.0;
  }
  return v;
}

// The signed area a closed 2D polyline encloses (shoelace), positive counter-clockwise.
inline double signed_area(const SurfaceMesh<2>& m) {
  double a = 0.0;
  for (const auto& s : m.elements) {
    const auto& p = m.vertices[s[0]];
    const auto& q = m.vertices[s[1]];
    a += 0.5 * (p.x() * q.y() - q.x() * p.y());
  }
  return a;
}

// Every part of the derived topology agrees with the elements: each triangle's edge k joins
// its corners k and k+1 and lists the triangle; each edge is in its two vertices' CSR lists,
// which are ascending; the owners are the lowest incident elements.
inline void expect_consistent_topology(const SurfaceMesh<3>& m) {
  ASSERT_EQ(m.element_edges.size(), m.elements.size());
  ASSERT_EQ(m.edge_elements.size(), m.edges.size());
  ASSERT_EQ(m.edge_owner.size(), m.edges.size());
  ASSERT_EQ(m.vertex_edge_begin.size(), m.vertices.size() + 1);
  for (std::size_t t = 0; t < m.elements.size(); ++t) {
    for (std::size_t k = 0; k < 3; ++k) {
      const auto& edge = m.edges[m.element_edges[t][k]];
      const auto a = m.elements[t][k], b = m.elements[t][(k + 1) % 3];
      EXPECT_EQ(edge, (std::array<std::uint32_t, 2>{std::min(a, b), std::max(a, b)}));
      const auto& two = m.edge_elements[m.element_edges[t][k]];
      EXPECT_TRUE(two[0] == t || two[1] == t) << "triangle " << t << " edge " << k;
    }
  }
  for (std::size_t e = 0; e < m.edges.size(); ++e) {
    EXPECT_LT(m.edges[e][0], m.edges[e][1]);
    EXPECT_EQ(m.edge_owner[e], m.edge_elements[e][0]);  // first seen = lowest index
    EXPECT_TRUE(m.edge_elements[e][1] == kNoElement ||
                m.edge_elements[e][1] > m.edge_elements[e][0]);
  }
  std::size_t incident = 0;
  for (std::size_t v = 0; v < m.vertices.size(); ++v) {
    for (auto i = m.vertex_edge_begin[v]; i < m.vertex_edge_begin[v + 1]; ++i) {
      const auto& edge = m.edges[m.vertex_edges[i]];
      EXPECT_TRUE(edge[0] == v || edge[1] == v);
      if (i > m.vertex_edge_begin[v]) {
        EXPECT_LT(m.vertex_edges[i - 1], m.vertex_edges[i]);
      }
      ++incident;
    }
  }
  EXPECT_EQ(incident, 2 * m.edges.size());  // each edge in exactly its two vertices' lists
  std::vector<std::uint32_t> lowest(m.vertices.size(), kNoElement);
  for (std::size_t t = m.elements.size(); t-- > 0;)
    for (auto v : m.elements[t]) lowest[v] = static_cast<std::uint32_t>(t);
  EXPECT_EQ(m.vertex_owner, lowest);
}

// The message of the InputError `f` throws ("" and a test failure if none).
inline std::string input_error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError";
  return "";
}

inline ::testing::AssertionResult contains(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "\"" << text << "\" lacks \"" << part << "\"";
}

inline std::array<std::uint64_t, 3> bits(const Space<3>::Vec& p) {
  return {std::bit_cast<std::uint64_t>(p.x()), std::bit_cast<std::uint64_t>(p.y()),
          std::bit_cast<std::uint64_t>(p.z())};
}

}  // namespace sable::test
