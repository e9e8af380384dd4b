// Stage keys for reaching static equilibrium: background viscous damping and the
// translational kinetic-energy criterion.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <sstream>

#include "run_helpers.hpp"
#include "sable/core/error.hpp"
#include "sable/dem/dem_solver.hpp"
#include "sable/scenario/build.hpp"

using namespace sable;

namespace {

std::string lone_grain(const std::string& stage_keys, const std::string& solver = "dem") {
  std::ostringstream s;
  s << "[simulation]\ndimension = 3\ndt = 1e-4\nsolver = \"" << solver << "\"\n"
    << "[domain]\nlo = [0, 0, 0]\nhi = [1, 1, 1]\n"
    << "[[material]]\nname = \"g\"\ndensity = 2500.0\nyoung = 1e8\npoisson = 0.3\n"
    << "[[grains]]\ngenerator = \"list\"\nmaterial = \"g\"\nradius = 1e-3\n"
    << "positions = [[0.5, 0.5, 0.5]]\nvelocity = [0.1, -0.2, 0.05]\n"
    << "[[stage]]\n"
    << stage_keys;
  return s.str();
}

}  // namespace

// A free grain with no contact under damping rate nu: each half kick divides its velocities by
// 1 + nu h / 2 (the implicit update), so after N steps v = v0 (1 + nu h / 2)^(-2N), close to
// v0 exp(-nu t). Checked to 1e-12 relative (N = 1000 roundings), translation and rotation.
TEST(ViscousDamping, FreeGrainDecaysAsTheImplicitUpdateSays) {
  const ScenarioConfig cfg =
      parse_scenario(lone_grain("steps = 1000\nviscous_damping = 5.0\n"), "d.toml");
  EXPECT_EQ(cfg.stages[0].viscous_damping, 5.0);
  World<3> w;
  build_model(cfg, w);
  build_grains(cfg, w);
  w.viscous_rate = cfg.stages[0].viscous_damping;
  w.particles.omega[0] = Eigen::Vector3d(30.0, 0.0, -10.0);
  const Eigen::Vector3d v0 = w.particles.v[0], w0 = w.particles.omega[0];
  DemSolver<3> dem(w);
  dem.initialize();
  for (int k = 0; k < 1000; ++k) dem.step();
  const double factor = std::pow(1.0 + 5.0 * 0.5e-4, -2000.0);
  EXPECT_NEAR((w.particles.v[0] - factor * v0).norm(), 0.0, 1e-12 * v0.norm());
  EXPECT_NEAR((w.particles.omega[0] - factor * w0).norm(), 0.0, 1e-12 * w0.norm());
  EXPECT_NEAR(factor, std::exp(-5.0 * 0.1), 1e-4);  // the implicit update tracks exp(-nu t)
}

// Without the key nothing changes: the grain keeps its velocity exactly (no gravity, no contact).
TEST(ViscousDamping, OffByDefault) {
  const ScenarioConfig cfg = parse_scenario(lone_grain("steps = 10\n"), "d.toml");
  EXPECT_EQ(cfg.stages[0].viscous_damping, 0.0);
  World<3> w;
  build_model(cfg, w);
  build_grains(cfg, w);
  const Eigen::Vector3d v0 = w.particles.v[0];
  DemSolver<3> dem(w);
  dem.initialize();
  for (int k = 0; k < 10; ++k) dem.step();
  EXPECT_EQ(w.particles.v[0], v0);
}

TEST(StageKeys, EquilibriumKeysAreChecked) {
  const auto fails = [](const std::string& text, const std::string& needle) {
    try {
      parse_scenario(text, "k.toml");
      ADD_FAILURE() << "expected an InputError mentioning " << needle;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("k.toml:"), std::string::npos) << e.what();
    }
  };
  fails(lone_grain("steps = 10\nviscous_damping = -1.0\n"), "viscous_damping");
  fails(lone_grain("steps = 10\nviscous_damping = 1.0\n", "cd"), "viscous_damping");
  fails(lone_grain("steps = 10\nkinetic_energy_of = \"translation\"\n"), "kinetic_energy_of");
  fails(lone_grain("kinetic_energy_below = 1e-9\nmax_steps = 10\nkinetic_energy_of = \"spin\"\n"),
        "kinetic_energy_of");
  const ScenarioConfig ok =
      parse_scenario(lone_grain("kinetic_energy_below = 1e-9\nmax_steps = 10\nkinetic_energy_of = "
                                "\"translation\"\n"),
                     "k.toml");
  EXPECT_TRUE(ok.stages[0].translation_only);
}

// The translational energy leaves out the spin: a grain spinning in place has none.
TEST(StageKeys, TranslationalEnergyLeavesOutRotation) {
  const ScenarioConfig cfg = parse_scenario(lone_grain("steps = 1\n"), "d.toml");
  World<3> w;
  build_model(cfg, w);
  build_grains(cfg, w);
  w.particles.v[0].setZero();
  w.particles.omega[0] = Eigen::Vector3d(0.0, 0.0, 50.0);
  const double inertia = 0.4 * w.particles.mass[0] * 1e-6;
  EXPECT_NEAR(kinetic_energy(w), 0.5 * inertia * 2500.0, 1e-12 * inertia * 2500.0);
  EXPECT_EQ(kinetic_energy(w, true), 0.0);
}

// A run resumed by another scenario takes that scenario's time step (a DEM state continued by
// CD, say, with its own dt), and says so: 100 steps at 1e-6 s then 50 at 2e-6 s end at
// t = 2e-4 s (to rounding of 150 additions).
TEST(StageKeys, ResumeTakesTheScenarioTimeStep) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "sable_test_resume_dt";
  fs::remove_all(dir);
  auto text = [&](const std::string& dt, const std::string& stages) {
    return "[simulation]\ndimension = 3\ndt = " + dt +
           "\n[domain]\nlo = [0, 0, 0]\nhi = [1, 1, 1]\n"
           "[[material]]\nname = \"g\"\ndensity = 2500.0\nyoung = 1e8\npoisson = 0.3\n"
           "[[grains]]\ngenerator = \"list\"\nmaterial = \"g\"\nradius = 1e-3\n"
           "positions = [[0.5, 0.5, 0.5]]\nvelocity = [0.1, 0, 0]\n" +
           stages + "[output]\ndir = \"" + dir.string() + "\"\nlog_interval = 0\n";
  };
  test::run_text(text("1e-6", "[[stage]]\nsteps = 100\n"));
  test::QuietRun resume;
  resume.resume = (dir / "snapshots" / "end_of_stage_1.h5").string();
  resume.outputs = false;
  resume.accept_changes = true;  // simulation.dt differs: a change of physics, accepted
  const auto r =
      test::run_text(text("2e-6", "[[stage]]\nsteps = 100\n[[stage]]\nsteps = 50\n"), resume);
  EXPECT_EQ(r.steps, 150u);
  EXPECT_NEAR(r.time, 100 * 1e-6 + 50 * 2e-6, 1e-16);
  fs::remove_all(dir);
}
