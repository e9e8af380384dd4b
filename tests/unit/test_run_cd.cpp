// Contact dynamics through the scenario runner: determinism with a seeded shuffled sweep
// order, and a bit-identical restart (the impulses that warm-start each step, and the RNG
// that shuffles the sweeps, travel in the snapshot). Exact comparisons of state hashes.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "run_helpers.hpp"
#include "sable/cd/nlgs.hpp"
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

// The named columns of a series.csv, row by row (a missing column throws).
std::vector<std::vector<double>> series_columns(const fs::path& csv,
                                                const std::vector<std::string>& names) {
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> head;
  std::stringstream hs(line);
  for (std::string h; std::getline(hs, h, ',');) head.push_back(h);
  std::vector<std::size_t> cols;
  for (const auto& name : names)
    cols.push_back(
        static_cast<std::size_t>(std::find(head.begin(), head.end(), name) - head.begin()));
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) {
    std::vector<std::string> v;
    std::stringstream ls(line);
    for (std::string x; std::getline(ls, x, ',');) v.push_back(x);
    rows.emplace_back();
    for (std::size_t c : cols) rows.back().push_back(std::stod(v.at(c)));
  }
  return rows;
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

// The Newton fallback (cd.newton_iterations, cd/grain_delassus.hpp): with a sweep budget far
// too small for the tolerance (20 forward sweeps for 1e-6), every step of the fall ends at the
// tolerance once Newton finishes what the sweeps start, where without it most steps stop
// short; and the run's bits do not depend on the number of threads.
TEST_P(CdRun, NewtonFallbackReachesTheToleranceTheSweepsMiss) {
  const int dim = GetParam();
  const fs::path dir = fs::temp_directory_path() / ("sable_cd_newton" + std::to_string(dim));
  fs::remove_all(dir);
  const auto text = [&](int newton, const std::string& out) {
    std::string t = cd_scenario(dim, 3, (dir / out).string());
    const std::string from = "[cd]\nsweep = \"shuffled\"\ntolerance = 1e-6\nmax_iterations = 300\n";
    t.replace(t.find(from), from.size(),
              "[cd]\ntolerance = 1e-6\nmax_iterations = 20\nnewton_iterations = " +
                  std::to_string(newton) + "\n");
    t.replace(t.find("csv_interval = 50"), 17, "csv_interval = 1");
    return t;
  };
  // Each row's residual, and the Newton steps it took.
  const auto rows = [&](const std::string& out) {
    std::vector<std::pair<double, double>> r;
    for (const auto& v :
         series_columns(dir / out / "series.csv", {"nlgs_residual", "newton_iterations"}))
      r.emplace_back(v[0], v[1]);
    return r;
  };
  const auto with = sable::test::run_text(text(100, "with"), {"", true, 1});
  const auto two = sable::test::run_text(text(100, "two"), {"", true, 2});
  sable::test::run_text(text(0, "without"), {"", true, 1});
  EXPECT_EQ(with.state_hash, two.state_hash);
  int short_without = 0, newton_used = 0;
  for (const auto& [res, newton] : rows("without")) short_without += res > 1e-6 ? 1 : 0;
  const auto rw = rows("with");
  ASSERT_EQ(rw.size(), 301u);  // the starting row and one per step
  for (const auto& [res, newton] : rw) {
    EXPECT_LE(res, 1e-6);
    newton_used += newton > 0 ? 1 : 0;
  }
  EXPECT_GT(short_without, 30);
  EXPECT_GT(newton_used, 30);
  fs::remove_all(dir);
}

// [cd] residual_checks = "spaced" (cd/nlgs.hpp): every step stops at a sweep count where a
// check was due, below the tolerance unless at the cap, and some steps run past the first 20
// sweeps (where the checks space out), so the key reaches the solver.
TEST_P(CdRun, SpacedResidualChecksStopOnlyWhereACheckIsDue) {
  const int dim = GetParam();
  const fs::path dir = fs::temp_directory_path() / ("sable_cd_spaced" + std::to_string(dim));
  fs::remove_all(dir);
  std::string t = cd_scenario(dim, 3, (dir / "spaced").string());
  const std::string from = "[cd]\nsweep = \"shuffled\"\ntolerance = 1e-6\nmax_iterations = 300\n";
  t.replace(t.find(from), from.size(),
            "[cd]\ntolerance = 1e-9\nmax_iterations = 300\nresidual_checks = \"spaced\"\n");
  t.replace(t.find("csv_interval = 50"), 17, "csv_interval = 1");
  sable::test::run_text(t, {"", true, 1});
  int long_solves = 0, rows = 0;
  for (const auto& v :
       series_columns(dir / "spaced" / "series.csv", {"nlgs_iterations", "nlgs_residual"})) {
    const int n = static_cast<int>(v[0]);
    if (rows++ == 0 || n == 0) continue;  // the starting row; a step without contacts
    EXPECT_TRUE(n == 300 || sable::cd::residual_due(n)) << "a step stopped after " << n;
    if (n < 300) {
      EXPECT_LE(v[1], 1e-9) << "after " << n << " sweeps";
    }
    long_solves += n > 20 ? 1 : 0;
  }
  EXPECT_EQ(rows, 301);
  EXPECT_GT(long_solves, 10);
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(TwoAndThreeD, CdRun, ::testing::Values(2, 3));

}  // namespace
