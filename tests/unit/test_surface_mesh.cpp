// Surface meshes (geometry/surface_mesh.hpp): welding, topology, the built-in shapes and every
// refusal of build_surface. The STL reader and writers are tested in test_stl.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "sable/core/error.hpp"
#include "sable/geometry/surface_mesh.hpp"
#include "surface_helpers.hpp"

namespace {

using sable::build_surface;
using sable::InputError;
using sable::kNoElement;
using sable::SurfaceMesh;
using sable::test::contains;
using sable::test::input_error_of;
using V3 = sable::Space<3>::Vec;
using V2 = sable::Space<2>::Vec;
using Edge = std::array<std::uint32_t, 2>;
constexpr double kPi = std::numbers::pi;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// ---------------------------------------------------------------- welding and topology

// Two triangles given as separate corner lists (the shared diagonal's corners repeated) and an
// unused vertex: welding keeps the first occurrences, in order, and drops the unused one.
TEST(SurfaceMesh, WeldsTwoTriangleSquare) {
  const V3 a(0, 0, 0), b(1, 0, 0), c(1, 1, 0), d(0, 1, 0), unused(5, 5, 5);
  const auto m = build_surface<3>({a, b, c, unused, a, c, d}, {{0, 1, 2}, {4, 5, 6}}, "square");
  // Exact: welding copies coordinates, it never computes them.
  ASSERT_EQ(m.vertices.size(), 4u);
  EXPECT_EQ(m.vertices[0], a);
  EXPECT_EQ(m.vertices[1], b);
  EXPECT_EQ(m.vertices[2], c);
  EXPECT_EQ(m.vertices[3], d);
  EXPECT_EQ(m.elements, (std::vector<std::array<std::uint32_t, 3>>{{0, 1, 2}, {0, 2, 3}}));
  // Edges in order of first appearance (triangle by triangle, corners k, k+1), ascending pairs.
  EXPECT_EQ(m.edges, (std::vector<Edge>{{0, 1}, {1, 2}, {0, 2}, {2, 3}, {0, 3}}));
  EXPECT_EQ(m.element_edges, (std::vector<std::array<std::uint32_t, 3>>{{0, 1, 2}, {2, 3, 4}}));
  // The diagonal has both triangles; the four sides are the border of the open square.
  EXPECT_EQ(m.edge_elements,
            (std::vector<Edge>{
                {0, kNoElement}, {0, kNoElement}, {0, 1}, {1, kNoElement}, {1, kNoElement}}));
  EXPECT_EQ(m.edge_owner, (std::vector<std::uint32_t>{0, 0, 0, 1, 1}));
  EXPECT_EQ(m.vertex_owner, (std::vector<std::uint32_t>{0, 0, 0, 1}));
  // Vertex CSR: v0 on edges 0, 2, 4; v1 on 0, 1; v2 on 1, 2, 3; v3 on 3, 4, each ascending.
  EXPECT_EQ(m.vertex_edge_begin, (std::vector<std::uint32_t>{0, 3, 5, 8, 10}));
  EXPECT_EQ(m.vertex_edges, (std::vector<std::uint32_t>{0, 2, 4, 0, 1, 1, 2, 3, 3, 4}));
  sable::test::expect_consistent_topology(m);
  EXPECT_EQ(m.size(), 2u);
}

// -0 and +0 are the same point: an exporter that mirrors a part writes both, and the mesh must
// still be one surface (the first occurrence's bits are kept).
TEST(SurfaceMesh, WeldsNegativeZero) {
  const auto m = build_surface<3>({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-0.0, 0, -0.0}, {0, 0, 1}},
                                  {{0, 1, 2}, {3, 2, 4}}, "zeros");
  ASSERT_EQ(m.vertices.size(), 4u);  // exact: vertex 3 welded to vertex 0
  EXPECT_EQ(m.elements[1], (std::array<std::uint32_t, 3>{0, 2, 3}));
  EXPECT_FALSE(std::signbit(m.vertices[0].x()));  // the first occurrence's +0 kept
  EXPECT_EQ(m.edge_elements[m.element_edges[1][0]], (Edge{0, 1}));  // the shared edge 0-2
}

// ---------------------------------------------------------------- built-in shapes, 3D

// Every edge of a closed surface has two triangles, and its Euler characteristic is 2.
void expect_closed(const SurfaceMesh<3>& m) {
  for (std::size_t e = 0; e < m.edges.size(); ++e)
    EXPECT_NE(m.edge_elements[e][1], kNoElement) << "edge " << e << " on a border";
  EXPECT_EQ(2 * m.edges.size(), 3 * m.elements.size());  // exact: closed triangle mesh
  EXPECT_EQ(m.vertices.size() + m.elements.size(), m.edges.size() + 2);  // V - E + F = 2
}

TEST(SurfaceMesh, ClosedBox) {
  const V3 lo(-0.1, 0.2, 0.3), hi(0.4, 0.7, 1.3);
  const auto m = sable::box_surface<3>(lo, hi, "box");
  EXPECT_EQ(m.vertices.size(), 8u);
  EXPECT_EQ(m.size(), 12u);
  EXPECT_EQ(m.edges.size(), 18u);  // 12 box edges and a diagonal per face
  expect_closed(m);
  sable::test::expect_consistent_topology(m);
  const V3 centre = 0.5 * (lo + hi);
  for (std::size_t t = 0; t < m.size(); ++t) {
    // Outward: the face normal points from the box centre towards the face.
    EXPECT_GT(sable::test::face_normal(m, t).dot(sable::test::face_centroid(m, t) - centre), 0.0)
        << "triangle " << t;
  }
  // Divergence theorem about the centre: exact up to a few round-offs of the products.
  const double volume = (hi - lo).prod();
  EXPECT_NEAR(sable::test::enclosed_volume(m, centre), volume, 1e-12 * volume);
}

// The 832-triangle cylinder of Guillard et al. (2015): 32 facets, 12 rows, capped.
TEST(SurfaceMesh, Cylinder32By12) {
  const V3 centre(0.1, -0.2, 0.3), axis = V3(1, 2, 3);
  const double r = 0.05, length = 0.3;
  const int facets = 32, segments = 12;
  const auto m = sable::cylinder_surface(centre, axis, r, length, facets, segments, true, "cyl");
  EXPECT_EQ(m.size(), 832u);  // 2 * 32 * 12 sides + 2 * 32 caps
  EXPECT_EQ(m.vertices.size(), 13u * 32u + 2u);
  EXPECT_EQ(m.edges.size(), 1248u);
  expect_closed(m);
  sable::test::expect_consistent_topology(m);
  const V3 w = axis.normalized();
  // The ring corners (all but the two cap centres) lie on the circle of radius r: to round-off.
  for (std::size_t v = 0; v + 2 < m.vertices.size(); ++v) {
    const V3 p = m.vertices[v] - centre;
    EXPECT_NEAR((p - p.dot(w) * w).norm(), r, 1e-12 * r) << "vertex " << v;
  }
  // Corner 0 of ring 0 at angle 0 from u = w.unitOrthogonal(), at the bottom end (-w).
  const V3 first = centre - 0.5 * length * w + r * w.unitOrthogonal();
  EXPECT_NEAR((m.vertices[0] - first).norm(), 0.0, 1e-12 * r);  // same arithmetic, round-off
  for (std::size_t t = 0; t < m.size(); ++t) {
    // Outward: from the closest axis point (sides) or the centre (caps) towards the face.
    const V3 c = sable::test::face_centroid(m, t) - centre;
    const V3 out = t < 768 ? V3(c - c.dot(w) * w) : V3(c.dot(w) * w);
    EXPECT_GT(sable::test::face_normal(m, t).dot(out), 0.0) << "triangle " << t;
  }
  // The prism on the inscribed 32-gon: (facets / 2) sin(2 pi / facets) r^2 L, to round-off.
  const double volume = 0.5 * facets * std::sin(2 * kPi / facets) * r * r * length;
  EXPECT_NEAR(sable::test::enclosed_volume(m, centre), volume, 1e-12 * volume);
}

// Without caps: an open tube, its two end rings the border.
TEST(SurfaceMesh, OpenTube) {
  const auto m = sable::cylinder_surface(V3::Zero(), V3(0, 0, 2), 1.0, 2.0, 8, 3, false, "tube");
  EXPECT_EQ(m.size(), 2u * 8u * 3u);
  EXPECT_EQ(m.vertices.size(), 4u * 8u);  // the cap centres are not in an open tube
  std::size_t border = 0;
  for (const auto& two : m.edge_elements) border += two[1] == kNoElement ? 1 : 0;
  EXPECT_EQ(border, 2u * 8u);  // exact: the two end rings of 8 edges
  sable::test::expect_consistent_topology(m);
}

TEST(SurfaceMesh, CylinderArgumentsRefused) {
  const auto refuse = [](double r, double len, int f, int s, const V3& axis) {
    return input_error_of(
        [&] { sable::cylinder_surface(V3::Zero(), axis, r, len, f, s, true, "wall.drum"); });
  };
  const V3 z(0, 0, 1);
  for (const auto& msg :
       {refuse(0.0, 1, 8, 1, z), refuse(1, -1, 8, 1, z), refuse(1, 1, 2, 1, z),
        refuse(1, 1, 8, 0, z), refuse(1, 1, 8, 1, V3::Zero()), refuse(kNaN, 1, 8, 1, z)})
    EXPECT_TRUE(contains(msg, "wall.drum: "));  // each refusal names the shape's key
  EXPECT_TRUE(contains(refuse(1, 1, 2, 1, z), "2 facets; expected at least 3"));
  EXPECT_TRUE(contains(refuse(1, 1, 8, 0, z), "0 segments; expected at least 1"));
  EXPECT_TRUE(contains(refuse(1, 1, 8, 1, V3::Zero()), "expected a finite non-zero axis"));
}

// ---------------------------------------------------------------- built-in shapes, 2D

// The 2D CSR: every vertex of a closed polygon joins exactly two segments, ascending.
void expect_closed_polygon(const SurfaceMesh<2>& m) {
  ASSERT_EQ(m.vertex_edge_begin.size(), m.vertices.size() + 1);
  for (std::size_t v = 0; v < m.vertices.size(); ++v) {
    ASSERT_EQ(m.vertex_edge_begin[v + 1] - m.vertex_edge_begin[v], 2u) << "vertex " << v;
    const auto s0 = m.vertex_edges[m.vertex_edge_begin[v]];
    const auto s1 = m.vertex_edges[m.vertex_edge_begin[v] + 1];
    EXPECT_LT(s0, s1);
    for (auto s : {s0, s1}) EXPECT_TRUE(m.elements[s][0] == v || m.elements[s][1] == v);
  }
  EXPECT_TRUE(m.edges.empty() && m.element_edges.empty() && m.edge_elements.empty() &&
              m.edge_owner.empty());  // 2D: the segments are the edges
}

// Outward in 2D: the segment's direction turned clockwise, (dy, -dx), points away from `inside`.
void expect_outward(const SurfaceMesh<2>& m, const V2& inside) {
  for (std::size_t s = 0; s < m.size(); ++s) {
    const V2 a = m.vertices[m.elements[s][0]], b = m.vertices[m.elements[s][1]];
    const V2 n(b.y() - a.y(), a.x() - b.x());
    EXPECT_GT(n.dot(0.5 * (a + b) - inside), 0.0) << "segment " << s;
  }
}

TEST(SurfaceMesh, CirclePolygon2D) {
  const V2 centre(0.3, -0.1);
  const double r = 0.02;
  const int facets = 24;
  const auto m = sable::circle_surface(centre, r, facets, "drum");
  EXPECT_EQ(m.size(), 24u);
  EXPECT_EQ(m.vertices.size(), 24u);
  expect_closed_polygon(m);
  for (const auto& p : m.vertices) EXPECT_NEAR((p - centre).norm(), r, 1e-12 * r);  // round-off
  // Counter-clockwise: positive shoelace area, that of the inscribed 24-gon, to round-off.
  const double area = 0.5 * facets * std::sin(2 * kPi / facets) * r * r;
  EXPECT_NEAR(sable::test::signed_area(m), area, 1e-12 * area);
  expect_outward(m, centre);
  // The owner of vertex k > 0 is segment k - 1 (the lowest of k - 1 and k); of vertex 0, 0.
  EXPECT_EQ(m.vertex_owner[0], 0u);
  EXPECT_EQ(m.vertex_owner[5], 4u);
}

TEST(SurfaceMesh, BoxPolygon2D) {
  const V2 lo(-1.0, 0.5), hi(2.0, 1.25);
  const auto m = sable::box_surface<2>(lo, hi, "box2");
  EXPECT_EQ(m.size(), 4u);
  expect_closed_polygon(m);
  // Counter-clockwise, exact: the products of these binary fractions are exact.
  EXPECT_EQ(sable::test::signed_area(m), (hi - lo).prod());
  expect_outward(m, 0.5 * (lo + hi));
  // A clockwise polygon is accepted as given; its area is negative (the orientation is the
  // caller's, build_surface does not reorder).
  const auto cw =
      build_surface<2>({{0, 0}, {0, 1}, {1, 1}, {1, 0}}, {{0, 1}, {1, 2}, {2, 3}, {3, 0}}, "cw");
  EXPECT_EQ(sable::test::signed_area(cw), -1.0);  // exact: unit square
  EXPECT_TRUE(contains(input_error_of([] { sable::box_surface<2>(V2(0, 0), V2(1, 0), "flat"); }),
                       "flat: box from (0, 0) to (1, 0)"));  // zero height refused
}

// ---------------------------------------------------------------- refusals

std::string refusal3(std::vector<V3> vertices, std::vector<std::array<std::uint32_t, 3>> tris) {
  return input_error_of([&] { build_surface<3>(vertices, tris, "parts/hopper.stl"); });
}

TEST(SurfaceMesh, RefusesNonFiniteCoordinate) {
  const auto msg =
      refusal3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {kNaN, 0, 1}}, {{0, 1, 2}, {0, 2, 3}});
  EXPECT_TRUE(contains(msg, "parts/hopper.stl: triangle 2 (counted from 1)"));
  EXPECT_TRUE(contains(msg, "corner 3 is at (nan, 0, 1); expected finite coordinates"));
  // An unused non-finite vertex is named by its number.
  const auto unused =
      refusal3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, std::numeric_limits<double>::infinity()}},
               {{0, 1, 2}});
  EXPECT_TRUE(contains(unused, "vertex 4 (counted from 1), used by no triangle"));
}

TEST(SurfaceMesh, RefusesRepeatedCorner) {
  // Corners 1 and 3 are distinct indices with the same coordinates: repeated after welding.
  const auto msg =
      refusal3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 1, 0}}, {{0, 1, 2}, {2, 3, 4}});
  EXPECT_TRUE(contains(msg, "parts/hopper.stl: triangle 2 (counted from 1)"));
  EXPECT_TRUE(contains(msg, "the same point (0, 1, 0)"));
  EXPECT_TRUE(contains(msg, "expected three distinct corners"));
}

TEST(SurfaceMesh, RefusesDegenerateTriangle) {
  // Height 1e-13 of a unit edge: area 5e-14 of the edge squared, below the 1e-12 threshold.
  const auto msg =
      refusal3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.5, 1e-13, 0}}, {{0, 1, 2}, {0, 1, 3}});
  EXPECT_TRUE(contains(msg, "parts/hopper.stl: triangle 2 (counted from 1)"));
  EXPECT_TRUE(contains(msg, "(nearly) on one line"));
  EXPECT_TRUE(contains(msg, "expected more than 1e-12"));
  // Height 1e-9 (area 5e-10 of the edge squared) is a thin triangle, not a degenerate one; and
  // the threshold is relative: the same shapes a micrometre across are judged alike.
  EXPECT_NO_THROW(build_surface<3>({{0, 0, 0}, {1, 0, 0}, {0.5, 1e-9, 0}}, {{0, 1, 2}}, "thin"));
  const double um = 1e-6;
  EXPECT_NO_THROW(build_surface<3>({{0, 0, 0}, {um, 0, 0}, {0, um, 0}}, {{0, 1, 2}}, "small"));
  EXPECT_THROW(
      build_surface<3>({{0, 0, 0}, {um, 0, 0}, {0.5 * um, 1e-13 * um, 0}}, {{0, 1, 2}}, "small"),
      InputError);
}

TEST(SurfaceMesh, RefusesNonManifoldEdge) {
  // Three triangles on the edge (0,0,0)-(1,0,0): a fin, no surface's side is defined there.
  const auto msg = refusal3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, -1, 0}},
                            {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}});
  EXPECT_TRUE(contains(msg, "parts/hopper.stl: triangle 3 (counted from 1)"));
  EXPECT_TRUE(contains(msg, "edge from (0, 0, 0) to (1, 0, 0)"));
  EXPECT_TRUE(contains(msg, "already shared by triangles 1 and 2"));
  EXPECT_TRUE(contains(msg, "non-manifold"));
}

TEST(SurfaceMesh, RefusesEmptyMeshAndBadIndex) {
  EXPECT_EQ(refusal3({{0, 0, 0}}, {}), "parts/hopper.stl: no triangles");
  EXPECT_EQ(input_error_of([] { build_surface<2>({}, {}, "line"); }), "line: no segments");
  const auto msg = refusal3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 3}});
  EXPECT_TRUE(contains(msg, "triangle 1 (counted from 1): corner 3 is vertex 3 (counted from 0)"));
}

TEST(SurfaceMesh, Refusals2D) {
  const auto refuse = [](std::vector<V2> v, std::vector<std::array<std::uint32_t, 2>> s) {
    return input_error_of([&] { build_surface<2>(v, s, "wall.ramp"); });
  };
  // Three segments meeting at (0, 0): not a polyline.
  const auto fork = refuse({{0, 0}, {1, 0}, {0, 1}, {-1, 0}}, {{0, 1}, {2, 0}, {0, 3}});
  EXPECT_TRUE(contains(fork, "wall.ramp: segment 3 (counted from 1): its end (0, 0)"));
  EXPECT_TRUE(contains(fork, "already shared by segments 1 and 2"));
  // Ends a round-off apart (1e-14 at coordinates near 1), and the same end twice after welding.
  EXPECT_TRUE(contains(refuse({{0, 0}, {1, 0}, {1 + 1e-14, 0}}, {{0, 1}, {1, 2}}),
                       "wall.ramp: segment 2 (counted from 1): its ends (1, 0) and"));
  EXPECT_TRUE(contains(refuse({{0, 0}, {1, 0}, {1, 0}}, {{0, 1}, {1, 2}}),
                       "segment 2 (counted from 1): both ends are the same point (1, 0)"));
  EXPECT_TRUE(contains(refuse({{0, 0}, {kNaN, 0}}, {{0, 1}}), "corner 2 is at (nan, 0)"));
}

}  // namespace
