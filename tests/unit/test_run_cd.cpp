// Contact dynamics through the scenario runner: determinism with a seeded shuffled sweep
// order, and a bit-identical restart (the impulses that warm-start each step, and the RNG
// that shuffles the sweeps, travel in the snapshot). Exact comparisons of state hashes.
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>

#include "run_helpers.hpp"
#include "sable/scenario/config.hpp"
#include "sable/scenario/runner.hpp"

namespace fs = std::filesystem;

namespace {

std::string cd_scenario(int dim, std::uint64_t seed, const std::string& out) {
  const bool three = dim == 3;
  std::ostringstream s;
  s << "[simulation]\ndimension = " << dim << "\nsolver = \"cd\"\nseed = " << seed
    << "\ndt = 2e-4\ngravity = " << (three ? "[0, 0, -9.81]" : "[0, -9.81]") << "\n"
    << (three ? "" : "thickness = 0.002\n") << "[domain]\nlo = " << (three ? "[0, 0, 0]" : "[0, 0]")
    << "\nhi = " << (three ? "[0.012, 0.012, 0.03]" : "[0.02, 0.03]") << "\n"
    << "[[material]]\nname = \"g\"\ndensity = 2500.0\nfriction = 0.4\n"
    << "[cd]\nsweep = \"shuffled\"\ntolerance = 1e-6\nmax_iterations = 300\n"
    << "[[grains]]\ngenerator = \"random\"\nmaterial = \"g\"\n"
    << "radius = { distribution = \"uniform\", mean = 1e-3, spread = 0.2 }\n"
    << "region = { box = { lo = " << (three ? "[0, 0, 0]" : "[0, 0]")
    << ", hi = " << (three ? "[0.012, 0.012, 0.03]" : "[0.02, 0.03]") << " } }\n"
    << "count = " << (three ? 60 : 50) << "\n"
    << "[[wall]]\nname = \"box\"\ntype = \"box\"\nmaterial = \"g\"\nlo = "
    << (three ? "[0, 0, 0]" : "[0, 0]")
    << "\nhi = " << (three ? "[0.012, 0.012, 0.03]" : "[0.02, 0.03]")
    << "\n[[stage]]\nname = \"fall\"\nsteps = 300\n"
    << "[output]\ndir = \"" << out << "\"\ncsv_interval = 50\nsnapshot_interval = 100\n"
    << "vtk_interval = 0\nlog_interval = 0\n";
  return s.str();
}

sable::RunResult run(const std::string& text, const std::string& resume, bool outputs) {
  return sable::test::run_text(text, {resume, outputs, 0});
}

class CdRun : public ::testing::TestWithParam<int> {};

TEST_P(CdRun, DeterministicWithShuffledSweeps) {
  const int dim = GetParam();
  const auto a = run(cd_scenario(dim, 11, "unused"), "", false);
  const auto b = run(cd_scenario(dim, 11, "unused"), "", false);
  const auto c = run(cd_scenario(dim, 12, "unused"), "", false);
  EXPECT_EQ(a.state_hash, b.state_hash);
  EXPECT_NE(a.state_hash, c.state_hash);
}

TEST_P(CdRun, RestartIsBitIdenticalImpulsesIncluded) {
  const int dim = GetParam();
  const fs::path dir = fs::temp_directory_path() / ("sable_cd_restart" + std::to_string(dim));
  fs::remove_all(dir);
  const auto full = run(cd_scenario(dim, 5, (dir / "full").string()), "", true);
  const fs::path snap = dir / "full" / "snapshots" / "step_0000000200.h5";
  ASSERT_TRUE(fs::exists(snap));
  const auto resumed = run(cd_scenario(dim, 5, (dir / "resumed").string()), snap.string(), true);
  EXPECT_EQ(resumed.steps, full.steps);
  EXPECT_EQ(resumed.state_hash, full.state_hash);
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(TwoAndThreeD, CdRun, ::testing::Values(2, 3));

}  // namespace
