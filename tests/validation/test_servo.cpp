// Stress-controlled walls (loading/servo.hpp): isotropic compaction of a loose 2D and 3D
// packing to a confining pressure, "until equilibrium"; and the scenario errors around it.
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>

#include "../unit/run_helpers.hpp"
#include "sable/core/error.hpp"
#include "sable/io/snapshot.hpp"
#include "sable/loading/servo.hpp"
#include "sable/scenario/build.hpp"
#include "servo_helpers.hpp"

namespace fs = std::filesystem;
using namespace sable;

namespace {

std::string compaction(int dim, const std::string& out, double pressure,
                       const std::string& extra_stage_keys = "") {
  sable::test::Compaction c;
  c.dim = dim;
  c.out = out;
  c.pressure = pressure;
  c.extra_stage_keys = extra_stage_keys;
  return sable::test::compaction_text(c);
}

// Every wall of the box ends within 2 % of the target pressure (the bound; the stage
// stops at 1 %), with the grains at rest (translational kinetic energy < 1e-8 J: a rattler
// that leaves its last contact spinning keeps its spin, nothing brakes a free rotation, so
// whether the total would fall below the bound depends on round-off of the trajectory), and
// the loose packing was compacted (solid fraction, servo_helpers.hpp). The stress is measured
// from the contact forces and the box's extent, not by the servo's own functions. Checked on
// the end-of-stage snapshot.
TEST(ServoWalls, IsotropicCompactionReachesThePressure) {
  for (int dim : {2, 3}) {
    SCOPED_TRACE(dim);
    const fs::path dir = fs::temp_directory_path() / ("sable_test_servo_" + std::to_string(dim));
    fs::remove_all(dir);
    const std::string text = compaction(dim, dir.string(), 1000.0);
    const auto r = sable::test::run_text(text);
    EXPECT_LT(r.steps, 400000u) << "equilibrium not reached";
    if (dim == 2)
      sable::test::expect_compacted<2>(text, dir, 1000.0, 0.02, 0.04,
                                       sable::test::kMinSolidFraction2D);
    else
      sable::test::expect_compacted<3>(text, dir, 1000.0, 0.02, 0.02,
                                       sable::test::kMinSolidFraction3D);
    fs::remove_all(dir);
  }
}

// A run resumed from a snapshot taken in the middle of a stress-controlled stage ends
// bit-identical to the uninterrupted run: the controller has no state of its own beyond the
// walls' positions, velocities and forces, which snapshots carry.
TEST(ServoWalls, ResumeMidStageIsBitIdentical) {
  const fs::path dir = fs::temp_directory_path() / "sable_test_servo_resume";
  fs::remove_all(dir);
  std::string text = compaction(2, dir.string(), 1000.0);
  text.replace(text.find("csv_interval = 0"), 16, "csv_interval = 0\nsnapshot_interval = 2000");
  const auto full = sable::test::run_text(text);
  ASSERT_GT(full.steps, 4000u);
  const auto resumed = sable::test::run_text(
      text, {(dir / "snapshots" / "step_0000002000.h5").string(), true, 0, false, true});
  EXPECT_EQ(resumed.steps, full.steps);
  EXPECT_EQ(resumed.state_hash, full.state_hash);
  fs::remove_all(dir);
}

// Triaxial compression after the isotropic compaction (3D): the top and bottom walls close at
// an imposed speed while the four lateral walls are held at p_m by the servo. The axial strain
// rate measured from the walls' positions is the imposed one, and the lateral stresses stay
// within 5 % of p_m at every snapshot of the compression (the bound), here over about
// 1 % of axial strain at 0.1 /s: faster compressions outrun the stability-limited servo.
TEST(ServoWalls, TriaxialKeepsTheLateralStress) {
  const fs::path dir = fs::temp_directory_path() / "sable_test_servo_triaxial";
  fs::remove_all(dir);
  std::string text = compaction(3, dir.string(), 1000.0);
  const double v = 0.001;  // m/s each: an axial strain rate of about 0.1 /s
  text.replace(text.find("[output]"), 8,
               "[[stage]]\nname = \"triaxial\"\nsteps = 20000\nwall_velocity = { "
               "\"box.zhi\" = [0, 0, -0.001], \"box.zlo\" = [0, 0, 0.001] }\n"
               "wall_stress = { \"box.xlo\" = 1000.0, \"box.xhi\" = 1000.0, "
               "\"box.ylo\" = 1000.0, \"box.yhi\" = 1000.0 }\nservo_max_velocity = 0.05\n"
               "[output]\nsnapshot_interval = 5000");
  sable::test::run_text(text);
  const ScenarioConfig cfg = parse_scenario(text, "test.toml");
  double z_before = 0.0, t_before = 0.0;
  int checked = 0;
  for (const char* name : {"end_of_stage_1.h5", "end_of_stage_2.h5"}) {
    World<3> w;
    build_model(cfg, w);
    load_snapshot((dir / "snapshots" / name).string(), w);
    const double height = w.walls[5].point.z() - w.walls[4].point.z();  // zhi - zlo
    if (std::string(name) == "end_of_stage_1.h5") {
      z_before = height;
      t_before = w.time;
      continue;
    }
    // Axial strain rate: the walls move exactly as prescribed (round-off over 20,000 steps).
    const double rate = (z_before - height) / (w.time - t_before) / z_before;
    EXPECT_NEAR(rate, 2.0 * v / z_before, 1e-9 * rate);
    ++checked;
  }
  EXPECT_EQ(checked, 1);
  for (const auto& e : fs::directory_iterator(dir / "snapshots")) {
    World<3> w;
    build_model(cfg, w);
    const RunPosition pos = load_snapshot(e.path().string(), w);
    if (pos.stage != 1 || pos.stage_step < 1000) continue;  // compression snapshots only
    for (std::size_t k = 0; k < 4; ++k)
      EXPECT_NEAR(wall_normal_stress(w, k), 1000.0, 50.0) << w.walls[k].name << " " << e.path();
    ++checked;
  }
  EXPECT_GE(checked, 4);
  fs::remove_all(dir);
}

// Scenario errors: an unknown wall, a missing speed limit, "until equilibrium" without a
// kinetic-energy bound, and a key of the other solver's stress control (DEM's servo_gain with
// contact dynamics, CD's servo_wall_mass with DEM) each stop with a message.
TEST(ServoWalls, BadScenariosAreRefused) {
  auto message = [](const std::string& text) {
    try {
      sable::test::run_text(text, {"", false, 0});
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  std::string t = compaction(2, "unused", 1000.0);
  std::string bad = t;
  bad.replace(bad.find("wall_stress = { box"), 19, "wall_stress = { lid");
  EXPECT_NE(message(bad).find("unknown wall"), std::string::npos);
  bad = t;
  bad.replace(bad.find("servo_max_velocity = 0.05\n"), 26, "");
  EXPECT_NE(message(bad).find("servo_max_velocity"), std::string::npos);
  bad = t;
  bad.replace(bad.find("[simulation]\n"), 13, "[simulation]\nsolver = \"cd\"\ndt = 1e-4\n");
  bad.replace(bad.find("servo_max_velocity"), 0, "servo_gain = 1e-4\n");
  EXPECT_NE(message(bad).find("servo_gain does not apply with simulation.solver = \"cd\""),
            std::string::npos)
      << message(bad);
  bad = t;
  bad.replace(bad.find("servo_max_velocity"), 0, "servo_wall_mass = 0.01\n");
  EXPECT_NE(message(bad).find("servo_wall_mass does not apply with simulation.solver = \"dem\""),
            std::string::npos)
      << message(bad);
  bad = t;
  bad.replace(bad.find("kinetic_energy_below = 1e-8\n"), 28, "steps = 10\n");
  bad.replace(bad.find("kinetic_energy_of = \"translation\"\n"), 35, "");
  bad.replace(bad.find("max_steps = 400000\n"), 19, "");
  bad.replace(bad.find("check_interval = 500\n"), 21, "");
  EXPECT_NE(message(bad).find("stress_tolerance"), std::string::npos);
}

}  // namespace
