// Mesh walls and turning walls in scenarios: every form of [[wall]] type = "mesh" parses and
// builds the surface it describes (an STL file found beside the scenario, the built-in shapes
// with their element counts), rotations reach the walls from the start and from a stage, every
// class of bad input is refused with its place, key and what was expected, and runs through
// the runner rest a grain on a mesh floor where Hertz puts it and turn a mesh by rate * t.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include "input_helpers.hpp"
#include "run_helpers.hpp"
#include "sable/core/error.hpp"
#include "sable/io/snapshot.hpp"
#include "sable/scenario/build.hpp"
#include "sable/scenario/config.hpp"
#include "sable/scenario/resume_changes.hpp"

namespace sable {
namespace {

namespace fs = std::filesystem;
using test::has;

constexpr const char* kPath = "scen/test.toml";

// 3D and 2D heads (15 lines each): a grain material "g" and a rigid wall material "steel".
std::string head(int dim, const std::string& solver = "dem") {
  const bool three = dim == 3;
  return "[simulation]\ndimension = " + std::to_string(dim) + "\nsolver = \"" + solver +
         "\"\ndt = 1e-5\n[domain]\nlo = " + (three ? "[-1, -1, -1]" : "[-1, -1]") +
         "\nhi = " + (three ? "[1, 1, 1]" : "[1, 1]") +
         "\n[[material]]\nname = \"g\"\ndensity = 2500.0\nyoung = 5e6\npoisson = 0.3\n"
         "[[material]]\nname = \"steel\"\nrigid = true\n";
}

// A wall named "part" of type "mesh" (line 16 of the text; its keys from line 20) with `keys`, then
// a stage.
std::string mesh_wall(int dim, const std::string& keys, const std::string& stage = "",
                      const std::string& solver = "dem") {
  return head(dim, solver) + "[[wall]]\nname = \"part\"\ntype = \"mesh\"\nmaterial = \"steel\"\n" +
         keys + "\n[[stage]]\nsteps = 1\n" + stage;
}

std::string error_of(const std::string& text) {
  try {
    parse_scenario(text, kPath);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError";
  return "";
}

// The wall(s) a scenario builds.
template <int D>
std::vector<Wall<D>> built_walls(const ScenarioConfig& cfg) {
  World<D> w;
  build_model(cfg, w);
  return w.walls;
}

template <int D>
std::vector<Wall<D>> built_walls(const std::string& text) {
  return built_walls<D>(parse_scenario(text, kPath));
}

// An ASCII STL of `triangles` (3 corners each), one facet per triangle.
void write_stl(const fs::path& path, const std::vector<std::array<Vec3a, 3>>& triangles) {
  std::ofstream f(path);
  f << "solid part\n";
  for (const auto& t : triangles) {
    f << "facet normal 0 0 0\nouter loop\n";
    for (const Vec3a& c : t) f << "vertex " << c[0] << " " << c[1] << " " << c[2] << "\n";
    f << "endloop\nendfacet\n";
  }
  f << "endsolid part\n";
}

// A tetrahedron with corners 0, e_x, e_y, e_z (file units).
const std::vector<std::array<Vec3a, 3>> kTetrahedron = {{{{0, 0, 0}, {0, 1, 0}, {1, 0, 0}}},
                                                        {{{0, 0, 0}, {1, 0, 0}, {0, 0, 1}}},
                                                        {{{0, 0, 0}, {0, 0, 1}, {0, 1, 0}}},
                                                        {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}};

class ScenarioMeshFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("sable_scen_mesh_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "parts");
  }
  void TearDown() override { fs::remove_all(dir_); }
  // The scenario `text` written beside the parts folder, loaded from there.
  ScenarioConfig load(const std::string& text) {
    std::ofstream(dir_ / "scen.toml") << text;
    return load_scenario((dir_ / "scen.toml").string());
  }
  fs::path dir_;
};

// --- parse and build -------------------------------------------------------------------------

// Guards: a relative file is found beside the scenario, whatever the working folder; each
// corner x is read as scale * x + offset; the wall's point is its starting box's centre.
TEST_F(ScenarioMeshFiles, FileRelativeToTheScenarioWithScaleAndOffset) {
  write_stl(dir_ / "parts" / "tet.stl", kTetrahedron);
  const ScenarioConfig cfg =
      load(mesh_wall(3, "file = \"parts/tet.stl\"\nscale = 0.001\noffset = [0.5, 0, -0.25]"));
  const MeshConfig& m = cfg.walls[0].mesh;
  EXPECT_EQ(m.file, (dir_ / "parts" / "tet.stl").lexically_normal().string());
  EXPECT_EQ(m.scale, 0.001);
  EXPECT_EQ(m.key, "wall[0].file");
  const auto walls = built_walls<3>(cfg);
  ASSERT_EQ(walls.size(), 1u);
  ASSERT_TRUE(walls[0].is_mesh());
  EXPECT_EQ(walls[0].elements(), 4u);
  EXPECT_NEAR(walls[0].point.x(), 0.5005, 1e-15);
  EXPECT_NEAR(walls[0].point.y(), 0.0005, 1e-15);
  EXPECT_NEAR(walls[0].point.z(), -0.2495, 1e-15);
  EXPECT_FALSE(walls[0].pivoted);
}

// Guards: the built-in shapes' element counts (docs/scenario.md lists them).
TEST(ScenarioMesh, BuiltInShapesHaveTheirElementCounts) {
  const std::string cyl =
      "shape = { cylinder = { center = [0, 0, 0], axis = [0, 0, 1], radius = 0.1, length = 0.2, "
      "facets = 32, segments = 12, caps = true } }";
  EXPECT_EQ(built_walls<3>(mesh_wall(3, cyl))[0].elements(), 832u);
  std::string open = cyl;
  open.replace(open.find("caps = true"), 11, "caps = false");
  EXPECT_EQ(built_walls<3>(mesh_wall(3, open))[0].elements(), 768u);
  // Defaults: axis z, 32 facets, one segment, caps.
  EXPECT_EQ(built_walls<3>(mesh_wall(3,
                                     "shape = { cylinder = { center = [0, 0, 0], radius = "
                                     "0.1, length = 0.2 } }"))[0]
                .elements(),
            128u);
  const std::string box3 = "shape = { box = { lo = [0, 0, 0], hi = [0.1, 0.2, 0.3] } }";
  EXPECT_EQ(built_walls<3>(mesh_wall(3, box3))[0].elements(), 12u);
  const std::string box2 = "shape = { box = { lo = [0, 0], hi = [0.1, 0.2] } }";
  EXPECT_EQ(built_walls<2>(mesh_wall(2, box2))[0].elements(), 4u);
  const std::string circle = "shape = { circle = { center = [0, 0], radius = 0.1, facets = 20 } }";
  EXPECT_EQ(built_walls<2>(mesh_wall(2, circle))[0].elements(), 20u);
  const std::string line = "shape = { polyline = { points = [[0, 0], [0.1, 0], [0.1, 0.1]] } }";
  const auto open_line = built_walls<2>(mesh_wall(2, line));
  EXPECT_EQ(open_line[0].elements(), 2u);
  EXPECT_EQ(open_line[0].mesh()->surface().vertices.size(), 3u);
  std::string closed = line;
  closed.replace(closed.find(" } }"), 4, ", closed = true } }");
  EXPECT_EQ(built_walls<2>(mesh_wall(2, closed))[0].elements(), 3u);
}

// Guards: rotation = {...} turns the wall from the start (Wall::set_rotation): 3D spin = rate
// times the unit axis, 2D spin = rate (about z); the point is the pivot.
TEST(ScenarioMesh, RotationKeysReachTheWall) {
  const std::string turn =
      "rotation = { point = [0.1, 0.2, 0.3], axis = [0, 0, -2], rate = 1.5 }\nshape = { box = { "
      "lo = [0, 0, 0], hi = [0.1, 0.1, 0.1] } }";
  const auto w3 = built_walls<3>(mesh_wall(3, turn));
  EXPECT_TRUE(w3[0].pivoted);
  EXPECT_EQ(w3[0].spin, Eigen::Vector3d(0, 0, -1.5));
  EXPECT_EQ(w3[0].pivot, Eigen::Vector3d(0.1, 0.2, 0.3));
  const auto w2 = built_walls<2>(head(2) +
                                 "[[wall]]\nname = \"floor\"\nmaterial = \"steel\"\npoint = [0, "
                                 "0]\nnormal = [0, 1]\nrotation = { point = [1, 2], rate = -3 }\n"
                                 "[[stage]]\nsteps = 1\n");
  EXPECT_EQ(w2[0].spin, -3.0);
  EXPECT_EQ(w2[0].pivot, Eigen::Vector2d(1, 2));
  // A stage's wall_rotation, parsed for the runner; rate 0 is a pivot without turning.
  const ScenarioConfig cfg = parse_scenario(
      mesh_wall(3, turn,
                "wall_rotation = { part = { point = [1, 2, 3], axis = [1, 0, 0], rate "
                "= 0 } }\n"),
      kPath);
  ASSERT_EQ(cfg.stages[0].wall_rotation.count("part"), 1u);
  const RotationConfig& r = cfg.stages[0].wall_rotation.at("part");
  EXPECT_EQ(r.point, (Vec3a{1, 2, 3}));
  EXPECT_EQ(r.axis, (Vec3a{1, 0, 0}));
  EXPECT_EQ(r.rate, 0.0);
}

// --- bad input -------------------------------------------------------------------------------

// Guards: each class of bad mesh input names file:line:column, the key and what was expected.
TEST(ScenarioMesh, BadMeshInputIsRefusedWithItsPlace) {
  EXPECT_TRUE(has(error_of(mesh_wall(3, "file = \"nowhere.stl\"")),
                  "scen/test.toml:20:8: wall[0].file = \"nowhere.stl\": expected an existing STL "
                  "file (nothing readable at \"scen/nowhere.stl\")"));
  const std::string box = "shape = { box = { lo = [0, 0, 0], hi = [1, 1, 1] } }";
  EXPECT_TRUE(has(error_of(mesh_wall(3, "file = \"a.stl\"\n" + box)),
                  "scen/test.toml:21:9: wall[0].shape = { box = "));
  EXPECT_TRUE(has(error_of(mesh_wall(3, "file = \"a.stl\"\n" + box)),
                  "expected exactly one of file = \"...\" (an STL file) or shape = {...} (a "
                  "built-in shape), found both"));
  EXPECT_TRUE(has(error_of(mesh_wall(3, "")),
                  "scen/test.toml:16:1: missing required key wall[0].file (expected exactly one "
                  "of file"));
  EXPECT_TRUE(has(error_of(mesh_wall(3, "shape = { sphere = { radius = 1 } }")),
                  "scen/test.toml:20:11: unknown key wall[0].shape.sphere; allowed keys in "
                  "wall[0].shape: cylinder, box"));
  EXPECT_TRUE(has(error_of(mesh_wall(3, "shape = {}")),
                  "wall[0].shape = {  }: expected exactly one of cylinder = {...} or box = {...}"));
  const std::string cyl = "shape = { cylinder = { center = [0, 0, 0], length = 1, ";
  EXPECT_TRUE(has(error_of(mesh_wall(3, cyl + "radius = 1, facets = 2 } }")),
                  "wall[0].shape.cylinder.facets = 2: expected an integer >= 3"));
  EXPECT_TRUE(has(error_of(mesh_wall(3, cyl + "radius = -0.5 } }")),
                  "wall[0].shape.cylinder.radius = -0.5: expected a number > 0"));
  EXPECT_TRUE(has(error_of(mesh_wall(3, cyl + "radius = 1, axis = [0, 0, 0] } }")),
                  "wall[0].shape.cylinder.axis = [0, 0, 0]: expected a non-zero direction"));
  EXPECT_TRUE(has(error_of(mesh_wall(3, cyl + "radius = 1, facets = 1000, segments = 1000000 } }")),
                  "wall[0].shape.cylinder.segments = 1000000: expected an integer >= 1 that keeps "
                  "the cylinder within 100000000 triangles"));
  EXPECT_TRUE(has(error_of(mesh_wall(3, cyl + "radius = 1, caps = 1 } }")),
                  "wall[0].shape.cylinder.caps = 1: expected a boolean"));
  EXPECT_TRUE(has(error_of(mesh_wall(3, "shape = { box = { lo = [0, 0, 0], hi = [1, 0, 1] } }")),
                  "wall[0].shape.box.hi = [1, 0, 1]: expected every component greater than "
                  "wall[0].shape.box.lo (axis y"));
  EXPECT_TRUE(has(error_of(mesh_wall(3, box + "\nscale = 2")),
                  "wall[0].scale does not apply to a built-in shape (only to file = \"...\""));
  EXPECT_TRUE(has(error_of(mesh_wall(3, box + "\noffset = [0, 0, 1]")),
                  "wall[0].offset does not apply to a built-in shape"));
  // Contact dynamics takes mesh walls as DEM does.
  EXPECT_NO_THROW(parse_scenario(mesh_wall(3, box, "", "cd"), kPath));
  // Keys of another wall type.
  EXPECT_TRUE(has(error_of(mesh_wall(3, box + "\nnormal = [0, 0, 1]")),
                  "wall[0].normal does not apply to type = \"mesh\" (only to \"plane\")"));
  EXPECT_TRUE(has(error_of(head(3) + "[[wall]]\nname = \"p\"\nmaterial = \"steel\"\npoint = [0, "
                                     "0, 0]\nnormal = [0, 0, 1]\nfile = \"a.stl\"\n"),
                  "wall[0].file does not apply to type = \"plane\" (only to \"mesh\")"));
}

// Guards: shapes of the other dimension are refused, saying what the dimension takes.
TEST(ScenarioMesh, ShapesOfTheOtherDimensionAreRefused) {
  EXPECT_TRUE(has(error_of(mesh_wall(3, "shape = { polyline = { points = [[0, 0], [1, 0]] } }")),
                  "wall[0].shape.polyline does not apply in 3D (a 2D mesh of segments; in 3D: "
                  "file = \"...\" (STL), cylinder = {...} or box = {...})"));
  EXPECT_TRUE(has(error_of(mesh_wall(3, "shape = { circle = { center = [0, 0], radius = 1 } }")),
                  "wall[0].shape.circle does not apply in 3D (a 2D shape; in 3D: cylinder"));
  EXPECT_TRUE(has(error_of(mesh_wall(2, "shape = { cylinder = { center = [0, 0, 0] } }")),
                  "wall[0].shape.cylinder does not apply in 2D (a 3D shape; in 2D: circle"));
  EXPECT_TRUE(has(error_of(mesh_wall(2, "file = \"a.stl\"")),
                  "wall[0].file = \"a.stl\": expected a shape = {...} in 2D (an STL file holds "
                  "triangles"));
  EXPECT_TRUE(has(error_of(mesh_wall(2, "shape = { polyline = { points = [[0, 0]] } }")),
                  "wall[0].shape.polyline.points = [[0, 0]]: expected at least 2 [x, y] points"));
  EXPECT_TRUE(has(
      error_of(mesh_wall(2, "shape = { polyline = { points = [[0, 0], [1, 0]], closed = true } }")),
      "expected at least 3 [x, y] points with closed = true"));
  EXPECT_TRUE(has(error_of(mesh_wall(2, "shape = { polyline = { points = [[0, 0], [1, 0, 0]] } }")),
                  "wall[0].shape.polyline.points[1] = [1, 0, 0]: expected an array of 2 numbers"));
  EXPECT_TRUE(has(error_of(mesh_wall(2,
                                     "shape = { circle = { center = [0, 0], radius = 1, "
                                     "facets = 2.5 } }")),
                  "wall[0].shape.circle.facets = 2.5: expected an integer >= 3, found a "
                  "floating-point number"));
}

// Guards: bad rotations, on a wall and in a stage.
TEST(ScenarioMesh, BadRotationsAreRefusedWithTheirPlace) {
  const std::string box = "shape = { box = { lo = [0, 0, 0], hi = [1, 1, 1] } }\n";
  EXPECT_TRUE(has(error_of(mesh_wall(3, box + "rotation = { point = [0, 0, 0], axis = [0, 0, "
                                              "0], rate = 1 }")),
                  "scen/test.toml:21:40: wall[0].rotation.axis = [0, 0, 0]: expected a non-zero "
                  "direction"));
  EXPECT_TRUE(has(error_of(mesh_wall(3, box + "rotation = { point = [0, 0, 0], axis = [0, 0, "
                                              "1], rate = \"fast\" }")),
                  "wall[0].rotation.rate = \"fast\": expected a rate in rad/s, found a string"));
  EXPECT_TRUE(has(error_of(mesh_wall(3, box + "rotation = { point = [0, 0, 0], axis = [0, 0, 1] "
                                              "}")),
                  "missing required key wall[0].rotation.rate (expected a rate in rad/s"));
  EXPECT_TRUE(has(error_of(mesh_wall(3, box + "rotation = { point = [0, 0, 0], rate = 1 }")),
                  "missing required key wall[0].rotation.axis (expected an array of 3 numbers)"));
  EXPECT_TRUE(has(error_of(mesh_wall(2,
                                     "shape = { box = { lo = [0, 0], hi = [1, 1] } }\n"
                                     "rotation = { point = [0, 0], axis = [0, 0, 1], rate = 1 "
                                     "}")),
                  "wall[0].rotation.axis does not apply in 2D (a 2D wall turns about z through "
                  "point: rate > 0 is counter-clockwise)"));
  EXPECT_TRUE(has(error_of(mesh_wall(3, box + "rotation = 2")),
                  "wall[0].rotation = 2: expected a table, found an integer"));
  // ... and turning walls.
  EXPECT_NO_THROW(parse_scenario(head(3, "cd") +
                                     "[[wall]]\nname = \"p\"\nmaterial = \"steel\"\npoint = [0, 0, "
                                     "0]\nnormal = [0, 0, 1]\nrotation = { point = [0, 0, 0], "
                                     "axis = [1, 0, 0], rate = 1 }\n[[stage]]\nsteps = 1\n",
                                 kPath));
  // A box is planes: refused on the wall and in a stage, with the mesh box suggested.
  const std::string bin =
      head(3) +
      "[[wall]]\nname = \"bin\"\ntype = \"box\"\nmaterial = \"steel\"\nlo = [0, "
      "0, 0]\nhi = [1, 1, 1]\n";
  EXPECT_TRUE(has(error_of(bin + "rotation = { point = [0, 0, 0], axis = [0, 0, 1], rate = 1 }\n"
                                 "[[stage]]\nsteps = 1\n"),
                  "wall[0].rotation does not apply to type = \"box\": a box is independent plane "
                  "walls (NAME.xlo, NAME.xhi, ...); a turning box is a wall of type = \"mesh\" "
                  "with shape = { box = "));
  const std::string turn = "{ point = [0, 0, 0], axis = [0, 0, 1], rate = 1 }";
  for (const char* name : {"bin", "\"bin.zhi\""})
    EXPECT_TRUE(has(
        error_of(bin + "[[stage]]\nsteps = 1\nwall_rotation = { " + name + " = " + turn + " }\n"),
        "a box or box plane cannot turn (\"bin\": a box is independent plane walls"));
  EXPECT_TRUE(has(error_of(mesh_wall(3, box, "wall_rotation = { nowhere = " + turn + " }\n")),
                  "scen/test.toml:24:19: unknown wall stage[0].wall_rotation.nowhere: expected a "
                  "wall name (known: part)"));
  EXPECT_TRUE(has(error_of(mesh_wall(3, box,
                                     "wall_rotation = { part = { point = [0, 0, 0], "
                                     "axis = [0, 1, 0], rate = [1] } }\n")),
                  "stage[0].wall_rotation.part.rate = [1]: expected a rate in rad/s, found an "
                  "array"));
  EXPECT_TRUE(has(error_of(mesh_wall(3, box,
                                     "wall_rotation = { part = { point = [0, 0, 0], "
                                     "axis = [0, 1e-200, 0], rate = 1 } }\n")),
                  "stage[0].wall_rotation.part.axis = [0, 1e-200, 0]: expected a non-zero "
                  "direction"));
  EXPECT_TRUE(has(error_of(mesh_wall(3, box, "wall_rotation = { part = 1 }\n")),
                  "stage[0].wall_rotation.part = 1: expected a table, found an integer"));
}

// Guards: errors found when the mesh is made (the file read, every element checked) name the
// scenario's [[wall]] table, the key, the mesh file and the element.
TEST_F(ScenarioMeshFiles, BuildErrorsNameScenarioWallFileAndTriangle) {
  auto bad = kTetrahedron;
  bad[1][2] = bad[1][1];  // triangle 2 has a repeated corner
  write_stl(dir_ / "parts" / "bad.stl", bad);
  const ScenarioConfig cfg = load(mesh_wall(3, "file = \"parts/bad.stl\""));
  try {
    built_walls<3>(cfg);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    const std::string scen = (dir_ / "scen.toml").string();
    const std::string stl = (dir_ / "parts" / "bad.stl").string();
    EXPECT_TRUE(
        has(e.what(), scen + ":16:1: [[wall]] part: wall[0].file: " + stl + ": triangle 2"));
  }
  // A built-in shape's element, by its key.
  try {
    built_walls<2>(mesh_wall(2, "shape = { polyline = { points = [[0, 0], [1, 0], [1, 0]] } }"));
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_TRUE(
        has(e.what(), "scen/test.toml:16:1: [[wall]] part: wall[0].shape.polyline: segment 2"));
  }
}

// Guards: `sable check` finds a relative mesh file beside the scenario from another folder.
TEST_F(ScenarioMeshFiles, CliChecksAScenarioWithAMeshFile) {
  write_stl(dir_ / "parts" / "tet.stl", kTetrahedron);
  std::ofstream(dir_ / "scen.toml") << mesh_wall(3, "file = \"parts/tet.stl\"\nscale = 0.01");
  std::string out;
  const int rc = test::run_cli("check " + (dir_ / "scen.toml").string(), dir_ / "check.log", out);
  EXPECT_EQ(rc, 0) << out;
  EXPECT_TRUE(has(out, "1 walls"));
}

// Guards: a snapshot records where its scenario was, so `sable analyze` of a snapshot (in
// another folder) finds the mesh file the scenario names by a relative path (before, it looked
// beside the snapshot and stopped).
TEST_F(ScenarioMeshFiles, AnalyzeFindsTheMeshOfARelativePath) {
  write_stl(dir_ / "parts" / "tet.stl", kTetrahedron);
  std::ofstream(dir_ / "scen.toml")
      << head(3) +
             "[[grains]]\ngenerator = \"list\"\nmaterial = \"g\"\nradius = 0.01\npositions = "
             "[[0.1, 0.1, 0.45]]\n[[wall]]\nname = \"part\"\ntype = \"mesh\"\nmaterial = "
             "\"steel\"\nfile = \"parts/tet.stl\"\nscale = 0.5\n[[stage]]\nsteps = 20\n"
             "[output]\ndir = \"unused\"\n";
  std::string out;
  ASSERT_EQ(
      test::run_cli("run " + (dir_ / "scen.toml").string() + " --out " + (dir_ / "run").string(),
                    dir_ / "run.log", out),
      0)
      << out;
  fs::path snap;
  for (const auto& e : fs::directory_iterator(dir_ / "run" / "snapshots")) snap = e.path();
  ASSERT_FALSE(snap.empty());
  EXPECT_EQ(test::run_cli(
                "analyze " + snap.string() + " --only walls --out " + (dir_ / "analysis").string(),
                dir_ / "analyze.log", out),
            0)
      << out;
  EXPECT_TRUE(fs::exists(dir_ / "analysis" / "summary.json")) << out;
}

// Guards: a resume under a scenario with another rotation keeps the snapshot's turning (the
// key is reported not applied, with the reason), and so a mesh's offset (a position); a new
// surface (here more facets) applies.
TEST(ScenarioMesh, ResumeChangesKeepTheSnapshotsTurning) {
  const std::string before =
      mesh_wall(3,
                "shape = { cylinder = { center = [0, 0, 0], radius = 1, length = 1 } }\n"
                "rotation = { point = [0, 0, 0], axis = [0, 0, 1], rate = 1 }");
  std::string after = before;
  after.replace(after.find("rate = 1"), 8, "rate = 2");
  after.replace(after.find("length = 1 }"), 12, "length = 1, facets = 12 }");
  const auto changes = scenario_changes(before, "old", after, "new");
  ASSERT_EQ(changes.size(), 2u);
  EXPECT_EQ(changes[0].key, "wall[0].rotation.rate");
  EXPECT_TRUE(has(changes[0].kept_because, "rotations come from the snapshot"));
  EXPECT_EQ(changes[1].key, "wall[0].shape.cylinder.facets");
  EXPECT_EQ(changes[1].kept_because, "");
  const auto moved = scenario_changes(mesh_wall(3, "file = \"a.stl\""), "old",
                                      mesh_wall(3, "file = \"a.stl\"\noffset = [1, 0, 0]"), "new");
  ASSERT_EQ(moved.size(), 1u);
  EXPECT_TRUE(has(moved[0].kept_because, "the walls' positions"));
}

// --- runs -------------------------------------------------------------------------------------

// One grain (r = 1 mm) dropped from 50 um onto a mesh floor (a box of 12 triangles, the grain
// off its centre) whose rotation key gives it a pivot (rate 0), settled by viscous damping;
// then a stage turns the floor about z through the origin at 2 rad/s for 300 steps. A mesh
// circle beside it ("wheel", 2D) turns from the start.
std::string floor_run(int dim, const std::string& out) {
  const bool three = dim == 3;
  std::string s = "[simulation]\ndimension = " + std::to_string(dim) + "\n";
  s += three ? "gravity = [0, 0, -9.81]\n" : "gravity = [0, -9.81]\nthickness = 0.002\n";
  s += three ? "[domain]\nlo = [-0.005, -0.005, -0.002]\nhi = [0.005, 0.005, 0.004]\n"
             : "[domain]\nlo = [-0.005, -0.002]\nhi = [0.005, 0.004]\n";
  s += "[[material]]\nname = \"g\"\ndensity = 2500.0\nyoung = 5e6\npoisson = 0.3\n"
       "restitution = 0.5\nfriction = 0.5\n"
       "[[material]]\nname = \"steel\"\nrigid = true\nrestitution = 0.5\nfriction = 0.5\n"
       "[[grains]]\ngenerator = \"list\"\nmaterial = \"g\"\nradius = 1e-3\n";
  s += three ? "positions = [[0.0015, -0.001, 1.05e-3]]\n" : "positions = [[0.0015, 1.05e-3]]\n";
  s += "[[wall]]\nname = \"floor\"\ntype = \"mesh\"\nmaterial = \"steel\"\n";
  s += three ? "shape = { box = { lo = [-0.004, -0.004, -0.001], hi = [0.004, 0.004, 0] } }\n"
               "rotation = { point = [0.0005, 0.0005, 0], axis = [0, 0, 1], rate = 0 }\n"
             : "shape = { polyline = { points = [[-0.004, 0], [0.0015, 0], [0.004, 0]] } }\n"
               "rotation = { point = [0.0005, 0], rate = 0 }\n"
               "[[wall]]\nname = \"wheel\"\ntype = \"mesh\"\nmaterial = \"steel\"\n"
               "shape = { circle = { center = [-0.003, 0.003], radius = 5e-4 } }\n"
               "rotation = { point = [-0.003, 0.003], rate = 3 }\n";
  s += "[[stage]]\nname = \"settle\"\nsteps = 5000\nviscous_damping = 200\n";
  s += "[[stage]]\nname = \"turn\"\nsteps = 300\n";
  s += three ? "wall_rotation = { floor = { point = [0, 0, 0], axis = [0, 0, 1], rate = 2 } }\n"
             : "wall_rotation = { floor = { point = [0, 0], rate = 2 } }\n";
  s += "[output]\ndir = \"" + out +
       "\"\ncsv_interval = 0\nsnapshot_interval = 100\n"
       "vtk_interval = 0\nlog_interval = 0\n";
  return s;
}

fs::path fresh_dir(const std::string& name) {
  fs::path p = fs::temp_directory_path() /
               ("sable_scen_mesh_run_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(p);
  return p;
}

// The world a snapshot of `text`'s run holds.
template <int D>
World<D> snapshot_world(const std::string& text, const fs::path& snapshot) {
  World<D> w;
  build_model(parse_scenario(text, kPath), w);
  load_snapshot(snapshot.string(), w);
  return w;
}

// Guards: a sphere rests on a mesh floor at Hertz's overlap under its weight (z = r - delta,
// delta = (3 m g / (4 Y* sqrt(r)))^(2/3), about 6e-4 r: within 1 % of delta), carried by one
// contact although it lies over the floor's two top triangles' region borders (the floor's
// force is its weight to 1e-6), with the torque about the rotation point (rate 0) of that
// weight; the stage's wall_rotation then turns the floor by exactly rate * steps * dt (the
// quaternion's angle to 1e-12 rad, a corner to 1e-15 m), about the new pivot.
TEST(ScenarioMeshRun, SphereRestsOnAMeshFloorThatThenTurns) {
  const fs::path dir = fresh_dir("3d");
  const std::string text = floor_run(3, dir.string());
  test::run_text(text);
  const World<3> settled = snapshot_world<3>(text, dir / "snapshots" / "end_of_stage_1.h5");
  const double r = 1e-3, m = settled.particles.mass[0], g = 9.81, weight = m * g;
  const double y_star = settled.materials.pair(0, 1).y_star;
  const double delta = std::pow(3.0 * weight / (4.0 * y_star * std::sqrt(r)), 2.0 / 3.0);
  const Eigen::Vector3d x = settled.particles.x[0];
  EXPECT_NEAR(x.z(), r, 1e-3 * r);
  EXPECT_NEAR(x.z(), r - delta, 1e-2 * delta);
  const Wall<3>& floor = settled.walls[0];
  EXPECT_NEAR(floor.force.z(), -weight, 1e-6 * weight);
  EXPECT_NEAR(floor.force.head<2>().norm(), 0.0, 1e-6 * weight);
  // Torque about the pivot (0.5, 0.5, 0) mm of the weight at the grain: (c - p) x (0, 0, -W).
  EXPECT_NEAR(floor.torque.x(), -(x.y() - 0.0005) * weight, 1e-6 * weight * r);
  EXPECT_NEAR(floor.torque.y(), (x.x() - 0.0005) * weight, 1e-6 * weight * r);
  EXPECT_FALSE(floor.turned());

  const World<3> turned = snapshot_world<3>(text, dir / "snapshots" / "end_of_stage_2.h5");
  const Wall<3>& f = turned.walls[0];
  const double angle = 2.0 * 300.0 * turned.dt;
  const Eigen::Quaterniond q = f.orientation;
  EXPECT_NEAR(2.0 * std::atan2(q.vec().norm(), q.w()), angle, 1e-12);
  EXPECT_NEAR(q.vec().normalized().z(), 1.0, 1e-12);
  EXPECT_EQ(f.pivot, Eigen::Vector3d::Zero());
  EXPECT_EQ(f.spin, Eigen::Vector3d(0, 0, 2));
  // The corner that started at (4, 4, 0) mm, turned about z through the origin.
  const Eigen::Vector3d corner =
      Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()) * Eigen::Vector3d(0.004, 0.004, 0);
  double nearest = 1.0;
  for (const auto& v : f.mesh()->vertices()) nearest = std::min(nearest, (v - corner).norm());
  EXPECT_LT(nearest, 1e-15);
  // The grain stays on the floor: turning about z does not move the surface vertically.
  EXPECT_NEAR(turned.particles.x[0].z(), r - delta, 2e-2 * delta);
  fs::remove_all(dir);
}

// Guards: a disk rests on a 2D polyline floor, on the vertex between two collinear segments
// (one contact: the floor carries its weight to 1e-6); a circle mesh turning from the start
// and the floor turned by its stage are at rate * steps * dt (to 1e-12 rad); and a run resumed
// mid-stage from a snapshot (the snapshot's spin and pivot, not the scenario's) ends with the
// same state hash as the uninterrupted one.
TEST(ScenarioMeshRun, DiskOnAPolylineAndTurningMeshesResumeBitForBit) {
  const fs::path dir = fresh_dir("2d");
  const std::string text = floor_run(2, (dir / "full").string());
  const RunResult full = test::run_text(text);
  const World<2> settled =
      snapshot_world<2>(text, dir / "full" / "snapshots" / "end_of_stage_1.h5");
  const double r = 1e-3, weight = settled.particles.mass[0] * 9.81;
  EXPECT_NEAR(settled.particles.x[0].y(), r, 1e-3 * r);
  EXPECT_NEAR(settled.walls[0].force.y(), -weight, 1e-6 * weight);
  EXPECT_NEAR(settled.walls[0].torque, (settled.particles.x[0].x() - 0.0005) * -weight,
              1e-6 * weight * r);
  const World<2> turned = snapshot_world<2>(text, dir / "full" / "snapshots" / "end_of_stage_2.h5");
  EXPECT_NEAR(turned.walls[0].orientation, 2.0 * 300.0 * turned.dt, 1e-12);
  EXPECT_NEAR(turned.walls[1].orientation, 3.0 * 5300.0 * turned.dt, 1e-12);
  EXPECT_EQ(turned.walls[0].pivot, Eigen::Vector2d::Zero());

  const fs::path resumed_dir = dir / "resumed";
  const RunResult resumed =
      test::run_text(floor_run(2, resumed_dir.string()),
                     {(dir / "full" / "snapshots" / "step_0000005200.h5").string()});
  EXPECT_EQ(resumed.steps, full.steps);
  EXPECT_EQ(resumed.state_hash, full.state_hash);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace sable
