// Random polyhedra from a scenario (tests/data/polyhedra_fall.toml), run end to end by
// contact dynamics: snapshots at the end of each stage keep the grains' shapes, and a resume
// from the first ends on the uninterrupted run's state hash, to the bit; DEM likewise, with
// the linear law it needs (a Hertz law is refused before anything runs).
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "run_helpers.hpp"
#include "sable/io/snapshot.hpp"
#include "sable/scenario/build.hpp"
#include "sable/scenario/config.hpp"
#include "sable/scenario/runner.hpp"
#include "sable/world/state_hash.hpp"

namespace sable {
namespace {

namespace fs = std::filesystem;

const std::string kScenario = std::string(SABLE_TEST_DATA) + "/polyhedra_fall.toml";

RunResult run(const std::string& out, const std::string& resume = "") {
  RunOptions opt;
  std::ostringstream log;
  opt.log = &log;
  opt.live_progress = false;
  opt.out_dir = out;
  opt.resume = resume;
  return run_scenario(load_scenario(kScenario), opt);
}

// The grains a snapshot holds, loaded into the scenario's world as a resume loads them.
World<3> loaded(const fs::path& snapshot) {
  World<3> w;
  build_model(load_scenario(kScenario), w);
  load_snapshot(snapshot.string(), w);
  return w;
}

// Exact comparisons: a resumed run repeats the same operations on the same bits. The box
// holds every centroid (strictly inside: each grain's bounding sphere is at least 0.8 mm
// across and rests on or above the floor).
TEST(RunPolyhedra, FallsAndResumesBitIdentical) {
  const fs::path dir =
      fs::temp_directory_path() / ("sable_run_polyhedra_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const RunResult full = run((dir / "full").string());
  EXPECT_EQ(full.steps, 400u);
  EXPECT_EQ(full.grains, 48u);
  const fs::path first = dir / "full" / "snapshots" / "end_of_stage_1.h5";
  const fs::path last = dir / "full" / "snapshots" / "end_of_stage_2.h5";
  ASSERT_TRUE(fs::exists(first));
  ASSERT_TRUE(fs::exists(last));
  const RunResult resumed = run((dir / "resumed").string(), first.string());
  EXPECT_EQ(resumed.steps, full.steps);
  EXPECT_EQ(resumed.state_hash, full.state_hash);
  const fs::path resumed_last = dir / "resumed" / "snapshots" / "end_of_stage_2.h5";
  EXPECT_EQ(read_snapshot_info(resumed_last.string()).state_hash,
            read_snapshot_info(last.string()).state_hash);
  const World<3> w = loaded(last);
  ASSERT_EQ(w.particles.size(), 48u);
  EXPECT_EQ(w.shapes.size(), 48u) << "one row per random polyhedron, kept by the snapshot";
  EXPECT_EQ(state_hash(w), full.state_hash);
  for (std::size_t k = 0; k < w.particles.size(); ++k) {
    EXPECT_TRUE(w.particles.polyhedron(k));
    for (int d = 0; d < 3; ++d) {
      EXPECT_GT(w.particles.x[k][d], 0.0) << k;
      EXPECT_LT(w.particles.x[k][d], d == 2 ? 0.03 : 0.012) << k;
    }
  }
  fs::remove_all(dir);
}

// The scenario's text for DEM (a linear law when `linear`, else the default Hertz law), written
// beside the test's outputs.
fs::path dem_scenario(const fs::path& dir, bool linear) {
  std::string text = test::slurp(kScenario);
  text.replace(text.find("solver = \"cd\""), 13, "solver = \"dem\"");
  text.replace(text.find("dt = 2e-4"), 9, "dt = 2e-6");
  text.replace(text.find("friction = 0.4"), 14, "friction = 0.4\nyoung = 5e7\npoisson = 0.3");
  text.erase(text.find("[cd]"), text.find("[[grains]]") - text.find("[cd]"));
  if (linear) text += "\n[contact]\nnormal = \"linear\"\nkn = 1e3\nkt = 800.0\n";
  fs::path scenario = dir / (linear ? "dem_linear.toml" : "dem_hertz.toml");
  std::ofstream(scenario) << text;
  return scenario;
}

// DEM steps polyhedra with the linear law (a spring per contact point: dem/polyhedral_dem.hpp):
// with the default Hertz law `sable check` and `sable run` stop at the `shape` key, exit 2,
// before a grain is made; with the linear law the run goes, and a resume from the end of the
// first stage ends on the same bits.
TEST(RunPolyhedra, DemTakesTheLinearLawAndResumesBitIdentical) {
  if (!fs::exists(SABLE_CLI)) GTEST_SKIP() << SABLE_CLI << " not built";
  const fs::path dir =
      fs::temp_directory_path() / ("sable_dem_polyhedra_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path hertz = dem_scenario(dir, false);
  const std::string text = test::slurp(hertz.string());
  const auto line =
      std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(text.find("shape = ")),
                 '\n') +
      1;
  const std::string message = fmt::format(
      "{}:{}:9: grains[0].shape: expected [contact] normal = \"linear\" with polyhedral grains",
      hertz.string(), line);
  for (const std::string& args :
       {"check " + hertz.string(), "run " + hertz.string() + " --out " + (dir / "out").string()}) {
    std::string out;
    EXPECT_EQ(test::run_cli(args, dir / "log.txt", out), 2) << args;
    EXPECT_NE(out.find(message), std::string::npos) << out;
  }
  EXPECT_FALSE(fs::exists(dir / "out")) << "nothing written";
  const fs::path linear = dem_scenario(dir, true);
  const auto run_dem = [&](const std::string& out, const std::string& resume) {
    RunOptions opt;
    std::ostringstream log;
    opt.log = &log;
    opt.live_progress = false;
    opt.out_dir = (dir / out).string();
    opt.resume = resume;
    return run_scenario(load_scenario(linear.string()), opt);
  };
  const RunResult full = run_dem("full", "");
  EXPECT_EQ(full.steps, 400u);
  const RunResult resumed =
      run_dem("resumed", (dir / "full" / "snapshots" / "end_of_stage_1.h5").string());
  EXPECT_EQ(resumed.state_hash, full.state_hash);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace sable
