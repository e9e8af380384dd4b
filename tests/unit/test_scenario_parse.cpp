// The TOML scenario parser: a valid scenario maps onto ScenarioConfig exactly, and every class
// of bad input is rejected with "FILE:LINE:COLUMN: key ... expected ..." pointing at the culprit.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "sable/core/error.hpp"
#include "sable/scenario/build.hpp"
#include "sable/scenario/config.hpp"

namespace sable {
namespace {

constexpr const char* kPath = "scen/test.toml";

// A small valid 3D scenario; error tests edit one line of it.
const std::string kBase = R"([simulation]
dimension = 3
seed = 7
dt = 1e-5
gravity = [0, 0, -9.81]

[domain]
lo = [0, 0, 0]
hi = [0.03, 0.03, 0.11]

[[material]]
name = "glass"
density = 2500.0
young = 5e6
poisson = 0.45
restitution = 0.6
friction = 0.5

[[material]]
name = "steel"
rigid = true

[[grains]]
generator = "lattice"
material = "glass"
radius = 0.75e-3
region = { box = { lo = [0, 0, 0], hi = [0.03, 0.03, 0.1] } }
count = 200
spacing = 1.6667e-3

[[wall]]
name = "floor"
type = "plane"
material = "steel"
point = [0, 0, 0]
normal = [0, 0, 2]

[[wall]]
name = "bin"
type = "box"
material = "steel"
lo = [0, 0, 0]
hi = [0.03, 0.03, 0.11]

[[stage]]
name = "settle"
steps = 1000
wall_velocity = { floor = [0, 0, -1e-3], "bin.zhi" = [0, 0, 1] }
)";

// 1-based line of the first occurrence of `needle` in `text`.
int line_of(const std::string& text, const std::string& needle) {
  const std::size_t pos = text.find(needle);
  EXPECT_NE(pos, std::string::npos) << "test text lacks: " << needle;
  if (pos == std::string::npos) return -1;
  int line = 1;
  for (std::size_t i = 0; i < pos; ++i) line += text[i] == '\n' ? 1 : 0;
  return line;
}

// kBase with the first occurrence of `from` replaced by `to`.
std::string edit(const std::string& from, const std::string& to, std::string text = kBase) {
  const std::size_t pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << "base lacks: " << from;
  if (pos != std::string::npos) text.replace(pos, from.size(), to);
  return text;
}

// The InputError message parsing `text` raises ("" and a test failure if none).
std::string error_of(const std::string& text) {
  try {
    parse_scenario(text, kPath);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected an InputError for:\n" << text;
  return "";
}

// Parsing fails with a message that starts "kPath:LINE:" and contains every one of `parts`.
::testing::AssertionResult FailsAt(const std::string& text, int line,
                                   const std::vector<std::string>& parts) {
  const std::string msg = error_of(text);
  const std::string prefix = std::string(kPath) + ":" + std::to_string(line) + ":";
  if (msg.rfind(prefix, 0) != 0) {
    return ::testing::AssertionFailure() << "message lacks prefix " << prefix << ": " << msg;
  }
  for (const auto& part : parts) {
    if (msg.find(part) == std::string::npos) {
      return ::testing::AssertionFailure() << "message lacks '" << part << "': " << msg;
    }
  }
  return ::testing::AssertionSuccess() << msg;
}

// Replace `from` by `to` in the base; the error must point at the line of `to`.
::testing::AssertionResult RejectsEdit(const std::string& from, const std::string& to,
                                       const std::vector<std::string>& parts) {
  const std::string text = edit(from, to);
  return FailsAt(text, line_of(text, to), parts);
}

// Append `extra` to the base; the error must point at the line holding `at`.
::testing::AssertionResult RejectsAppended(const std::string& extra, const std::string& at,
                                           const std::vector<std::string>& parts) {
  const std::string text = kBase + extra;
  return FailsAt(text, line_of(text, at), parts);
}

// ---------------------------------------------------------------------------------------------

// The base scenario plus every optional table, for the valid-input tests.
const std::string kFull = kBase + R"(
[[material_pair]]
materials = ["glass", "steel"]
friction = 0.3

[contact]
normal = "linear"
tangential = "history"
kn = 1e5
kt = 0.5e5

[[grains]]
generator = "random"
material = "glass"
radius = { distribution = "uniform", mean = 1.5e-3, spread = 0.1 }
region = { cylinder = { center = [0.015, 0.015], radius = 0.01, zlo = 0.0, zhi = 0.05 } }
count = 50
max_attempts = 20

[[grains]]
generator = "list"
material = "glass"
radius = [1e-3, 2e-3]
positions = [[0.0, 0.0, 0.1], [0.01, 0.0, 0.1]]
fixed = true

[[stage]]
name = "shake"
kinetic_energy_below = 1e-7
max_steps = 200000
check_interval = 50
wall_velocity = { bin = [0, 0, 0.5] }

[output]
dir = "results"
csv_interval = 10
vtk_walls = false
)";

// Guards [simulation] and [domain] values, defaults and source locations.
TEST(ScenarioParse, ValidSimulationAndDomain) {
  const std::string& text = kFull;
  const ScenarioConfig cfg = parse_scenario(text, kPath);
  EXPECT_EQ(cfg.path, kPath);
  EXPECT_EQ(cfg.text, text);
  EXPECT_EQ(cfg.sim.dimension, 3);
  EXPECT_EQ(cfg.sim.seed, 7u);
  ASSERT_TRUE(cfg.sim.dt.has_value());
  EXPECT_EQ(*cfg.sim.dt, 1e-5);
  EXPECT_EQ(cfg.sim.dt_safety, 0.2);
  EXPECT_EQ(cfg.sim.gravity, (Vec3a{0, 0, -9.81}));
  EXPECT_FALSE(cfg.sim.skin.has_value());
  EXPECT_TRUE(cfg.sim.track_orientation);  // the default
  EXPECT_FALSE(
      parse_scenario(
          std::string(text).replace(text.find("seed = 7"), 8, "track_orientation = false"), kPath)
          .sim.track_orientation);
  EXPECT_EQ(cfg.domain.hi, (Vec3a{0.03, 0.03, 0.11}));
  EXPECT_EQ(cfg.domain.loc.line, line_of(text, "[domain]"));
}

// Guards [[material]], [[material_pair]] and [contact] values and defaults.
TEST(ScenarioParse, ValidMaterialsAndContact) {
  const std::string& text = kFull;
  const ScenarioConfig cfg = parse_scenario(text, kPath);
  ASSERT_EQ(cfg.materials.size(), 2u);
  const Material& glass = cfg.materials[0].material;
  EXPECT_EQ(glass.name, "glass");
  EXPECT_EQ(glass.density, 2500.0);
  EXPECT_EQ(glass.young, 5e6);
  EXPECT_EQ(glass.poisson, 0.45);
  EXPECT_EQ(glass.restitution, 0.6);
  EXPECT_EQ(glass.friction, 0.5);
  EXPECT_FALSE(glass.rigid);
  EXPECT_TRUE(cfg.materials[1].material.rigid);
  EXPECT_EQ(cfg.materials[1].material.restitution, 1.0);
  EXPECT_EQ(cfg.materials[1].loc.file, kPath);
  EXPECT_EQ(cfg.materials[1].loc.line, line_of(text, "[[material]]\nname = \"steel\""));

  ASSERT_EQ(cfg.overrides.size(), 1u);
  EXPECT_EQ(cfg.overrides[0].a, "glass");
  EXPECT_EQ(cfg.overrides[0].b, "steel");
  EXPECT_EQ(cfg.overrides[0].friction, 0.3);
  EXPECT_FALSE(cfg.overrides[0].restitution.has_value());

  EXPECT_EQ(cfg.contact.normal, "linear");
  EXPECT_EQ(cfg.contact.kn, 1e5);
  EXPECT_EQ(cfg.contact.kt, 0.5e5);
}

// Guards [[grains]]: mono, uniform and list radii; box and cylinder regions; positions.
TEST(ScenarioParse, ValidGrains) {
  const ScenarioConfig cfg = parse_scenario(kFull, kPath);
  ASSERT_EQ(cfg.grains.size(), 3u);
  const GrainsConfig& lattice = cfg.grains[0];
  EXPECT_EQ(lattice.radius.kind, RadiusConfig::Kind::kMono);
  EXPECT_EQ(lattice.radius.value, 0.75e-3);
  EXPECT_EQ(lattice.region.kind, RegionConfig::Kind::kBox);
  EXPECT_EQ(lattice.region.hi, (Vec3a{0.03, 0.03, 0.1}));
  EXPECT_EQ(lattice.count, 200u);
  EXPECT_EQ(lattice.spacing, 1.6667e-3);
  EXPECT_EQ(lattice.jitter_rng, "sable");
  const GrainsConfig& random = cfg.grains[1];
  EXPECT_EQ(random.radius.kind, RadiusConfig::Kind::kUniform);
  EXPECT_EQ(random.radius.value, 1.5e-3);
  EXPECT_EQ(random.radius.spread, 0.1);
  EXPECT_EQ(random.region.kind, RegionConfig::Kind::kCylinder);
  EXPECT_EQ(random.region.center, (Vec3a{0.015, 0.015, 0}));
  EXPECT_EQ(random.region.zhi, 0.05);
  EXPECT_EQ(random.max_attempts, 20u);
  const GrainsConfig& list = cfg.grains[2];
  EXPECT_EQ(list.radius.kind, RadiusConfig::Kind::kList);
  EXPECT_EQ(list.radius.values, (std::vector<double>{1e-3, 2e-3}));
  ASSERT_EQ(list.positions.size(), 2u);
  EXPECT_EQ(list.positions[1], (Vec3a{0.01, 0.0, 0.1}));
  EXPECT_TRUE(list.fixed);
}

// Guards [[wall]] (normalised normal), [[stage]] (box and plane names) and [output].
TEST(ScenarioParse, ValidWallsStagesAndOutput) {
  const ScenarioConfig cfg = parse_scenario(kFull, kPath);
  ASSERT_EQ(cfg.walls.size(), 2u);
  EXPECT_EQ(cfg.walls[0].normal, (Vec3a{0, 0, 1}));  // normalised
  EXPECT_EQ(cfg.walls[1].type, "box");
  ASSERT_EQ(cfg.stages.size(), 2u);
  EXPECT_EQ(cfg.stages[0].steps, 1000u);
  EXPECT_EQ(cfg.stages[0].wall_velocity.at("floor"), (Vec3a{0, 0, -1e-3}));
  EXPECT_EQ(cfg.stages[0].wall_velocity.at("bin.zhi"), (Vec3a{0, 0, 1}));
  EXPECT_FALSE(cfg.stages[1].steps.has_value());
  EXPECT_EQ(cfg.stages[1].kinetic_energy_below, 1e-7);
  EXPECT_EQ(cfg.stages[1].max_steps, 200000u);
  EXPECT_EQ(cfg.stages[1].wall_velocity.at("bin"), (Vec3a{0, 0, 0.5}));
  EXPECT_EQ(cfg.output.dir, "results");
  EXPECT_EQ(cfg.output.csv_interval, 10u);
  EXPECT_FALSE(cfg.output.vtk_walls);
  EXPECT_TRUE(cfg.output.vtk_contacts);
}

// Guards 2D: vectors of two numbers padded with z = 0, and the four plane names of a 2D box.
TEST(ScenarioParse, TwoDimensionalPaddingAndBoxPlanes) {
  const std::string text = R"([simulation]
dimension = 2
thickness = 0.01
gravity = [0, -9.81]
[domain]
lo = [0, 0]
hi = [0.1, 0.2]
[[material]]
name = "m"
density = 1000
young = 1e7
poisson = 0.3
[[grains]]
generator = "list"
material = "m"
radius = 1e-3
positions = [[0.01, 0.02]]
[[wall]]
name = "b"
type = "box"
material = "m"
lo = [0, 0]
hi = [0.1, 0.2]
[[stage]]
steps = 10
wall_velocity = { "b.yhi" = [0, -1] }
[[stage]]
steps = 10
wall_velocity = { b.xlo = [1, 0], b.xhi = [-1, 0] }
)";
  const ScenarioConfig cfg = parse_scenario(text, kPath);
  EXPECT_EQ(cfg.sim.dimension, 2);
  EXPECT_EQ(cfg.sim.thickness, 0.01);
  EXPECT_EQ(cfg.sim.gravity, (Vec3a{0, -9.81, 0}));
  EXPECT_EQ(cfg.domain.hi, (Vec3a{0.1, 0.2, 0}));
  EXPECT_EQ(cfg.grains[0].positions[0], (Vec3a{0.01, 0.02, 0}));
  EXPECT_EQ(cfg.stages[0].name, "stage0");
  EXPECT_EQ(cfg.stages[0].wall_velocity.at("b.yhi"), (Vec3a{0, -1, 0}));
  EXPECT_EQ(cfg.stages[1].wall_velocity.at("b.xlo"), (Vec3a{1, 0, 0}));
  EXPECT_EQ(cfg.stages[1].wall_velocity.at("b.xhi"), (Vec3a{-1, 0, 0}));
  // A 2D box has no z planes.
  const std::string bad = edit("\"b.yhi\" = [0, -1]", "\"b.zhi\" = [0, -1]", text);
  EXPECT_TRUE(FailsAt(bad, line_of(bad, "\"b.zhi\""), {"b.zhi", "wall name", "b.yhi"}));
}

// Guards generator "file": the path resolves against the scenario's directory; load_scenario.
TEST(ScenarioParse, DataFileResolvedAgainstScenarioDirectory) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(::testing::TempDir()) / "sable_scenario_parse";
  fs::create_directories(dir / "data");
  std::ofstream(dir / "data" / "lattice.data") << "LAMMPS data file\n";
  const std::string text =
      kBase +
      "[[grains]]\ngenerator = \"file\"\nmaterial = \"glass\"\nfile = \"data/lattice.data\"\n";
  std::ofstream(dir / "pour.toml") << text;
  const ScenarioConfig cfg = load_scenario((dir / "pour.toml").string());
  EXPECT_EQ(cfg.text, text);
  EXPECT_EQ(fs::path(cfg.grains.back().file), (dir / "data" / "lattice.data").lexically_normal());
}

// Guards: a TOML syntax error is reported with file:line:column.
TEST(ScenarioParse, TomlSyntaxError) {
  EXPECT_TRUE(RejectsEdit("dt = 1e-5", "dt = = 1e-5", {"TOML syntax error"}));
}

// Guards: an unknown top-level table is named with the allowed keys.
TEST(ScenarioParse, UnknownTopLevelKey) {
  EXPECT_TRUE(RejectsAppended("[simulaton]\nseed = 1\n", "[simulaton]",
                              {"unknown key simulaton", "allowed keys", "simulation"}));
}

// Guards: unknown keys inside tables and inline tables are named with their dotted path.
TEST(ScenarioParse, UnknownNestedKey) {
  EXPECT_TRUE(RejectsEdit("friction = 0.5", "colour = \"red\"",
                          {"unknown key material[0].colour", "allowed keys", "poisson"}));
  const std::string text = edit("hi = [0.03, 0.03, 0.1] }", "hi = [0.03, 0.03, 0.1], top = 1 }");
  EXPECT_TRUE(FailsAt(text, line_of(text, "region ="), {"grains[0].region.box.top", "lo, hi"}));
}

// Guards: a value of the wrong type names what was expected and what was found.
TEST(ScenarioParse, WrongType) {
  EXPECT_TRUE(
      RejectsEdit("density = 2500.0", "density = \"heavy\"",
                  {"material[0].density = \"heavy\"", "expected a number > 0", "found a string"}));
  EXPECT_TRUE(RejectsEdit("count = 200", "count = 200.0", {"count", "integer", "floating"}));
}

// Guards: a missing required key is reported at its table with the key's full path.
TEST(ScenarioParse, MissingRequiredKey) {
  const std::string text = edit("name = \"glass\"\n", "");
  EXPECT_TRUE(FailsAt(text, line_of(text, "[[material]]"), {"material[0].name", "missing"}));
}

// Guards: density <= 0 is unphysical.
TEST(ScenarioParse, DensityNotPositive) {
  EXPECT_TRUE(RejectsEdit("density = 2500.0", "density = -1", {"material[0].density", "> 0"}));
}

// Guards: Young's modulus <= 0 is unphysical (unless the material is rigid).
TEST(ScenarioParse, YoungNotPositive) {
  EXPECT_TRUE(RejectsEdit("young = 5e6", "young = 0", {"material[0].young = 0", "> 0"}));
}

// Guards: Poisson's ratio outside [0, 0.5); also checks the column of the value.
TEST(ScenarioParse, PoissonOutOfRange) {
  const std::string text = edit("poisson = 0.45", "poisson = 0.6");
  const int line = line_of(text, "poisson = 0.6");
  EXPECT_TRUE(FailsAt(text, line,
                      {std::string(kPath) + ":" + std::to_string(line) + ":11: ",
                       "material[0].poisson = 0.6: expected a number in [0, 0.5)"}));
  EXPECT_TRUE(RejectsEdit("poisson = 0.45", "poisson = 0.5", {"poisson", "[0, 0.5)"}));
}

// Guards: restitution outside (0, 1].
TEST(ScenarioParse, RestitutionOutOfRange) {
  EXPECT_TRUE(RejectsEdit("restitution = 0.6", "restitution = 0", {"restitution", "(0, 1]"}));
  EXPECT_TRUE(RejectsEdit("restitution = 0.6", "restitution = 1.5", {"restitution", "(0, 1]"}));
}

// Guards: a negative friction coefficient.
TEST(ScenarioParse, NegativeFriction) {
  EXPECT_TRUE(RejectsEdit("friction = 0.5", "friction = -0.1", {"material[0].friction", ">= 0"}));
}

// Guards: radius <= 0 in every radius form (number, list value, uniform mean).
TEST(ScenarioParse, RadiusNotPositive) {
  EXPECT_TRUE(RejectsEdit("radius = 0.75e-3", "radius = -0.75e-3", {"grains[0].radius", "> 0"}));
  EXPECT_TRUE(RejectsEdit("radius = 0.75e-3", "radius = [1e-3, 0]", {"grains[0].radius[1]"}));
  EXPECT_TRUE(RejectsEdit("radius = 0.75e-3",
                          "radius = { distribution = \"uniform\", mean = 0, spread = 0.1 }",
                          {"grains[0].radius.mean", "> 0"}));
}

// Guards: a relative spread outside [0, 1).
TEST(ScenarioParse, SpreadOutOfRange) {
  EXPECT_TRUE(RejectsEdit("radius = 0.75e-3",
                          "radius = { distribution = \"uniform\", mean = 1e-3, spread = 1 }",
                          {"grains[0].radius.spread", "[0, 1)"}));
}

// Guards: a negative count is not an unsigned count, and zero grains is refused.
TEST(ScenarioParse, NegativeOrZeroCount) {
  EXPECT_TRUE(RejectsEdit("count = 200", "count = -5", {"grains[0].count = -5", "integer"}));
  EXPECT_TRUE(RejectsEdit("count = 200", "count = 0", {"grains[0].count = 0", ">= 1"}));
}

// Guards: a domain whose hi is not above lo on some axis.
TEST(ScenarioParse, BadDomain) {
  EXPECT_TRUE(RejectsEdit("hi = [0.03, 0.03, 0.11]", "hi = [0.03, 0.0, 0.11]",
                          {"domain.hi", "greater than domain.lo", "axis y"}));
}

// Guards: an inverted box wall.
TEST(ScenarioParse, BadBoxWall) {
  const std::string text =
      edit("hi = [0.03, 0.03, 0.11]\n\n[[stage]]", "hi = [0.03, 0.03, -0.11]\n\n[[stage]]");
  EXPECT_TRUE(FailsAt(text, line_of(text, "-0.11"), {"wall[1].hi", "axis z"}));
}

// Guards: time-step settings (dt <= 0, dt_safety outside (0, kTimeStepError]).
TEST(ScenarioParse, BadTimeStep) {
  EXPECT_TRUE(RejectsEdit("dt = 1e-5", "dt = 0", {"simulation.dt", "> 0"}));
  EXPECT_TRUE(RejectsEdit("dt = 1e-5", "dt_safety = 1.5", {"simulation.dt_safety", "(0, 0.7]"}));
}

// Guards: other [simulation] ranges: skin < 0, max_speed <= 0, overlap_warning <= 0.
TEST(ScenarioParse, BadSimulationLimits) {
  EXPECT_TRUE(RejectsEdit("seed = 7", "skin = -1e-3", {"simulation.skin", ">= 0"}));
  EXPECT_TRUE(RejectsEdit("seed = 7", "max_speed = 0", {"simulation.max_speed", "> 0"}));
  EXPECT_TRUE(RejectsEdit("seed = 7", "overlap_warning = -1", {"overlap_warning", "> 0"}));
  EXPECT_TRUE(RejectsEdit("seed = 7", "track_orientation = 1", {"track_orientation"}));
}

// Guards: thickness is 2D-only, and must be positive in 2D.
TEST(ScenarioParse, Thickness) {
  EXPECT_TRUE(RejectsEdit("seed = 7", "thickness = 0.1", {"simulation.thickness", "2D only"}));
  std::string text = edit("gravity = [0, 0, -9.81]", "thickness = 0");
  text = edit("dimension = 3", "dimension = 2", text);
  EXPECT_TRUE(FailsAt(text, line_of(text, "thickness"), {"simulation.thickness", "> 0"}));
}

// Guards: geometry limits: zero plane normal, cylinder radius <= 0, jitter < 0.
TEST(ScenarioParse, BadGeometry) {
  EXPECT_TRUE(
      RejectsEdit("normal = [0, 0, 2]", "normal = [0, 0, 0]", {"wall[0].normal", "non-zero"}));
  EXPECT_TRUE(RejectsEdit("region = { box = { lo = [0, 0, 0], hi = [0.03, 0.03, 0.1] } }",
                          "region = { cylinder = { center = [0, 0], radius = 0, zlo = 0, "
                          "zhi = 1 } }",
                          {"grains[0].region.cylinder.radius", "> 0"}));
  EXPECT_TRUE(RejectsEdit("spacing = 1.6667e-3", "jitter = -1e-4", {"grains[0].jitter", ">= 0"}));
}

// Guards: the linear law needs positive stiffnesses; hertz refuses them.
TEST(ScenarioParse, LinearStiffness) {
  EXPECT_TRUE(RejectsAppended("[contact]\nnormal = \"linear\"\nkn = 0\nkt = 1\n", "kn = 0",
                              {"contact.kn", "> 0"}));
  EXPECT_TRUE(RejectsAppended("[contact]\nkn = 1e5\n", "kn = 1e5",
                              {"contact.kn", "does not apply", "linear"}));
}

// Guards: enumerated strings (solver, contact laws, generator, jitter_rng).
TEST(ScenarioParse, BadChoice) {
  EXPECT_TRUE(RejectsEdit("seed = 7", "solver = \"fem\"", {"simulation.solver", "\"dem\""}));
  EXPECT_TRUE(RejectsAppended("[contact]\ntangential = \"mindlin\"\n", "mindlin",
                              {"contact.tangential", "one of", "\"history\""}));
  EXPECT_TRUE(RejectsEdit("spacing = 1.6667e-3", "jitter_rng = \"mt\"",
                          {"grains[0].jitter_rng", "numpy-pcg64"}));
}

// Guards: a reference to a material that does not exist lists the known ones.
TEST(ScenarioParse, UnknownMaterialReference) {
  EXPECT_TRUE(RejectsEdit("material = \"glass\"", "material = \"sand\"",
                          {"grains[0].material = \"sand\"", "\"glass\", \"steel\""}));
  EXPECT_TRUE(RejectsAppended("[[material_pair]]\nmaterials = [\"glass\", \"iron\"]\n", "\"iron\"",
                              {"material_pair[0].materials[1]", "material"}));
}

// Guards: duplicate material and wall names (box plane names included).
TEST(ScenarioParse, DuplicateNames) {
  EXPECT_TRUE(RejectsEdit("name = \"steel\"", "name = 'glass'", {"material[1].name", "unique"}));
  // Wall 0 takes the name of a plane of the box "bin", wall 1: the clash is reported there.
  const std::string text = edit("name = \"floor\"", "name = \"bin.xlo\"");
  EXPECT_TRUE(FailsAt(text, line_of(text, "name = \"bin\""), {"wall[1].name", "unique"}));
}

// Guards: wall_velocity naming a wall that does not exist lists the valid names.
TEST(ScenarioParse, UnknownWallInWallVelocity) {
  EXPECT_TRUE(RejectsEdit("floor = [0, 0, -1e-3]", "roof = [0, 0, -1e-3]",
                          {"stage[0].wall_velocity.roof", "wall name", "bin.zhi"}));
}

// Guards: cylinders (walls and regions) need a 3D scenario.
TEST(ScenarioParse, CylinderIn2D) {
  const std::string text = R"([simulation]
dimension = 2
[domain]
lo = [0, 0]
hi = [1, 1]
[[material]]
name = "m"
density = 1
young = 1
poisson = 0
[[wall]]
name = "c"
type = "cylinder"
material = "m"
center = [0, 0]
radius = 1
[[stage]]
steps = 1
)";
  EXPECT_TRUE(FailsAt(text, line_of(text, "\"cylinder\""), {"wall[0].type", "dimension = 3"}));
  const std::string region = std::string(R"([simulation]
dimension = 2
[domain]
lo = [0, 0]
hi = [1, 1]
[[material]]
name = "m"
density = 1
young = 1
poisson = 0
[[grains]]
generator = "random"
material = "m"
radius = 0.1
count = 1
region = { cylinder = { center = [0, 0], radius = 1, zlo = 0, zhi = 1 } }
[[stage]]
steps = 1
)");
  EXPECT_TRUE(
      FailsAt(region, line_of(region, "region ="), {"grains[0].region.cylinder", "dimension = 3"}));
}

// Guards: a vector with the wrong number of components for the dimension.
TEST(ScenarioParse, WrongVectorLength) {
  EXPECT_TRUE(RejectsEdit("gravity = [0, 0, -9.81]", "gravity = [0, -9.81]",
                          {"simulation.gravity", "expected an array of 3 numbers", "2 elements"}));
}

// Guards: a stage needs exactly one of steps / kinetic_energy_below, and max_steps with KE.
TEST(ScenarioParse, StageStopCondition) {
  std::string text = edit("steps = 1000", "steps = 1000\nkinetic_energy_below = 1e-7");
  EXPECT_TRUE(FailsAt(text, line_of(text, "kinetic_energy_below"),
                      {"stage[0].kinetic_energy_below", "exactly one", "both"}));
  text = edit("steps = 1000\n", "");
  EXPECT_TRUE(FailsAt(text, line_of(text, "[[stage]]"), {"stage[0]", "exactly one", "neither"}));
  text = edit("steps = 1000", "kinetic_energy_below = 1e-7");
  EXPECT_TRUE(FailsAt(text, line_of(text, "[[stage]]"), {"stage[0].max_steps", "missing"}));
}

// Guards: a scenario needs at least one stage and at least one material.
TEST(ScenarioParse, MissingStageOrMaterial) {
  const std::string no_stage = kBase.substr(0, kBase.find("[[stage]]"));
  EXPECT_TRUE(FailsAt(no_stage, 1, {"stage", "at least one"}));
  EXPECT_TRUE(FailsAt("[domain]\nlo = [0, 0, 0]\nhi = [1, 1, 1]\n", 1, {"material", "at least"}));
}

// Guards: generator "list": positions required, a radius list must match their number.
TEST(ScenarioParse, ListGenerator) {
  const std::string extra =
      "[[grains]]\ngenerator = \"list\"\nmaterial = \"glass\"\n"
      "radius = [1e-3, 2e-3, 3e-3]\npositions = [[0, 0, 0.1], [0, 0, 0.2]]\n";
  EXPECT_TRUE(RejectsAppended(extra, "radius = [1e-3, 2e-3, 3e-3]",
                              {"grains[1].radius", "one per position"}));
  EXPECT_TRUE(RejectsAppended(
      "[[grains]]\ngenerator = \"list\"\nmaterial = \"glass\"\nradius = 1\npositions = []\n",
      "positions = []", {"grains[1].positions", "non-empty"}));
}

// Guards: keys that only other generators use are refused (a file carries its own radii).
TEST(ScenarioParse, KeysOfOtherGenerators) {
  EXPECT_TRUE(
      RejectsAppended("[[grains]]\ngenerator = \"list\"\nmaterial = \"glass\"\n"
                      "radius = 1e-3\ncount = 3\npositions = [[0, 0, 0]]\n",
                      "count = 3", {"grains[1].count", "does not apply", "lattice"}));
  EXPECT_TRUE(
      RejectsAppended("[[grains]]\ngenerator = \"file\"\nmaterial = \"glass\"\n"
                      "radius = 1e-3\nfile = \"x.data\"\n",
                      "radius = 1e-3\nfile", {"grains[1].radius", "does not apply"}));
}

// Guards: generator "file" pointing at a file that does not exist; and a missing scenario.
TEST(ScenarioParse, MissingFile) {
  EXPECT_TRUE(RejectsAppended(
      "[[grains]]\ngenerator = \"file\"\nmaterial = \"glass\"\nfile = \"nope.data\"\n",
      "file = \"nope.data\"", {"grains[1].file", "existing data file", "scen/nope.data"}));
  try {
    load_scenario("/nonexistent/dir/pour.toml");
    ADD_FAILURE() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/dir/pour.toml: cannot read"),
              std::string::npos)
        << e.what();
  }
}

// ---------------------------------------------------------------------------------------------
// Rolling resistance (contact/rolling.hpp): [contact] rolling and rolling_damping, and the
// rolling_friction of materials and material pairs.

// The base with rolling resistance on: glass and steel given a rolling friction, a pair
// override for glass on steel, and a damping other than the default.
const std::string kRolling = edit("friction = 0.5", "friction = 0.5\nrolling_friction = 0.2",
                                  edit("rigid = true", "rigid = true\nrolling_friction = 0.08")) +
                             R"(
[[material_pair]]
materials = ["glass", "steel"]
rolling_friction = 0.05

[contact]
rolling = "epsd"
rolling_damping = 0.4
)";

// Guards: the rolling keys land in the config, and through the builder in the world: the
// model, the pair table (a pair without override takes the smaller mu_r of its two materials,
// an override replaces it for its pair only) and the neighbour list's spring flag (so the
// lists carry springs from their first build). Values are copied: compared exactly.
TEST(ScenarioParse, ValidRollingResistance) {
  const ScenarioConfig cfg = parse_scenario(kRolling, kPath);
  EXPECT_EQ(cfg.contact.rolling, "epsd");
  EXPECT_EQ(cfg.contact.rolling_damping, 0.4);
  EXPECT_EQ(cfg.materials[0].material.rolling_friction, 0.2);
  EXPECT_EQ(cfg.materials[1].material.rolling_friction, 0.08);
  ASSERT_EQ(cfg.overrides.size(), 1u);
  EXPECT_EQ(cfg.overrides[0].rolling_friction, 0.05);
  EXPECT_FALSE(cfg.overrides[0].friction.has_value());

  World<3> w;
  build_model(cfg, w);
  EXPECT_EQ(w.model.rolling, RollingModel::kEpsd);
  EXPECT_EQ(w.model.rolling_damping, 0.4);
  EXPECT_TRUE(w.neighbors.rolling);
  const MaterialIndex glass = *w.materials.find("glass"), steel = *w.materials.find("steel");
  EXPECT_EQ(w.materials.pair(glass, glass).rolling_friction, 0.2);
  EXPECT_EQ(w.materials.pair(steel, steel).rolling_friction, 0.08);
  EXPECT_EQ(w.materials.pair(glass, steel).rolling_friction, 0.05);  // the override
  EXPECT_EQ(w.materials.pair(steel, glass).rolling_friction, 0.05);  // both ways round
  EXPECT_EQ(w.materials.pair(glass, steel).friction, 0.0);  // min(0.5, 0), the override has none

  // Without the override the pair mixes to min(0.2, 0.08); the damping defaults to 0.3.
  std::string text = kRolling;
  text.replace(text.find("[[material_pair]]"),
               text.find("[contact]") - text.find("[[material_pair]]"), "");
  text.replace(text.find("rolling_damping = 0.4\n"), 22, "");
  const ScenarioConfig mixed = parse_scenario(text, kPath);
  EXPECT_EQ(mixed.contact.rolling_damping, 0.3);
  World<3> wm;
  build_model(mixed, wm);
  EXPECT_EQ(wm.model.rolling_damping, 0.3);
  EXPECT_EQ(
      wm.materials.pair(*wm.materials.find("glass"), *wm.materials.find("steel")).rolling_friction,
      0.08);

  // No [contact] rolling: none, the lists carry no springs; an explicit zero rolling friction
  // is accepted without the sub-model (it asks for nothing).
  const ScenarioConfig plain =
      parse_scenario(edit("friction = 0.5", "friction = 0.5\nrolling_friction = 0"), kPath);
  EXPECT_EQ(plain.contact.rolling, "none");
  World<3> wp;
  build_model(plain, wp);
  EXPECT_EQ(wp.model.rolling, RollingModel::kNone);
  EXPECT_FALSE(wp.neighbors.rolling);
}

// Guards: a rolling friction > 0 without the rolling sub-model would be silently ignored: it
// is refused where it is written, for a material and for a material pair; negative is refused
// whatever the sub-model.
TEST(ScenarioParse, RollingFrictionNeedsTheRollingModel) {
  std::string text = edit("friction = 0.5", "friction = 0.5\nrolling_friction = 0.1");
  EXPECT_TRUE(
      FailsAt(text, line_of(text, "rolling_friction"),
              {"material[0].rolling_friction = 0.1", "0 or absent", "contact.rolling = \"epsd\""}));
  EXPECT_TRUE(RejectsAppended(
      "[[material_pair]]\nmaterials = [\"glass\", \"steel\"]\nrolling_friction = 0.2\n",
      "rolling_friction",
      {"material_pair[0].rolling_friction = 0.2", "contact.rolling = \"epsd\""}));
  // rolling = "none" written out is the same as absent.
  EXPECT_TRUE(RejectsAppended(
      "[contact]\nrolling = \"none\"\n[[material_pair]]\nmaterials = [\"glass\", \"steel\"]\n"
      "rolling_friction = 0.2\n",
      "rolling_friction", {"material_pair[0].rolling_friction", "contact.rolling = \"epsd\""}));
  text = edit("rolling_friction = 0.2", "rolling_friction = -0.1", kRolling);
  EXPECT_TRUE(FailsAt(text, line_of(text, "rolling_friction = -0.1"),
                      {"material[0].rolling_friction", ">= 0"}));
  text = edit("rolling_friction = 0.05", "rolling_friction = -0.05", kRolling);
  EXPECT_TRUE(FailsAt(text, line_of(text, "rolling_friction = -0.05"),
                      {"material_pair[0].rolling_friction", ">= 0"}));
}

// Guards: cd.overlap_recovery is a share of an overlap, in [0, 1] (both ends allowed).
TEST(ScenarioParse, OverlapRecoveryIsAShare) {
  const std::string cd = edit("seed = 7", "seed = 7\nsolver = \"cd\"");
  for (const char* bad : {"1.5", "-0.1"}) {
    const std::string text = cd + "[cd]\noverlap_recovery = " + bad + "\n";
    EXPECT_TRUE(FailsAt(text, line_of(text, "overlap_recovery"),
                        {std::string("cd.overlap_recovery = ") + bad, "a number in [0, 1]"}));
  }
  for (const char* ok : {"0", "1", "0.2"})
    EXPECT_NO_THROW(parse_scenario(cd + "[cd]\noverlap_recovery = " + ok + "\n", kPath)) << ok;
  EXPECT_EQ(parse_scenario(cd + "[cd]\noverlap_recovery = 0.2\n", kPath).cd.overlap_recovery, 0.2);
}

// Guards: rolling_damping only with rolling = "epsd", and within [0, 1] (a fraction of
// critical damping); the sub-model's name is one of the registry's.
TEST(ScenarioParse, RollingDampingAndChoice) {
  EXPECT_TRUE(RejectsAppended("[contact]\nrolling_damping = 0.5\n", "rolling_damping",
                              {"contact.rolling_damping", "does not apply", "rolling = \"epsd\""}));
  EXPECT_TRUE(RejectsAppended("[contact]\nrolling = \"none\"\nrolling_damping = 0.5\n",
                              "rolling_damping", {"contact.rolling_damping", "does not apply"}));
  for (const char* bad : {"1.5", "-0.1"}) {
    const std::string text =
        edit("rolling_damping = 0.4", std::string("rolling_damping = ") + bad, kRolling);
    EXPECT_TRUE(FailsAt(text, line_of(text, "rolling_damping"),
                        {std::string("contact.rolling_damping = ") + bad, "a number in [0, 1]"}));
  }
  for (const char* ok : {"0", "1"}) {  // both ends are allowed
    const std::string text =
        edit("rolling_damping = 0.4", std::string("rolling_damping = ") + ok, kRolling);
    EXPECT_EQ(parse_scenario(text, kPath).contact.rolling_damping, std::stod(ok));
  }
  const std::string text = edit("rolling = \"epsd\"", "rolling = \"coulomb\"", kRolling);
  EXPECT_TRUE(
      FailsAt(text, line_of(text, "coulomb"), {"contact.rolling", "one of", "\"none\", \"epsd\""}));
}

// Guards: under contact dynamics the rolling couple of rigid grains has no spring, so
// rolling_damping is refused there (naming the solver), and epsd without it parses; rolling
// resistance is not combined with capillary cohesion yet: refused at contact.rolling.
TEST(ScenarioParse, RollingWithContactDynamicsAndCohesion) {
  std::string text = edit("seed = 7", "seed = 7\nsolver = \"cd\"", kRolling);
  EXPECT_TRUE(FailsAt(text, line_of(text, "rolling_damping"),
                      {"contact.rolling_damping", "does not apply", "solver = \"cd\""}));
  text = edit("rolling_damping = 0.4\n", "", text);
  const ScenarioConfig cd = parse_scenario(text, kPath);
  EXPECT_EQ(cd.sim.solver, "cd");
  EXPECT_EQ(cd.contact.rolling, "epsd");
  EXPECT_EQ(cd.materials[0].material.rolling_friction, 0.2);
  text = edit("rolling = \"epsd\"", "rolling = \"epsd\"\ncohesion = \"capillary\"", kRolling);
  EXPECT_TRUE(FailsAt(text, line_of(text, "rolling = \"epsd\""),
                      {"contact.rolling = \"epsd\"", "cohesion = \"capillary\""}));
}

}  // namespace
}  // namespace sable
