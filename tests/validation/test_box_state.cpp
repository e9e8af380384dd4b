// What a stage of a sample in a box reports (series.csv box columns, loading/box_state.hpp),
// checked against hand computation on small runs, and stress-controlled walls released to
// 0 Pa (p_m = 0 in Richefeu et al. 2009).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>

#include "../unit/run_helpers.hpp"
#include "sable/core/error.hpp"
#include "sable/io/snapshot.hpp"
#include "sable/loading/box_state.hpp"
#include "sable/loading/servo.hpp"
#include "sable/scenario/build.hpp"

namespace fs = std::filesystem;
using namespace sable;

namespace {

// 4 x 4 x 4 spheres of radius 1 mm on a cubic lattice of pitch 2 mm, touching without overlap
// (no force anywhere), in a box 8 x 8 x 12 mm whose lid comes down at 0.01 m/s for 1000 steps
// of 1 us: 10 um in all, far from the grains (a 4 mm gap), so nothing but the lid moves.
std::string lid_run(const std::string& out) {
  std::ostringstream s;
  s << "[simulation]\ndimension = 3\ndt = 1e-6\n[domain]\nlo = [0, 0, 0]\nhi = [0.008, 0.008, "
       "0.012]\n[[material]]\nname = \"g\"\ndensity = 2500.0\nyoung = 1e8\npoisson = 0.3\n"
    << "restitution = 0.3\nfriction = 0.4\n[[grains]]\ngenerator = \"lattice\"\nmaterial = "
       "\"g\"\nradius = 1e-3\nspacing = 2e-3\ncount = 64\n"
    << "region = { box = { lo = [0, 0, 0], hi = [0.008, 0.008, 0.008] } }\n"
    << "[[wall]]\nname = \"box\"\ntype = \"box\"\nmaterial = \"g\"\nlo = [0, 0, 0]\n"
    << "hi = [0.008, 0.008, 0.012]\n[[stage]]\nname = \"lid\"\nsteps = 1000\n"
    << "wall_velocity = { \"box.zhi\" = [0, 0, -0.01] }\n"
    << "[output]\ndir = \"" << out << "\"\ncsv_interval = 100\nsnapshot_interval = 500\n"
    << "vtk_interval = 0\nlog_interval = 0\nvtk_contacts = false\n";
  return s.str();
}

// The box columns of series.csv against hand computation. series.csv holds 10 significant
// digits, so values of order 1 are compared to 1e-9 relative (the format's resolution) and the
// strain, of order 1e-3, to 1e-12 absolute (its last digit is 1e-13; the lid's position
// accumulates 1000 additions of 1e-8 m with a rounding of ~1e-18 m each, 1e-13 in strain).
TEST(BoxState, SeriesColumnsMatchHandComputation) {
  const fs::path dir = fs::temp_directory_path() / "sable_test_box_lid";
  fs::remove_all(dir);
  sable::test::run_text(lid_run(dir.string()), {"", true, 1});
  auto c = sable::test::read_csv_columns(dir / "series.csv");
  ASSERT_EQ(c["step"].size(), 11u);  // step 0, then every 100 steps
  const double v = 0.01, dt = 1e-6, l0 = 0.012, grains = 64 * 4.0 / 3.0 * std::numbers::pi * 1e-9;
  for (std::size_t k = 0; k < c["step"].size(); ++k) {
    const double t = c["step"][k] * dt, lz = l0 - v * t;
    EXPECT_NEAR(c["strain_zz"][k], v * t / l0, 1e-12) << "step " << c["step"][k];
    EXPECT_EQ(c["strain_xx"][k], 0.0);
    EXPECT_EQ(c["strain_yy"][k], 0.0);
    EXPECT_NEAR(c["box_zhi_m"][k], lz, 1e-9 * lz);
    EXPECT_NEAR(c["solid_fraction"][k], grains / (0.008 * 0.008 * lz), 1e-9);
    for (const char* s : {"sigma_xx_Pa", "sigma_yy_Pa", "sigma_zz_Pa"}) EXPECT_EQ(c[s][k], 0.0);
  }
  EXPECT_NEAR(c["strain_zz"].back(), 1e-5 / 0.012, 1e-12);  // v t / L after 1000 steps
  fs::remove_all(dir);
}

// The strain reference survives a resume: it is the box the scenario builds, recomputed, so a
// run resumed at step 500 rewrites rows 600-1000 of series.csv identically (same text).
TEST(BoxState, ResumedRunReportsTheSameStrain) {
  const fs::path dir = fs::temp_directory_path() / "sable_test_box_resume";
  fs::remove_all(dir);
  const std::string text = lid_run(dir.string());
  sable::test::run_text(text, {"", true, 1});
  const std::string full = sable::test::slurp(dir / "series.csv");
  sable::test::run_text(
      text, {(dir / "snapshots" / "step_0000000500.h5").string(), true, 1, false, true});
  EXPECT_EQ(sable::test::slurp(dir / "series.csv"), full);
  fs::remove_all(dir);
}

// A loose 3D sample (250 grains) compacted to 1000 Pa, then released: wall_stress = 0 with
// stress_scale = 1000 Pa and stress_tolerance = 0.01. The release stage ends before max_steps,
// every wall then carries less than 10 Pa (1 % of the 1000 Pa scale: the stage's own end
// criterion, checked independently on the snapshot; at rest means a translational kinetic
// energy below 1e-8 J, since a rattler may keep spinning), the walls have moved outward on every
// axis (the packing unloads elastically), and the mean stress per axis that series.csv reports
// is the walls' forces over the areas from its box columns, row by row (to 1e-8 relative: two
// 10-digit numbers divided).
TEST(ServoZeroTarget, DrySampleReleasedToZeroPressure) {
  const fs::path dir = fs::temp_directory_path() / "sable_test_box_release";
  fs::remove_all(dir);
  std::ostringstream s;
  s << "[simulation]\ndimension = 3\nseed = 3\n[domain]\nlo = [0, 0, 0]\nhi = [0.02, 0.02, 0.02]\n"
    << "[[material]]\nname = \"g\"\ndensity = 2500.0\nyoung = 1e8\npoisson = 0.3\n"
    << "restitution = 0.3\nfriction = 0.3\n[[grains]]\ngenerator = \"random\"\nmaterial = \"g\"\n"
    << "radius = { distribution = \"uniform\", mean = 1e-3, spread = 0.2 }\n"
    << "region = { box = { lo = [0, 0, 0], hi = [0.02, 0.02, 0.02] } }\ncount = 250\n"
    << "[[wall]]\nname = \"box\"\ntype = \"box\"\nmaterial = \"g\"\nlo = [0, 0, 0]\n"
    << "hi = [0.02, 0.02, 0.02]\n";
  for (const char* stage : {"compact", "release"})
    s << "[[stage]]\nname = \"" << stage
      << "\"\nwall_stress = { box = " << (stage[0] == 'c' ? "1000.0" : "0.0")
      << " }\nservo_max_velocity = 0.05\n"
      << "stress_scale = 1000.0\nkinetic_energy_below = 1e-8\nkinetic_energy_of = "
      << "\"translation\"\nstress_tolerance = 0.01\n"
      << "max_steps = 400000\ncheck_interval = 500\n";
  s << "[output]\ndir = \"" << dir.string() << "\"\ncsv_interval = 500\nlog_interval = 0\n"
    << "vtk_interval = 0\nvtk_contacts = false\n";
  const std::string text = s.str();
  sable::test::run_text(text, {"", true, 1});
  const ScenarioConfig cfg = parse_scenario(text, "test.toml");
  World<3> before, after;
  build_model(cfg, before);
  build_model(cfg, after);
  const RunPosition p1 = load_snapshot((dir / "snapshots" / "end_of_stage_1.h5").string(), before);
  const RunPosition p2 = load_snapshot((dir / "snapshots" / "end_of_stage_2.h5").string(), after);
  EXPECT_LT(p1.stage_step, 400000u) << "compaction did not reach equilibrium";
  EXPECT_LT(p2.stage_step, 400000u) << "release did not reach equilibrium";
  for (std::size_t k = 0; k < 6; ++k) {
    EXPECT_NEAR(wall_normal_stress(before, k), 1000.0, 10.0) << before.walls[k].name;
    EXPECT_LT(std::abs(wall_normal_stress(after, k)), 10.0) << after.walls[k].name;
  }
  const auto b1 = measure_box(before), b2 = measure_box(after);
  for (int d = 0; d < 3; ++d) EXPECT_GT(b2->extent()[d], b1->extent()[d]) << "axis " << d;
  auto c = sable::test::read_csv_columns(dir / "series.csv");
  const char* ax[] = {"x", "y", "z"};
  for (std::size_t k = 0; k < c["step"].size(); ++k)
    for (int d = 0; d < 3; ++d) {
      auto len = [&](int e) {
        return c[fmt::format("box_{}hi_m", ax[e])][k] - c[fmt::format("box_{}lo_m", ax[e])][k];
      };
      const double area = len((d + 1) % 3) * len((d + 2) % 3);
      const double lo = c[fmt::format("wall_box.{}lo_f{}_N", ax[d], ax[d])][k];  // normal +e_d
      const double hi = c[fmt::format("wall_box.{}hi_f{}_N", ax[d], ax[d])][k];  // normal -e_d
      const double expected = 0.5 * (-lo + hi) / area;
      EXPECT_NEAR(c[fmt::format("sigma_{0}{0}_Pa", ax[d])][k], expected,
                  1e-8 * std::max(std::abs(expected), 1.0))
          << "step " << c["step"][k];
    }
  fs::remove_all(dir);
}

// Scenario errors around zero targets name the file, the stage's line and the key.
TEST(ServoZeroTarget, BadKeysAreRefused) {
  const std::string head =
      "[simulation]\ndimension = 2\nthickness = 0.002\n[domain]\nlo = [0, 0]\nhi = [0.04, 0.04]\n"
      "[[material]]\nname = \"g\"\ndensity = 2500.0\nyoung = 1e8\npoisson = 0.3\n"
      "[[wall]]\nname = \"box\"\ntype = \"box\"\nmaterial = \"g\"\nlo = [0, 0]\nhi = [0.04, "
      "0.04]\n[[stage]]\n";  // the stage table opens on line 18
  auto message = [&](const std::string& stage) {
    try {
      parse_scenario(head + stage, "test.toml");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string until = "kinetic_energy_below = 1e-8\nmax_steps = 10\n";
  // A 0 Pa target with a relative tolerance and nothing it is relative to.
  std::string m = message(
      "wall_stress = { box = 0.0 }\nservo_max_velocity = 0.05\n"
      "servo_gain = 1e-4\nstress_tolerance = 0.01\n" +
      until);
  EXPECT_NE(m.find("test.toml:18:"), std::string::npos) << m;
  EXPECT_NE(m.find("stage[0].stress_scale"), std::string::npos) << m;
  // Every target 0 and no gain: the default gain needs the scale.
  m = message("wall_stress = { box = 0.0 }\nservo_max_velocity = 0.05\nsteps = 10\n");
  EXPECT_NE(m.find("test.toml:18:"), std::string::npos) << m;
  EXPECT_NE(m.find("stress_scale"), std::string::npos) << m;
  EXPECT_NE(m.find("servo_gain"), std::string::npos) << m;
  // A scale must be a positive stress, and only where walls are stress-controlled.
  m = message(
      "wall_stress = { box = 0.0 }\nservo_max_velocity = 0.05\nstress_scale = -1.0\n"
      "steps = 10\n");
  EXPECT_NE(m.find("stress_scale"), std::string::npos) << m;
  EXPECT_NE(m.find("test.toml:21:"), std::string::npos) << m;
  m = message("stress_scale = 100.0\nsteps = 10\n");
  EXPECT_NE(m.find("does not apply"), std::string::npos) << m;
  // Valid: a zero target with its scale; and mixed targets without one (no tolerance).
  EXPECT_EQ(message("wall_stress = { box = 0.0 }\nservo_max_velocity = 0.05\nstress_scale = "
                    "100.0\nstress_tolerance = 0.01\n" +
                    until),
            "no error");
  EXPECT_EQ(message("wall_stress = { \"box.xlo\" = 0.0, \"box.ylo\" = 100.0 }\n"
                    "servo_max_velocity = 0.05\nsteps = 10\n"),
            "no error");
}

}  // namespace
