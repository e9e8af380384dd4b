// A tiny version of the rotating cylinder of Guillard, Forterre & Pouliquen (2015), written by
// the example's own generator (examples/rotating-cylinder/make_scenario.py: L = 6 d, filled to
// 2.5 L, ~3,000 grains, a tenth of a turn) and analysed by its own script (analyze_run.py):
// the torque balance between the cylinder, the container and the grains, and the drag
// bookkeeping F = 4 M / L against series.csv.
#include <gtest/gtest.h>

#include <unistd.h>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "../unit/run_helpers.hpp"
#include "sable/io/snapshot.hpp"
#include "sable/scenario/build.hpp"
#include "sable/scenario/config.hpp"
#include "sable/world/world.hpp"

namespace fs = std::filesystem;

namespace {

// The grains' angular momentum about the vertical axis through the origin (the container's
// axis): orbital plus spin.
double angular_momentum_z(const sable::World<3>& w) {
  const auto& p = w.particles;
  double lz = 0.0;
  for (std::size_t k = 0; k < p.size(); ++k) {
    lz += p.mass[k] * (p.x[k].x() * p.v[k].y() - p.x[k].y() * p.v[k].x());
    if (p.inv_inertia[k] > 0.0) lz += p.omega[k].z() / p.inv_inertia[k];
  }
  return lz;
}

double json_number(const std::string& text, const std::string& key) {
  const auto pos = text.find("\"" + key + "\":");
  if (pos == std::string::npos) throw std::runtime_error("no key " + key);
  return std::stod(text.substr(pos + key.size() + 3));
}

struct TinyRun {
  fs::path dir;
  std::string text;  // the scenario
};

// Written and run once for the file's tests.
const TinyRun& tiny_run() {
  static const TinyRun run = [] {
    TinyRun r;
    r.dir = fs::temp_directory_path() / ("sable-rotating-cylinder-" + std::to_string(::getpid()));
    fs::remove_all(r.dir);
    fs::create_directories(r.dir);
    const fs::path example = fs::path(SABLE_SOURCE_DIR) / "examples" / "rotating-cylinder";
    // A row of series.csv every step (rows-per-turn above the steps per turn), so that the
    // torque's time integral is the solver's own sum.
    const std::string make =
        "/usr/bin/python3 " + (example / "make_scenario.py").string() + " " +
        (r.dir / "scenario.toml").string() + " --out-dir " + (r.dir / "run").string() +
        " --length-d 6 --fill-L 2.5 --depth 1 --young 5e6 --turns 0.1 --inertial 0.05"
        " --dt-fraction 0.2 --rows-per-turn 1000000 --snapshots-per-turn 4 --pour-seconds 0.1"
        " > " +
        (r.dir / "make.log").string() + " 2>&1";
    if (std::system(make.c_str()) != 0) throw std::runtime_error("make_scenario.py failed");
    r.text = sable::test::slurp(r.dir / "scenario.toml");
    std::string output;
    const int rc = sable::test::run_cli("run " + (r.dir / "scenario.toml").string() + " --out " +
                                            (r.dir / "run").string() + " --threads 1",
                                        r.dir / "run.log", output);
    if (rc != 0) throw std::runtime_error("sable run failed: " + output);
    return r;
  }();
  return run;
}

// The tiny run's folder goes when the tests end (kept if one failed, to look at).
class RemoveTinyRun : public ::testing::Environment {
 public:
  void TearDown() override {
    const auto* unit = ::testing::UnitTest::GetInstance();
    const fs::path dir =
        fs::temp_directory_path() / ("sable-rotating-cylinder-" + std::to_string(::getpid()));
    if (unit->failed_test_count() == 0) fs::remove_all(dir);
  }
};
const auto* const kRemoveTinyRun = ::testing::AddGlobalTestEnvironment(new RemoveTinyRun);

}  // namespace

// Over the turning stage, the torque the grains exert on the cylinder, the container and the
// floor, integrated in time, equals minus the change of the grains' angular momentum about the
// axis (gravity, vertical, has no moment about it; grain-grain forces cancel in pairs at their
// common contact point). The run turns only a tenth of a turn, from a bed still settling, so
// the grains' angular momentum changes: it is included, from the two end-of-stage snapshots.
// Velocity Verlet changes the momentum by the trapezoid of the step torques, which the
// per-step rows give, so the balance closes to the rows' 10 significant digits (measured:
// 2e-12 of the integral of |M_cylinder|); the tolerance, 1e-8 of it, leaves room for the
// cancellation between the cylinder's and the walls' torques on another compiler or machine.
TEST(RotatingCylinder, TorqueOnCylinderBalancesContainerFloorAndGrains) {
  const TinyRun& r = tiny_run();
  const sable::ScenarioConfig cfg =
      sable::parse_scenario(r.text, (r.dir / "scenario.toml").string());
  sable::World<3> start, end;
  sable::build_model(cfg, start);
  sable::build_model(cfg, end);
  sable::load_snapshot((r.dir / "run" / "snapshots" / "end_of_stage_1.h5").string(), start);
  sable::load_snapshot((r.dir / "run" / "snapshots" / "end_of_stage_2.h5").string(), end);
  ASSERT_GT(start.particles.size(), 2000u);
  ASSERT_LT(start.particles.size(), 5000u);
  const auto cols = sable::test::read_csv_columns(r.dir / "run" / "series.csv");
  const auto& step = cols.at("step");
  const auto& cyl = cols.at("wall_cylinder_tz_Nm");
  const auto& cont = cols.at("wall_container_tz_Nm");
  const auto& floor = cols.at("wall_floor_tz_Nm");
  double integral = 0.0, cyl_abs = 0.0;
  std::size_t rows = 0;
  for (std::size_t k = 0; k < step.size(); ++k) {
    const auto s = static_cast<std::uint64_t>(step[k]);
    if (s < start.step || s > end.step) continue;
    const double weight = (s == start.step || s == end.step) ? 0.5 : 1.0;
    integral += weight * (cyl[k] + cont[k] + floor[k]) * end.dt;
    cyl_abs += weight * std::abs(cyl[k]) * end.dt;
    ++rows;
  }
  ASSERT_EQ(rows, end.step - start.step + 1) << "series.csv must have a row every step";
  ASSERT_GT(cyl_abs, 0.0);
  // The grains receive minus the torque they exert on the walls.
  const double dlz = angular_momentum_z(end) - angular_momentum_z(start);
  std::cout << "[ balance  ] (integral + dLz) / integral |M_cylinder| = "
            << (integral + dlz) / cyl_abs << "\n";
  EXPECT_NEAR(integral, -dlz, 1e-8 * cyl_abs)
      << "integral of the walls' torques " << integral << " N m s, grains' dLz " << dlz
      << ", integral of |M_cylinder| " << cyl_abs;
  // The cylinder resists the turning (omega > 0 about +z): its mean torque is negative.
  EXPECT_LT(cols.at("wall_cylinder_tz_Nm").back(), 0.0);
}

// The example's analysis (analyze_run.py) takes the drag as F = 4 M / L from series.csv's
// torque about the axis: its first half-turn (here the whole tenth of a turn) against the mean
// of -4 M / L over the rows after the turning began, computed here. Both are the same sum of
// the same printed numbers; 1e-9 relative allows for summation order only.
TEST(RotatingCylinder, DragIsFourTorquesOverLengthFromSeries) {
  const TinyRun& r = tiny_run();
  const std::string analyze =
      "/usr/bin/python3 " +
      (fs::path(SABLE_SOURCE_DIR) / "examples" / "rotating-cylinder" / "analyze_run.py").string() +
      " " + r.dir.string() + " --sable " + SABLE_CLI + " > " + (r.dir / "analysis.log").string() +
      " 2>&1";
  ASSERT_EQ(std::system(analyze.c_str()), 0) << sable::test::slurp(r.dir / "analysis.log");
  const std::string settings = sable::test::slurp(r.dir / "scenario.json");
  const std::string summary = sable::test::slurp(r.dir / "summary.json");
  const double length = json_number(settings, "L_m");
  const double t0 = json_number(summary, "turn_start_s");
  const auto cols = sable::test::read_csv_columns(r.dir / "run" / "series.csv");
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t k = 0; k < cols.at("time_s").size(); ++k) {
    if (cols.at("time_s")[k] <= t0) continue;
    sum += -4.0 * cols.at("wall_cylinder_tz_Nm")[k] / length;
    ++n;
  }
  ASSERT_GT(n, 100u);
  const double drag = sum / static_cast<double>(n);
  EXPECT_GT(drag, 0.0);
  EXPECT_NEAR(json_number(summary, "drag_first_half_turn_N"), drag, 1e-9 * drag);
  // A tenth of a turn holds no whole half-turn: the per-half-turn table has its header only.
  EXPECT_EQ(sable::test::slurp(r.dir / "drag_halfturns.csv"),
            "half_turn,t_start_s,t_end_s,rows,torque_Nm,torque_sd_Nm,drag_N\n");
}
