// Messages about hostile input quote at most 120 characters of it (sable::clip): names and
// keys of 200,000 characters, long lists of known names, paths that name no file, command-line
// values. A 200,000-character wall name or key made a 200 KB message. And the messages about a
// [[grains]] block's `shape` (scenario/parse_shape.cpp): each names the file, line and column,
// the key's full name and what was expected.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "input_helpers.hpp"
#include "run_helpers.hpp"
#include "sable/core/error.hpp"
#include "sable/scenario/config.hpp"

namespace sable {
namespace {

namespace fs = std::filesystem;
using test::error_of;
using test::grains;
using test::has;
using test::kHead;
using test::kTail;
using test::kValid;

void expect_short(const std::string& text, const std::string& place) {
  const std::string msg = error_of(text);
  EXPECT_LT(msg.size(), 1024u) << msg.substr(0, 300);
  EXPECT_TRUE(has(msg, place));
  EXPECT_TRUE(has(msg, "... (200000 characters)"));
}

// Guards: every message quotes at most 120 characters of an input (a 200,000-character wall
// name or key made a 200 KB message), with the whole length, and still names the place.
TEST(InputMessages, LongNamesAndKeysAreQuotedClipped) {
  const std::string name(200000, 'w'), key(200000, 'k');
  const std::string wall =
      "[[wall]]\nname = \"" + name + "\"\nmaterial = \"g\"\npoint = [0, 0]\nnormal = [0, 1]\n";
  // A duplicate wall name, an unknown key, an unknown material name.
  expect_short(kHead + grains() + wall + wall + "[[stage]]\nsteps = 1\n",
               "bounds.toml:24:8: wall[1].name = \"wwww");
  expect_short(key + " = 1\n" + kValid, "bounds.toml:1:1: unknown key kkkk");
  std::string text = kValid;
  text.replace(text.find("material = \"g\""), 14, "material = \"" + name + "\"");
  expect_short(text, "bounds.toml:14:12: grains[0].material = \"wwww");
  // A material of that name, and grains naming another: the known names are clipped too.
  text = kValid;
  text.replace(text.find("name = \"g\""), 10, "name = \"" + name + "\"");
  expect_short(text, "expected the name of a [[material]] (known: \"wwww");
  // toml++'s own message quotes the key it cannot redefine (toml++ cuts it at about 500).
  const std::string redefined = error_of(key + " = 1\n" + key + " = 2\n" + kValid);
  EXPECT_LT(redefined.size(), 1024u) << redefined.substr(0, 300);
  EXPECT_TRUE(has(redefined, "bounds.toml:2:200004: TOML syntax error: "));
  // A wall name in a stage's wall_velocity.
  expect_short(kValid + "wall_velocity = { " + key + " = [0, 0] }\n", "unknown wall stage[0]");
}

// Guards: a list of known names (here 2,000 walls) is cut after about 120 characters.
TEST(InputMessages, KnownNamesAreListedClipped) {
  std::string text = kHead + grains();
  for (int k = 0; k < 2000; ++k)
    text += "[[wall]]\nname = \"wall" + std::to_string(k) +
            "\"\nmaterial = \"g\"\npoint = [0, 0]\nnormal = [0, 1]\n";
  const std::string msg =
      error_of(text + "[[stage]]\nsteps = 1\nwall_velocity = { nowhere = [0, 0] }\n");
  EXPECT_LT(msg.size(), 512u) << msg.substr(0, 600);
  EXPECT_TRUE(has(msg, "(known: wall0, wall1, wall2"));
  EXPECT_TRUE(has(msg, ", ... (2000 in all))"));
}

// Guards: a scenario path that names no file, however long, is quoted clipped.
TEST(InputMessages, MissingScenarioPathIsClipped) {
  const std::string path = "/nowhere/" + std::string(200000 - 9, 'p');
  try {
    load_scenario(path);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_LT(msg.size(), 256u);
    EXPECT_TRUE(has(msg, "/nowhere/pppp"));
    EXPECT_TRUE(has(msg, "... (200000 characters): cannot read scenario: no such file"));
  }
}

// Guards: the command line quotes a refused value clipped (CLI11's message and Sable's own
// held the whole 100,000 characters), exit 2.
TEST(InputMessages, CommandLineValuesAreQuotedClipped) {
  if (!fs::exists(SABLE_CLI)) GTEST_SKIP() << SABLE_CLI << " not built";
  const std::string value(100000, 'v');  // one argument may hold at most 128 KiB
  const fs::path log =
      fs::temp_directory_path() / ("sable_bounds_cli_" + std::to_string(::getpid()) + ".log");
  for (const std::string& args : {"fc3d none.dat --local " + value, "fc3d " + value,
                                  "info " + value, "analyze " + value, "check " + value}) {
    std::string out;
    EXPECT_EQ(test::run_cli(args, log, out), 2) << args.substr(0, 40);
    EXPECT_LT(out.size(), 1024u) << out.substr(0, 300);
    EXPECT_TRUE(has(out, "vvvv")) << args.substr(0, 40);
    EXPECT_TRUE(has(out, "... (1000")) << args.substr(0, 40);  // 100,000 and CLI11's words
  }
  fs::remove(log);
}

// An output folder given on the command line is a path of any length (PATH_MAX is 4096): the
// refusal of a folder that is a file quotes 120 characters of it. Before the clip the whole
// 1,200-character path was echoed.
TEST(InputMessages, OutputFolderIsQuotedClipped) {
  if (!fs::exists(SABLE_CLI)) GTEST_SKIP() << SABLE_CLI << " not built";
  const fs::path base =
      fs::temp_directory_path() / ("sable_clip_out_" + std::to_string(::getpid()));
  fs::path deep = base;
  for (int k = 0; k < 6; ++k) deep /= std::string(200, static_cast<char>('a' + k));
  fs::create_directories(deep.parent_path());
  std::ofstream(deep) << "not a folder\n";  // --out names this file
  const fs::path scen = base / "s.toml";
  std::ofstream(scen) << kValid;
  std::string out;
  EXPECT_EQ(test::run_cli("run " + scen.string() + " --out " + deep.string(), base / "log", out),
            2);
  EXPECT_TRUE(has(out, "is a file, expected a folder")) << out.substr(0, 300);
  EXPECT_TRUE(has(out, "characters)")) << out.substr(0, 300);
  EXPECT_LT(out.size(), 600u) << out.substr(0, 300);
  fs::remove_all(base);
}

// A 3D scenario whose one [[grains]] block (its header on line 13) ends with `shape` on line
// 19; `more` follows the block (walls, [contact]) before the stage.
std::string shaped(const std::string& shape, const std::string& solver = "cd",
                   const std::string& more = "") {
  return "[simulation]\ndimension = 3\nsolver = \"" + solver +
         "\"\ndt = 1e-5\n[domain]\nlo = [0, 0, 0]\nhi = [0.01, 0.01, 0.01]\n"
         "[[material]]\nname = \"g\"\ndensity = 2500.0\nyoung = 5e6\npoisson = 0.3\n"
         "[[grains]]\ngenerator = \"lattice\"\nmaterial = \"g\"\nradius = 1e-3\n"
         "region = { box = { lo = [0, 0, 0], hi = [0.01, 0.01, 0.01] } }\ncount = 4\n"
         "shape = " +
         shape + "\n" + more + "[[stage]]\nsteps = 1\n";
}

// Every message pinned whole (after its place): the words are the interface here.
TEST(InputMessages, GrainShapeKeys) {
  const auto expect_message = [](const std::string& text, const std::string& message) {
    EXPECT_TRUE(has(error_of(text), message));
  };
  const std::string poly = "{ polyhedron = { vertices = 12 } }";
  // Accepted: each form (the file form: test_scenario_shapes.cpp, with its files).
  for (const std::string& ok : {std::string("\"sphere\""), poly, std::string("{ polyhedron = {} }"),
                                std::string("{ points = [[0, 0, 0], [1, 0, 0], [0, 1, 0], "
                                            "[0, 0, 1]], orientation = \"aligned\" }")})
    EXPECT_NO_THROW(parse_scenario(shaped(ok), test::kPath)) << ok;
  expect_message(kHead + grains("4", "shape = \"sphere\"\n") + kTail,
                 "bounds.toml:18:9: grains[0].shape does not apply in 2D (grains are disks there; "
                 "polyhedral grains are 3D only)");
  const std::string forms =
      ": expected \"sphere\" or a table { polyhedron = {...} }, { points = [...] } or { file = "
      "\"...\" }";
  expect_message(shaped("\"cube\""), "bounds.toml:19:9: grains[0].shape = \"cube\"" + forms);
  expect_message(shaped("3"),
                 "bounds.toml:19:9: grains[0].shape = 3" + forms + ", found an integer");
  // DEM takes polyhedra with the linear law only (dem/polyhedral_dem.hpp).
  const std::string linear =
      " with polyhedral grains (grains[0].shape) and DEM: a linear spring per contact point "
      "(docs/contact-laws.md, \"Polyhedral grains\"); a Hertz law needs a curvature, which "
      "corners and edges do not have";
  expect_message(
      shaped(poly, "dem"),
      "bounds.toml:19:9: grains[0].shape: expected [contact] normal = \"linear\"" + linear);
  expect_message(shaped(poly, "dem", "[contact]\nnormal = \"hertz\"\n"),
                 "bounds.toml:21:10: contact.normal = \"hertz\": expected \"linear\"" + linear);
  EXPECT_NO_THROW(parse_scenario(
      shaped(poly, "dem", "[contact]\nnormal = \"linear\"\nkn = 1e4\nkt = 8e3\n"), test::kPath));
  const std::string vertices =
      ": expected an integer in [4, 64] (the points drawn on the sphere, each a corner)";
  for (const char* n : {"3", "65", "-1"})
    expect_message(shaped(std::string("{ polyhedron = { vertices = ") + n + " } }"),
                   std::string("grains[0].shape.polyhedron.vertices = ") + n + vertices);
  expect_message(shaped("{ polyhedron = { vertices = 12.5 } }"),
                 "bounds.toml:19:37: grains[0].shape.polyhedron.vertices = 12.5" + vertices +
                     ", found a floating-point number");
  expect_message(shaped("{ polyhedron = { aspect = [1, 0.5] } }"),
                 "grains[0].shape.polyhedron.aspect = [1, 0.5]: expected an array of 3 numbers");
  expect_message(shaped("{ polyhedron = { aspect = [1, 0, 0.5] } }"),
                 "grains[0].shape.polyhedron.aspect[1] = 0: expected a number in (0, 1]");
  expect_message(shaped("{ polyhedron = { aspect = [1, 1, 1.5] } }"),
                 "grains[0].shape.polyhedron.aspect[2] = 1.5: expected a number in (0, 1]");
  expect_message(shaped("{ polyhedron = { faces = 8 } }"),
                 "unknown key grains[0].shape.polyhedron.faces; allowed keys in "
                 "grains[0].shape.polyhedron: vertices, aspect");
  expect_message(shaped("{ polyhedron = {}, points = [] }"),
                 "expected a table with exactly one of polyhedron = {...}, points = [...] or file "
                 "= \"...\", found several");
  expect_message(shaped("{ orientation = \"random\" }"), "or file = \"...\", found none");
  expect_message(shaped("{ polyhedron = {}, orientation = \"aligned\" }"),
                 "grains[0].shape.orientation does not apply to polyhedron = {...} (random "
                 "polyhedra are turned at random; only to points = [...] and file = \"...\")");
  const std::string tetra = "[[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]";
  expect_message(shaped("{ points = " + tetra + ", orientation = \"sideways\" }"),
                 "grains[0].shape.orientation = \"sideways\": expected one of \"random\", "
                 "\"aligned\"");
  expect_message(shaped("{ points = [[0, 0, 0], [1, 0, 0], [0, 1, 0]] }"),
                 "grains[0].shape.points = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]: expected an array of "
                 "at least 4 points [x, y, z] spanning a solid");
  expect_message(shaped("{ points = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]] }"),
                 "bounds.toml:19:20: grains[0].shape.points: its 4 points lie in one plane: no "
                 "volume");
  expect_message(shaped("{ points = [[0, 0, 0], [1, 0], [0, 1, 0], [0, 0, 1]] }"),
                 "grains[0].shape.points[1] = [1, 0]: expected an array of 3 numbers");
  expect_message(shaped("{ file = \"rock.ply\" }"),
                 "grains[0].shape.file = \"rock.ply\": expected an STL file (.stl) or an OBJ file "
                 "(.obj) of the shape's vertices");
  expect_message(shaped("{ file = \"nowhere/rock.obj\" }"),
                 "grains[0].shape.file = \"nowhere/rock.obj\": expected an existing shape file "
                 "(nothing readable at \"nowhere/rock.obj\")");
}

// With polyhedra in one block, what contact dynamics cannot step with them yet is refused at
// the key that asks for it, so that `sable check` refuses what `sable run` would.
TEST(InputMessages, WhatPolyhedraCannotMeetYet) {
  const std::string poly = "{ polyhedron = {} }";
  const std::string spheres =
      "[[grains]]\ngenerator = \"list\"\nmaterial = \"g\"\nradius = 1e-3\n"
      "positions = [[0.005, 0.005, 0.008]]\n";
  EXPECT_TRUE(has(error_of(shaped(poly, "cd", spheres)),
                  "bounds.toml:20:1: grains[1]: expected a polyhedral shape = {...}, as "
                  "grains[0].shape has: contact dynamics steps a world of polyhedral grains or of "
                  "round ones, not both"));
  const std::string cylinder =
      "[[wall]]\nname = \"drum\"\ntype = \"cylinder\"\nmaterial = \"g\"\ncenter = [0.005, "
      "0.005]\nradius = 0.005\n";
  EXPECT_TRUE(has(error_of(shaped(poly, "cd", cylinder)),
                  "bounds.toml:22:8: wall[0].type = \"cylinder\": expected \"plane\" or \"box\" "
                  "with polyhedral grains (grains[0].shape): they touch plane walls only"));
  EXPECT_TRUE(has(error_of(shaped(poly, "cd", "[contact]\nrolling = \"epsd\"\n")),
                  "bounds.toml:21:11: contact.rolling = \"epsd\": expected \"none\" with "
                  "polyhedral grains (grains[0].shape): their faces resist rolling, and no rolling "
                  "law applies to them"));
}

// Guards: a shape's file name and orientation, however long, are quoted clipped.
TEST(InputMessages, LongShapeValuesAreQuotedClipped) {
  const std::string name(200000, 'w');
  expect_short(shaped("{ file = \"" + name.substr(4) + ".obj\" }"),
               "bounds.toml:19:18: grains[0].shape.file = \"wwww");
  expect_short(shaped("{ points = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], orientation = \"" +
                      name + "\" }"),
               "grains[0].shape.orientation = \"wwww");
}

}  // namespace
}  // namespace sable
