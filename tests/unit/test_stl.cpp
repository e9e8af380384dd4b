// STL files (io/stl.hpp): round trips through both encodings, the binary-or-ASCII decision,
// scale and offset, and every refusal of a bad file, each naming the file and the triangle or
// line. The suite is named SurfaceStl so that `ctest -R Surface` runs it with the mesh tests.
#include <gtest/gtest.h>
#include <unistd.h>

#include <bit>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "sable/core/error.hpp"
#include "sable/geometry/surface_mesh.hpp"
#include "sable/io/stl.hpp"
#include "surface_helpers.hpp"

namespace {

namespace fs = std::filesystem;
using sable::InputError;
using sable::IoError;
using sable::read_stl;
using sable::SurfaceMesh;
using sable::test::bits;
using sable::test::contains;
using sable::test::input_error_of;
using V3 = sable::Space<3>::Vec;
using Tri = std::array<V3, 3>;

// A closed tetrahedron, wound outward, on coordinates 0 and 1.
const V3 kO(0, 0, 0), kX(1, 0, 0), kY(0, 1, 0), kZ(0, 0, 1);
const std::vector<Tri> kTetra = {{kO, kY, kX}, {kO, kX, kZ}, {kO, kZ, kY}, {kX, kY, kZ}};

// ASCII STL of `tris`: line 1 "solid tet", then 7 lines per facet (facet k, counted from 1,
// starts on line 7k - 5, its vertices on lines 7k - 3 .. 7k - 1), then "endsolid tet".
std::string ascii_of(const std::vector<Tri>& tris) {
  std::ostringstream s;
  s << "solid tet\n";
  for (const auto& t : tris) {
    s << "  facet normal 0 0 0\n    outer loop\n";
    for (const auto& p : t) s << "      vertex " << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
    s << "    endloop\n  endfacet\n";
  }
  s << "endsolid tet\n";
  return s.str();
}

// `text` with its line `n` (counted from 1) replaced by `line`, or removed if `line` is null.
std::string edit_line(const std::string& text, int n, const char* line) {
  std::istringstream in(text);
  std::string out, l;
  for (int k = 1; std::getline(in, l); ++k)
    if (k != n)
      out += l + "\n";
    else if (line != nullptr)
      out += std::string(line) + "\n";
  return out;
}

void put_u32(std::string& s, std::uint32_t v) {
  for (int k = 0; k < 4; ++k) s.push_back(static_cast<char>(v >> (8 * k) & 0xff));
}

// Binary STL of `tris` with the 80-byte `header` (padded with spaces) and the triangle count
// `count` (that of `tris` unless given).
std::string binary_of(const std::vector<Tri>& tris, const std::string& header,
                      std::int64_t count = -1) {
  std::string s = header + std::string(80 - header.size(), ' ');
  put_u32(s,
          static_cast<std::uint32_t>(count < 0 ? static_cast<std::int64_t>(tris.size()) : count));
  for (const auto& t : tris) {
    for (int k = 0; k < 3; ++k) put_u32(s, 0);  // the normal, ignored
    for (const auto& p : t)
      for (int i = 0; i < 3; ++i)
        put_u32(s, std::bit_cast<std::uint32_t>(static_cast<float>(p[i])));
    s.append(2, '\0');
  }
  return s;
}

// Each triangle's corners as coordinates: what an STL file holds, whatever the vertex order.
std::vector<std::array<std::array<std::uint64_t, 3>, 3>> corner_bits(const SurfaceMesh<3>& m) {
  std::vector<std::array<std::array<std::uint64_t, 3>, 3>> out;
  for (const auto& t : m.elements)
    out.push_back({bits(m.vertices[t[0]]), bits(m.vertices[t[1]]), bits(m.vertices[t[2]])});
  return out;
}

class SurfaceStl : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("sable_stl_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string write(const std::string& name, const std::string& bytes) const {
    std::ofstream(path(name), std::ios::binary) << bytes;
    return path(name);
  }
  std::string bytes(const std::string& p) const {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
  // The message with which read_stl refuses the file `name` holding `content`.
  std::string refusal(const std::string& name, const std::string& content) const {
    const std::string p = write(name, content);
    return input_error_of([&] { read_stl(p, 1.0, V3::Zero()); });
  }

  fs::path dir_;
};

// ---------------------------------------------------------------- round trips

// 17 significant digits give every double back: the same triangles, corner for corner, to the
// bit (the vertices are numbered in order of first use in the file, not as the shape made them).
TEST_F(SurfaceStl, AsciiRoundTripOfTheCylinder) {
  const auto mesh =
      sable::cylinder_surface(V3(0.1, -0.2, 0.3), V3(1, 2, 3), 0.05, 0.3, 32, 12, true, "cyl");
  const std::string p = path("drum.stl");
  sable::write_stl_ascii(mesh, p, "drum\nwall");
  EXPECT_EQ(bytes(p).substr(0, 16), "solid drum_wall\n");  // a newline in the name cannot end it
  const auto back = read_stl(p, 1.0, V3::Zero());
  EXPECT_EQ(back.size(), 832u);
  EXPECT_EQ(back.vertices.size(), mesh.vertices.size());  // welded again to the same vertices
  EXPECT_EQ(back.edges.size(), mesh.edges.size());
  EXPECT_EQ(corner_bits(back), corner_bits(mesh));
  // And the mesh read is a fixed point: written and read again, the same arrays exactly.
  sable::write_stl_ascii(back, p, "drum");
  const auto again = read_stl(p, 1.0, V3::Zero());
  EXPECT_EQ(again.elements, back.elements);
  for (std::size_t v = 0; v < back.vertices.size(); ++v)
    EXPECT_EQ(bits(again.vertices[v]), bits(back.vertices[v]));
  EXPECT_EQ(again.edge_elements, back.edge_elements);
}

// Binary stores floats: a mesh on float-representable coordinates comes back to the bit.
TEST_F(SurfaceStl, BinaryRoundTripOfFloatCoordinates) {
  const auto mesh = sable::box_surface<3>(V3(-0.5, 0.25, 1.0), V3(1.5, 2.0, 3.125), "box");
  const std::string p = path("box.stl");
  sable::write_stl_binary(mesh, p);
  const std::string b = bytes(p);
  ASSERT_EQ(b.size(), 84u + 50u * 12u);  // exact: header, count, 50 bytes a triangle
  EXPECT_NE(b.substr(0, 5), "solid");    // so that no reader takes it for ASCII
  float n[3];
  std::memcpy(n, b.data() + 84, sizeof n);  // triangle 1 is on the -x face (little-endian host)
  EXPECT_EQ(n[0], -1.0f);
  EXPECT_EQ(n[1], 0.0f);
  EXPECT_EQ(n[2], 0.0f);
  const auto back = read_stl(p, 1.0, V3::Zero());
  EXPECT_EQ(back.size(), 12u);
  EXPECT_EQ(back.vertices.size(), 8u);
  EXPECT_EQ(corner_bits(back), corner_bits(mesh));
}

// Many exporters begin a binary header with "solid": the size decides, not the first bytes.
TEST_F(SurfaceStl, BinaryBeginningWithSolidIsReadAsBinary) {
  const std::string p = write("cad.stl", binary_of(kTetra, "solid tetrahedron exported by CAD"));
  const auto m = read_stl(p, 1.0, V3::Zero());
  EXPECT_EQ(m.size(), 4u);
  ASSERT_EQ(m.vertices.size(), 4u);
  EXPECT_EQ(m.vertices[0], kO);  // exact: 0 and 1 are floats
  EXPECT_EQ(m.vertices[1], kY);
  EXPECT_EQ(m.vertices[2], kX);
  EXPECT_EQ(m.vertices[3], kZ);
  // With a wrong count it is still refused as binary, not parsed as text.
  const auto msg = refusal("cad_bad.stl", binary_of(kTetra, "solid tetrahedron", 5));
  EXPECT_TRUE(contains(msg, "truncated binary STL: the header claims 5 triangles"));
}

TEST_F(SurfaceStl, ScaleAndOffsetApplied) {
  const std::string p = write("tet.stl", ascii_of(kTetra));
  const V3 offset(1.0, -2.0, 0.25);
  const auto m = read_stl(p, 0.5, offset);
  ASSERT_EQ(m.vertices.size(), 4u);
  // Exact: 0.5 x + offset on 0 and 1 is exact in binary.
  EXPECT_EQ(m.vertices[0], offset);
  EXPECT_EQ(m.vertices[1], V3(1.0, -1.5, 0.25));
  EXPECT_EQ(m.vertices[2], V3(1.5, -2.0, 0.25));
  EXPECT_EQ(m.vertices[3], V3(1.0, -2.0, 0.75));
  const double volume = sable::test::enclosed_volume(m, offset);
  EXPECT_NEAR(volume, 0.125 / 6.0, 1e-15);  // scaled by 0.5^3, outward; round-off only
  for (double bad : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN(),
                     std::numeric_limits<double>::infinity()})
    EXPECT_TRUE(contains(input_error_of([&] { read_stl(p, bad, offset); }), p + ": STL scale"));
  EXPECT_TRUE(contains(input_error_of([&] { read_stl(p, 1.0, V3(0, std::nan(""), 0)); }),
                       p + ": STL offset"));
}

// ---------------------------------------------------------------- bad binary files

TEST_F(SurfaceStl, TruncatedBinaryRefused) {
  const std::string whole = binary_of(std::vector<Tri>(kTetra.begin(), kTetra.end()), "b");
  const std::string p = path("cut.stl");
  const auto msg = refusal("cut.stl", whole.substr(0, 84 + 50 + 20));  // mid-triangle 2
  EXPECT_TRUE(contains(msg, p + ": truncated binary STL"));
  EXPECT_TRUE(contains(msg,
                       "the header claims 4 triangles (284 bytes) but the file has 154 "
                       "bytes; triangle 2 (counted from 1) is cut short"));
  EXPECT_TRUE(contains(refusal("short.stl", std::string(40, '\0')),
                       "40 bytes, shorter than the 84-byte header"));
}

TEST_F(SurfaceStl, WrongBinaryCountRefused) {
  const auto many = refusal("many.stl", binary_of(kTetra, "b", 6));
  EXPECT_TRUE(contains(many, path("many.stl") + ": truncated binary STL: the header claims 6 "
                                                "triangles (384 bytes) but the file has 284 bytes; "
                                                "triangle 5 (counted from 1) is missing"));
  const auto few = refusal("few.stl", binary_of(kTetra, "b", 3));
  EXPECT_TRUE(contains(few, path("few.stl") + ": binary STL whose header says 3 triangles (234 "
                                              "bytes), but the file has 284 bytes: 4 triangles"));
  const auto trailing = refusal("tail.stl", binary_of(kTetra, "b") + "xyz");
  EXPECT_TRUE(contains(trailing, "the file has 287 bytes: 4 triangles and 3 bytes more"));
}

TEST_F(SurfaceStl, NaNInBinaryRefusedWithTriangle) {
  std::vector<Tri> tris = kTetra;
  tris[2][1].y() = std::numeric_limits<double>::quiet_NaN();
  const auto msg = refusal("nan.stl", binary_of(tris, "b"));
  EXPECT_TRUE(contains(msg, path("nan.stl") + ": triangle 3 (counted from 1), corner 2: "
                                              "coordinates (0, nan, 1); expected finite numbers"));
}

// ---------------------------------------------------------------- bad ASCII files

TEST_F(SurfaceStl, AsciiMissingVertexRefused) {
  // Triangle 2's third vertex (line 13) gone: its "endloop" comes after two vertices.
  const auto msg = refusal("two.stl", edit_line(ascii_of(kTetra), 13, nullptr));
  EXPECT_TRUE(contains(msg, path("two.stl") +
                                ": line 13 (triangle 2, counted from 1): found "
                                "'endloop' after 2 vertices; expected 'vertex x y z'"));
  // A fourth vertex in triangle 1 (line 7 holds its "endloop").
  const auto four = refusal("four.stl", edit_line(ascii_of(kTetra), 7, "vertex 1 1 1\nendloop"));
  EXPECT_TRUE(contains(four,
                       "line 7 (triangle 1, counted from 1): found a fourth vertex; "
                       "expected 'endloop' after three vertices"));
}

TEST_F(SurfaceStl, AsciiNonNumberRefused) {
  const auto msg = refusal("word.stl", edit_line(ascii_of(kTetra), 18, "  vertex 0 0 one"));
  EXPECT_TRUE(contains(msg, path("word.stl") + ": line 18 (triangle 3, counted from 1): found "
                                               "'one', not a number"));
  EXPECT_TRUE(contains(msg, "expected 'vertex x y z' with x, y and z numbers"));
  const auto short_line = refusal("xy.stl", edit_line(ascii_of(kTetra), 4, "vertex 0 0"));
  EXPECT_TRUE(contains(short_line,
                       "line 4 (triangle 1, counted from 1): found 'vertex 0 0'; "
                       "expected 'vertex x y z'"));
  const auto nan = refusal("nan.stl", edit_line(ascii_of(kTetra), 27, "vertex 0 nan 1"));
  EXPECT_TRUE(contains(nan,
                       "line 27 (triangle 4, counted from 1), corner 3: coordinates (0, "
                       "nan, 1); expected finite numbers"));
}

TEST_F(SurfaceStl, AsciiStructureRefused) {
  const std::string text = ascii_of(kTetra);
  // Cut after triangle 2's "endfacet" (line 15): no "endsolid".
  const auto cut = refusal(
      "cut.stl", text.substr(0, text.find("  facet normal",
                                          text.find("endfacet", text.find("endfacet") + 1))));
  EXPECT_TRUE(contains(cut, path("cut.stl") + ": the file ends after line 15; expected "
                                              "'endsolid NAME'"));
  const auto loop = refusal("loop.stl", edit_line(text, 3, "outer"));
  EXPECT_TRUE(contains(loop,
                       "line 3 (triangle 1, counted from 1): found 'outer'; expected "
                       "'outer loop'"));
  EXPECT_EQ(refusal("empty.stl", "solid empty\nendsolid empty\n"),
            path("empty.stl") + ": no triangles");
  EXPECT_TRUE(contains(refusal("none.stl", ""), "truncated binary STL: 0 bytes"));
  EXPECT_TRUE(contains(refusal("text.stl", "hello\n"),
                       path("text.stl") + ": not an STL file: text that does not begin with "
                                          "'solid'"));
  const std::string missing = path("missing.stl");
  EXPECT_TRUE(contains(input_error_of([&] { read_stl(missing, 1.0, V3::Zero()); }),
                       missing + ": cannot open STL file: No such file or directory"));
}

// What build_surface refuses is refused in a file too, naming the file and the triangle.
TEST_F(SurfaceStl, DegenerateAndNonManifoldFilesRefused) {
  std::vector<Tri> flat = kTetra;
  flat.push_back({kO, kX, V3(2, 0, 0)});
  const auto degenerate = refusal("flat.stl", ascii_of(flat));
  EXPECT_TRUE(contains(degenerate, path("flat.stl") + ": triangle 5 (counted from 1): corners"));
  EXPECT_TRUE(contains(degenerate, "(nearly) on one line"));
  std::vector<Tri> fin = kTetra;
  fin.push_back({kX, kO, V3(0, -1, 0)});  // a third triangle on the edge O-X
  const auto nonmanifold = refusal("fin.stl", binary_of(fin, "b"));
  EXPECT_TRUE(contains(nonmanifold, path("fin.stl") + ": triangle 5 (counted from 1): its edge "
                                                      "from (0, 0, 0) to (1, 0, 0) is already "
                                                      "shared by triangles 1 and 2"));
}

// ---------------------------------------------------------------- writing

TEST_F(SurfaceStl, WriteFailuresAreIoErrors) {
  const auto mesh = sable::box_surface<3>(V3::Zero(), V3(1, 1, 1), "box");
  const std::string p = path("no/such/dir/box.stl");
  for (int binary = 0; binary < 2; ++binary) {
    try {
      binary != 0 ? sable::write_stl_binary(mesh, p) : sable::write_stl_ascii(mesh, p, "box");
      ADD_FAILURE() << "no IoError";
    } catch (const IoError& e) {
      EXPECT_TRUE(contains(e.what(), p));  // the message names the file
    }
  }
  // A coordinate beyond float range cannot be stored in binary STL.
  const auto huge = sable::box_surface<3>(V3::Zero(), V3(1e39, 1e39, 1e39), "huge");
  EXPECT_THROW(sable::write_stl_binary(huge, path("huge.stl")), IoError);
  EXPECT_FALSE(fs::exists(path("huge.stl")));  // atomic: nothing left behind
}

}  // namespace
