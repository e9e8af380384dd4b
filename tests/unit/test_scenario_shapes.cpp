// Polyhedral grains from a scenario's [[grains]] `shape` (scenario/build.cpp, generation/
// shape_draws.hpp): each grain a polyhedron on the sphere the generator placed, its bounding
// radius the sphere's, its mass its density times its hull's volume; seeded draws apart from
// the positions'; a given shape from its points, an OBJ or an STL file. The parser's messages
// are in test_input_messages.cpp, a run and its resume in test_run_polyhedra.cpp.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include "sable/core/error.hpp"
#include "sable/generation/shape_draws.hpp"
#include "sable/geometry/convex_hull.hpp"
#include "sable/geometry/polyhedron_mass.hpp"
#include "sable/geometry/surface_mesh.hpp"
#include "sable/io/stl.hpp"
#include "sable/scenario/build.hpp"
#include "sable/scenario/config.hpp"
#include "sable/world/polyhedral_grains.hpp"
#include "sable/world/state_hash.hpp"

namespace sable {
namespace {

namespace fs = std::filesystem;
using Vec = Eigen::Vector3d;

constexpr double kDensity = 2600.0;
const std::string kUniform = "{ distribution = \"uniform\", mean = 1e-3, spread = 0.2 }";

// 40 grains placed at random in a box, stepped by contact dynamics, the [[grains]] block's
// header on line 11 and `shape = SHAPE` (when given) its last line.
std::string scenario(const std::string& shape, std::uint64_t block_seed = 3,
                     const std::string& radius = kUniform) {
  return "[simulation]\ndimension = 3\nsolver = \"cd\"\ndt = 1e-4\n[domain]\nlo = [0, 0, 0]\n"
         "hi = [0.02, 0.02, 0.02]\n[[material]]\nname = \"rock\"\ndensity = 2600.0\n"
         "[[grains]]\ngenerator = \"random\"\nmaterial = \"rock\"\nradius = " +
         radius +
         "\nregion = { box = { lo = [0, 0, 0], hi = [0.02, 0.02, 0.02] } }\ncount = 40\nseed = " +
         std::to_string(block_seed) + "\n" + (shape.empty() ? "" : "shape = " + shape + "\n") +
         "[[stage]]\nsteps = 1\n";
}

World<3> build(const std::string& text, const std::string& path = "shapes.toml") {
  const ScenarioConfig cfg = parse_scenario(text, path);
  World<3> w;
  build_model(cfg, w);
  build_grains(cfg, w);
  return w;
}

// The message of the InputError building `text` raises.
std::string build_error(const std::string& text, const std::string& path) {
  try {
    build(text, path);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError";
  return "";
}

// Grain k's corners where they stand in the world.
std::vector<Vec> world_corners(const World<3>& w, std::size_t k) {
  std::vector<Vec> out;
  for (const Vec& b : w.shapes[w.particles.shape_index[k]].points)
    out.push_back(w.particles.x[k] + w.particles.q[k] * b);
  return out;
}

// Each form as the parser reads it (exact: the values are the file's, or the defaults).
TEST(ScenarioShapes, ParsesEachForm) {
  using Kind = GrainShapeConfig::Kind;
  const auto shape_of = [](const std::string& shape, const std::string& path = "shapes.toml") {
    return parse_scenario(scenario(shape), path).grains.at(0).shape;
  };
  EXPECT_EQ(shape_of("").kind, Kind::kSphere);
  EXPECT_EQ(shape_of("\"sphere\"").kind, Kind::kSphere);
  const GrainShapeConfig defaults = shape_of("{ polyhedron = {} }");
  EXPECT_EQ(defaults.kind, Kind::kRandomPolyhedron);
  EXPECT_EQ(defaults.vertices, 12u);
  EXPECT_EQ(defaults.aspect, (Vec3a{1.0, 1.0, 1.0}));
  EXPECT_EQ(defaults.key, "grains[0].shape");
  const GrainShapeConfig random =
      shape_of("{ polyhedron = { vertices = 20, aspect = [1, 0.5, 0.25] } }");
  EXPECT_EQ(random.vertices, 20u);
  EXPECT_EQ(random.aspect, (Vec3a{1.0, 0.5, 0.25}));
  const GrainShapeConfig points = shape_of(
      "{ points = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], orientation = "
      "\"aligned\" }");
  EXPECT_EQ(points.kind, Kind::kGiven);
  EXPECT_FALSE(points.random_orientation);
  ASSERT_EQ(points.points.size(), 4u);
  EXPECT_EQ(points.points[3], (Vec3a{0.0, 0.0, 1.0}));
  EXPECT_TRUE(points.file.empty());
  const fs::path dir =
      fs::temp_directory_path() / ("sable_shapes_parse_" + std::to_string(::getpid()));
  fs::create_directories(dir / "rocks");
  std::ofstream(dir / "rocks" / "a.OBJ") << "v 0 0 0\n";
  const GrainShapeConfig file =
      shape_of("{ file = \"rocks/a.OBJ\" }", (dir / "shapes.toml").string());
  EXPECT_EQ(file.kind, Kind::kGiven);
  EXPECT_TRUE(file.random_orientation);
  EXPECT_EQ(file.file, (dir / "rocks" / "a.OBJ").string()) << "from the scenario's folder";
  fs::remove_all(dir);
}

const std::string kPoly = "{ polyhedron = { vertices = 12, aspect = [1.0, 0.8, 0.6] } }";

// Each grain is a polyhedron of 12 corners on the sphere the generator placed: the same centre
// to the bit (the shapes' draws do not touch the positions' stream), the same radius as its
// bounding radius (1e-12 relative: the hull's centroid and the scaling round at 1e-16), a row
// of its own, and the mass of its hull at the material's density (1e-12 relative: the volume
// integrals over ~20 triangles, recomputed here in the world frame, round at 1e-15).
TEST(ScenarioShapes, RandomPolyhedraSitOnTheGeneratedSpheres) {
  const World<3> spheres = build(scenario(""));
  const World<3> w = build(scenario(kPoly));
  const auto& p = w.particles;
  ASSERT_EQ(p.size(), 40u);
  ASSERT_EQ(spheres.particles.size(), 40u);
  EXPECT_EQ(w.shapes.size(), 40u);
  std::set<std::uint32_t> rows;
  for (std::size_t k = 0; k < p.size(); ++k) {
    ASSERT_TRUE(p.polyhedron(k));
    rows.insert(p.shape_index[k]);
    EXPECT_EQ(p.x[k], spheres.particles.x[k]) << k;
    const double r = spheres.particles.radius[k];
    EXPECT_NEAR(p.radius[k], r, 1e-12 * r) << k;
    const PolyhedronShape& s = w.shapes[p.shape_index[k]];
    EXPECT_EQ(s.solid.radius(), p.radius[k]);
    // Points on an ellipsoid are all extreme: every one is a corner.
    EXPECT_EQ(s.solid.vertices().size(), 12u) << k;
    const std::vector<Vec> corners = world_corners(w, k);
    const ConvexHull hull = convex_hull(corners);
    const double volume = polyhedron_mass(hull.vertices, hull.triangles).volume;
    EXPECT_NEAR(p.mass[k], kDensity * volume, 1e-12 * p.mass[k]) << k;
    EXPECT_NEAR(p.q[k].norm(), 1.0, 1e-15) << k;
  }
  EXPECT_EQ(rows.size(), 40u) << "one row per grain";
}

// The same block seed gives the same grains to the bit; another seed, others. `shape =
// "sphere"` is today's round grains: the same hash as no shape at all.
TEST(ScenarioShapes, SeededAndReproducible) {
  const std::uint64_t a = state_hash(build(scenario(kPoly, 3)));
  EXPECT_EQ(a, state_hash(build(scenario(kPoly, 3))));
  EXPECT_NE(a, state_hash(build(scenario(kPoly, 4))));
  EXPECT_EQ(state_hash(build(scenario("\"sphere\""))), state_hash(build(scenario(""))));
  const World<3> round = build(scenario("\"sphere\""));
  EXPECT_TRUE(round.shapes.empty());
  for (std::size_t k = 0; k < round.particles.size(); ++k)
    EXPECT_FALSE(round.particles.polyhedron(k));
}

// A given shape (a cube's corners and its face centres, which the hull drops) is scaled per
// radius: one row for a single radius, one per distinct radius of a list, shared by the grains
// of that radius; turned at random, so the grains' orientations differ.
TEST(ScenarioShapes, GivenShapeHasARowPerDistinctRadius) {
  const std::string cube =
      "{ points = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [0, 0, 1], [1, 0, 1], [0, 1, 1], "
      "[1, 1, 1], [0.5, 0.5, 0], [0.5, 0.5, 1]] }";
  const World<3> mono = build(scenario(cube, 3, "1e-3"));
  EXPECT_EQ(mono.shapes.size(), 1u);
  EXPECT_EQ(mono.shapes[0].solid.vertices().size(), 8u);
  // Bounding radius 1e-3 about the centre: side 2e-3 / sqrt(3), volume side^3 (1e-12: rounding).
  const double side = 2e-3 / std::sqrt(3.0);
  EXPECT_NEAR(mono.shapes[0].volume, side * side * side, 1e-12 * side * side * side);
  std::set<std::vector<double>> turns;
  for (std::size_t k = 0; k < mono.particles.size(); ++k) {
    EXPECT_EQ(mono.particles.shape_index[k], 0u);
    const auto& c = mono.particles.q[k].coeffs();
    turns.insert({c[0], c[1], c[2], c[3]});
  }
  EXPECT_EQ(turns.size(), 40u) << "each grain turned by its own draw";
  const World<3> two =
      build(scenario(cube, 3, "{ distribution = \"list\", values = [1e-3, 1.2e-3] }"));
  ASSERT_EQ(two.shapes.size(), 2u);
  for (std::size_t k = 0; k < two.particles.size(); ++k)
    EXPECT_EQ(two.particles.shape_index[k], k % 2 == 0 ? 0u : 1u) << "radii cycle";
  EXPECT_NEAR(two.shapes[1].solid.radius(), 1.2e-3, 1e-12 * 1.2e-3);
}

// orientation = "aligned": the grain stands as its points do, scaled about their hull's
// centroid: each corner at x + (p - c) r / R0 (R0: the points' bounding radius about c), to
// 1e-12 of r (the principal frame's rotation and back round at 1e-16). The points: a 2 x 1 x
// 0.5 box turned off the axes, so that its principal frame is not the points' own.
TEST(ScenarioShapes, AlignedShapeStandsAsItsPoints) {
  const Eigen::Quaterniond tilt(Eigen::AngleAxisd(0.7, Vec(1, 2, 3).normalized()));
  std::vector<Vec> box;
  std::string points = "{ orientation = \"aligned\", points = [";
  for (int k = 0; k < 8; ++k) {
    box.push_back(tilt * Vec(k & 1 ? 2.0 : 0.0, k & 2 ? 1.0 : 0.0, k & 4 ? 0.5 : 0.0));
    points += fmt::format("[{}, {}, {}], ", box.back().x(), box.back().y(), box.back().z());
  }
  points += "] }";
  const World<3> w = build(scenario(points, 3, "1e-3"));
  const Vec c = tilt * Vec(1.0, 0.5, 0.25);
  const double scale = 1e-3 / std::sqrt(1.0 + 0.25 + 0.0625);
  ASSERT_EQ(w.particles.size(), 40u);
  EXPECT_GT((w.particles.q[0].toRotationMatrix() - Eigen::Matrix3d::Identity()).norm(), 0.1)
      << "the body frame is the box's principal frame, not the points' axes";
  for (std::size_t k = 0; k < w.particles.size(); ++k) {
    const std::vector<Vec> corners = world_corners(w, k);
    ASSERT_EQ(corners.size(), 8u);
    for (const Vec& v : box) {
      const Vec want = w.particles.x[k] + (v - c) * scale;
      double nearest = 1.0;
      for (const Vec& got : corners) nearest = std::min(nearest, (got - want).norm());
      EXPECT_LT(nearest, 1e-12 * 1e-3) << "grain " << k;
    }
  }
}

// A folder of its own for one test's files.
fs::path test_folder(const std::string& name) {
  fs::path dir =
      fs::temp_directory_path() / ("sable_shapes_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// The same cube's corners as points, as an OBJ file (with the faces, normals and comments a
// file holds, and a weight after one vertex) and as an STL file: the OBJ gives the points'
// grains to the bit (its vertices in the same order), the STL (its vertices welded in its own
// order) the same masses and radii to 1e-12 relative (the rounding of another vertex order).
TEST(ScenarioShapes, ObjAndStlFilesGiveTheShapeOfTheirVertices) {
  const fs::path dir = test_folder("files");
  std::ofstream(dir / "cube.obj") << "# a unit cube\no cube\n"
                                     "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0 1.0\n"
                                     "v 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1 # a corner\n"
                                     "vn 0 0 1\nf 1 2 4 3\nf 5 6 8 7\n";
  write_stl_ascii(box_surface<3>(Vec::Zero(), Vec::Ones(), "cube"), (dir / "cube.stl").string(),
                  "cube");
  const std::string path = (dir / "shapes.toml").string();
  const std::string points =
      "{ points = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [0, 0, 1], [1, 0, 1], [0, 1, 1], "
      "[1, 1, 1]] }";
  const World<3> from_points = build(scenario(points), path);
  const World<3> from_obj = build(scenario("{ file = \"cube.obj\" }"), path);
  const World<3> from_stl = build(scenario("{ file = \"cube.stl\" }"), path);
  EXPECT_EQ(state_hash(from_obj), state_hash(from_points));
  ASSERT_EQ(from_stl.particles.size(), from_points.particles.size());
  EXPECT_EQ(from_stl.shapes.size(), 40u) << "uniform radii: each grain's radius its own";
  for (std::size_t k = 0; k < from_points.particles.size(); ++k) {
    const double m = from_points.particles.mass[k], r = from_points.particles.radius[k];
    EXPECT_NEAR(from_stl.particles.mass[k], m, 1e-12 * m);
    EXPECT_NEAR(from_stl.particles.radius[k], r, 1e-12 * r);
    EXPECT_EQ(from_stl.particles.x[k], from_points.particles.x[k]);
  }
  fs::remove_all(dir);
}

// A shape file's errors name the scenario's block, the key, the file and its line.
TEST(ScenarioShapes, ShapeFileErrorsNameTheFileAndLine) {
  const fs::path dir = test_folder("errors");
  const std::string path = (dir / "shapes.toml").string();
  std::ofstream(dir / "short.obj") << "v 0 0 0\nv 1 0 0\nv 1 2\n";
  std::ofstream(dir / "bad.obj") << "v 0 0 0 x\n";
  std::ofstream(dir / "empty.obj") << "# nothing\nf 1 2 3\n";
  std::ofstream(dir / "flat.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n";
  const std::string head = path + ":11:1: grains[0].shape.file: " + (dir / "").string();
  EXPECT_EQ(
      build_error(scenario("{ file = \"short.obj\" }"), path),
      head + "short.obj:3: expected a vertex `v x y z` of three finite numbers, found 'v 1 2'");
  EXPECT_EQ(build_error(scenario("{ file = \"bad.obj\" }"), path),
            head +
                "bad.obj:1: expected numbers after `v x y z` (a weight or colours), found 'x' "
                "in 'v 0 0 0 x'");
  EXPECT_EQ(build_error(scenario("{ file = \"empty.obj\" }"), path),
            head + "empty.obj: no vertex (`v x y z` line) in the OBJ file");
  EXPECT_EQ(build_error(scenario("{ file = \"flat.obj\" }"), path),
            head + "flat.obj: its 4 points lie in one plane: no volume");
  fs::remove_all(dir);
}

// An aspect so small that the stretched sphere is flat to the hull's tolerance never gives a
// solid: the block is refused after kMaxShapeDraws draws, not drawn for ever.
TEST(ScenarioShapes, FlatAspectIsRefused) {
  EXPECT_EQ(build_error(scenario("{ polyhedron = { aspect = [1, 1, 1e-14] } }"), "shapes.toml"),
            "shapes.toml:11:1: grains[0].shape.polyhedron: 100 draws of 12 points stretched by "
            "aspect = [1, 1, 1e-14] gave no solid (the points lie in one plane to 1e-12 of their "
            "size): raise the smallest aspect");
}

// The draws themselves. Points on the ellipsoid of semi-axes `aspect` (x^2/a^2 + ... = 1 to
// 1e-15: one rounding per coordinate); over 20,000 points or rotations, the moments of the
// uniform laws: a point's mean 0 and E[z^2] = 1/3, a rotation matrix's mean 0 (each entry's
// standard deviation over n draws is at most 1/sqrt(3n) = 0.0041: 0.03 is seven of them).
TEST(ScenarioShapes, DrawsAreUniform) {
  Rng rng = shape_stream(11);
  const Vec3a aspect{1.0, 0.8, 0.6};
  for (int k = 0; k < 100; ++k)
    for (const Vec& p : random_polyhedron_points(12, aspect, rng, "test")) {
      const double e = p.x() * p.x() + p.y() * p.y() / 0.64 + p.z() * p.z() / 0.36;
      EXPECT_NEAR(e, 1.0, 1e-15);
    }
  constexpr int n = 20000;
  Vec mean = Vec::Zero();
  double z2 = 0.0;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Zero();
  for (int k = 0; k < n / 4; ++k)
    for (const Vec& p : random_polyhedron_points(4, {1.0, 1.0, 1.0}, rng, "test")) {
      mean += p / n;
      z2 += p.z() * p.z() / n;
    }
  for (int k = 0; k < n; ++k) rotation += random_rotation(rng).toRotationMatrix() / n;
  EXPECT_LT(mean.cwiseAbs().maxCoeff(), 0.03);
  EXPECT_NEAR(z2, 1.0 / 3.0, 0.03);
  EXPECT_LT(rotation.cwiseAbs().maxCoeff(), 0.03);
  EXPECT_FALSE(spans_volume({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 1e-13}}));
  EXPECT_TRUE(spans_volume({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 1e-9}}));
  EXPECT_FALSE(spans_volume({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}));
  EXPECT_FALSE(spans_volume({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, std::nan("")}}));
}

}  // namespace
}  // namespace sable
