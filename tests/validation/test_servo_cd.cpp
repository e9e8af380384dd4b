// Stress-controlled walls with contact dynamics (loading/servo.hpp, cd/cd_solver.hpp): the walls
// are bodies under target * area, moved by the NLGS with the grains. Isotropic compaction of a
// loose packing to a confining pressure in 2D and 3D, a triaxial compression at constant
// lateral stress, and bit-identical results across thread counts and across a mid-stage resume.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "../unit/run_helpers.hpp"
#include "sable/io/snapshot.hpp"
#include "sable/loading/servo.hpp"
#include "sable/scenario/build.hpp"
#include "servo_helpers.hpp"

namespace fs = std::filesystem;
using namespace sable;

namespace {

// Rigid grains dissipate only through impacts and friction, so a rattler (a grain without
// contacts in its cage) keeps the spin of its last impact forever: in a 2D compaction like the
// one below, one kept spinning at 88 rad/s (2.5e-8 J) for 2,700 steps after the packing had
// settled. The kinetic-energy bound of an
// "until equilibrium" stage must leave room for a few such grains; it is set at about 1e-3 of
// the work p V the walls did. The walls' own equilibrium is what stress_tolerance (1 %) and
// expect_walls_at_rest check.

// 2D: 200 disks in a 4 cm box to 1000 Pa. h = 5e-4 s: at the 0.05 m/s speed cap a wall moves
// 2.5 % of a radius per step.
test::Compaction cd_2d(const std::string& out) {
  test::Compaction c;
  c.dim = 2;
  c.out = out;
  c.pressure = 1000.0;
  c.dt = 5e-4;
  c.max_steps = 10000;
  c.check_interval = 50;
  c.kinetic_energy_below = "1e-6";  // p V = 1.7e-3 J
  return c;
}

// 3D: 120 spheres in a 1.6 cm box to 100 Pa (small, to stay fast: while the packing jams or
// shears, a 3D NLGS step takes hundreds of sweeps over some 500 contacts). h = 1e-3 s: 5 % of a
// radius per step at the speed cap.
test::Compaction cd_3d(const std::string& out) {
  test::Compaction c;
  c.dim = 3;
  c.out = out;
  c.pressure = 100.0;
  c.dt = 1e-3;
  c.side = 0.016;
  c.count = 120;
  c.max_steps = 5000;
  c.check_interval = 50;
  c.kinetic_energy_below = "1e-7";  // p V = 1.2e-4 J
  return c;
}

// On the end-of-stage snapshot, every wall body moves slower than 1 % of its 0.05 m/s speed cap:
// it has stopped where the grains balance its force, it is not crossing the box.
template <int D>
void expect_walls_at_rest(const std::string& text, const fs::path& dir) {
  const ScenarioConfig cfg = parse_scenario(text, "test.toml");
  World<D> w;
  build_model(cfg, w);
  load_snapshot((dir / "snapshots" / "end_of_stage_1.h5").string(), w);
  for (const auto& wall : w.walls) EXPECT_LT(wall.velocity.norm(), 5e-4) << wall.name;
}

// Every wall within 2 % of the pressure on the end-of-stage snapshot (the bound; the
// stage itself stops at 1 %, with the kinetic energy below its bound), measured from the
// contact forces and the box's extent, and the packing compacted (expect_compacted). At rest a wall
// body's measured stress is its applied force / area: only the last step's change of the wall's
// velocity and the change of its area within the step separate them.
TEST(ServoCd, IsotropicCompaction2D) {
  const fs::path dir = fs::temp_directory_path() / "sable_test_servo_cd_2d";
  fs::remove_all(dir);
  const test::Compaction c = cd_2d(dir.string());
  const std::string text = test::compaction_text(c);
  const auto r = test::run_text(text);
  EXPECT_LT(r.steps, c.max_steps) << "equilibrium not reached";
  test::expect_compacted<2>(text, dir, c.pressure, 0.02, 0.04, sable::test::kMinSolidFraction2D);
  expect_walls_at_rest<2>(text, dir);
  fs::remove_all(dir);
}

TEST(ServoCd, IsotropicCompaction3D) {
  const fs::path dir = fs::temp_directory_path() / "sable_test_servo_cd_3d";
  fs::remove_all(dir);
  const test::Compaction c = cd_3d(dir.string());
  const std::string text = test::compaction_text(c);
  const auto r = test::run_text(text);
  EXPECT_LT(r.steps, c.max_steps) << "equilibrium not reached";
  test::expect_compacted<3>(text, dir, c.pressure, 0.02, c.side, sable::test::kMinSolidFraction3D);
  expect_walls_at_rest<3>(text, dir);
  fs::remove_all(dir);
}

// Triaxial compression after the isotropic compaction (3D): the top and bottom walls close at
// 0.5 mm/s each (an axial strain rate of about 0.1 /s, inertial number 1e-3: quasi-static)
// while the four lateral wall bodies are pushed at p_m = 100 Pa. Checked over 100 steps, about
// 1 % of axial strain.
TEST(ServoCd, TriaxialKeepsTheLateralStress) {
  const fs::path dir = fs::temp_directory_path() / "sable_test_servo_cd_triaxial";
  fs::remove_all(dir);
  test::Compaction c = cd_3d(dir.string());
  std::string text = test::compaction_text(c);
  const double v = 0.0005;
  text.replace(text.find("[output]"), 8,
               "[[stage]]\nname = \"triaxial\"\nsteps = 100\nwall_velocity = { "
               "\"box.zhi\" = [0, 0, -0.0005], \"box.zlo\" = [0, 0, 0.0005] }\n"
               "wall_stress = { \"box.xlo\" = 100.0, \"box.xhi\" = 100.0, "
               "\"box.ylo\" = 100.0, \"box.yhi\" = 100.0 }\nservo_max_velocity = 0.05\n"
               "[output]\nsnapshot_interval = 25");
  test::run_text(text);
  const ScenarioConfig cfg = parse_scenario(text, "test.toml");
  auto height = [&](const std::string& name, double& time) {
    World<3> w;
    build_model(cfg, w);
    load_snapshot((dir / "snapshots" / name).string(), w);
    time = w.time;
    return w.walls[5].point.z() - w.walls[4].point.z();  // zhi - zlo
  };
  double t0 = 0.0, t1 = 0.0;
  const double h0 = height("end_of_stage_1.h5", t0), h1 = height("end_of_stage_2.h5", t1);
  // Axial strain rate: kinematic walls move exactly as prescribed; the bound is round-off
  // over 100 position updates.
  const double rate = (h0 - h1) / (t1 - t0) / h0;
  EXPECT_NEAR(rate, 2.0 * v / h0, 1e-9 * rate);
  // Lateral stresses within 5 % of p_m (the bound) at every snapshot of the
  // compression after its first 25 steps (the walls' start from rest). What is measured is one
  // step's impulse / h, so the bound also covers the step-to-step fluctuation of a wall body
  // that follows a yielding packing (1.8 % at most at these snapshots).
  int checked = 0;
  for (const auto& e : fs::directory_iterator(dir / "snapshots")) {
    World<3> w;
    build_model(cfg, w);
    const RunPosition pos = load_snapshot(e.path().string(), w);
    if (pos.stage != 1 || pos.stage_step < 25) continue;
    for (std::size_t k = 0; k < 4; ++k)
      EXPECT_NEAR(wall_normal_stress(w, k), 100.0, 5.0) << w.walls[k].name << " " << e.path();
    ++checked;
  }
  EXPECT_GE(checked, 4);
  fs::remove_all(dir);
}

// The 2D compaction through its approach and jamming (the walls reach the grains near step
// 200, the stage ends at equilibrium at step 250; 300 steps at most), shuffled NLGS sweeps
// included: the state hash (every double of the grains, walls, contact lists and the RNG) is the
// same with 1 and 2 OpenMP threads. Exact equality: the NLGS sweep is sequential in a fixed
// (seeded) order, so nothing may depend on threads.
TEST(ServoCd, DeterministicAcrossThreads) {
  test::Compaction c = cd_2d("unused");
  c.max_steps = 300;
  const std::string text = test::compaction_text(c);
  const auto one = test::run_text(text, {"", false, 1});
  const auto two = test::run_text(text, {"", false, 2});
  EXPECT_EQ(one.steps, two.steps);
  EXPECT_EQ(one.state_hash, two.state_hash);
}

// Resuming from a snapshot in the middle of the stage (step 150: the walls moving at their
// speed cap, grains being pushed) ends bit-identical to the uninterrupted run: a wall body's
// only state is its velocity, which snapshots carry; its force and mass are recomputed from
// the walls' positions and the grains at each step. Exact equality of state hashes.
TEST(ServoCd, ResumeMidStageIsBitIdentical) {
  const fs::path dir = fs::temp_directory_path() / "sable_test_servo_cd_resume";
  fs::remove_all(dir);
  test::Compaction c = cd_2d(dir.string());
  c.max_steps = 300;
  std::string text = test::compaction_text(c);
  text.replace(text.find("csv_interval = 0"), 16, "csv_interval = 0\nsnapshot_interval = 150");
  const auto full = test::run_text(text);
  ASSERT_GT(full.steps, 150u);
  const auto resumed = test::run_text(
      text, {(dir / "snapshots" / "step_0000000150.h5").string(), true, 0, false, true});
  EXPECT_EQ(resumed.steps, full.steps);
  EXPECT_EQ(resumed.state_hash, full.state_hash);
  fs::remove_all(dir);
}

}  // namespace
