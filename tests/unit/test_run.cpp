// End-to-end runs through the scenario runner: determinism, bit-exact restart, and the CLI's
// handling of bad input. All comparisons are exact (state hashes over every bit of the state).
#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "run_helpers.hpp"
#include "sable/analysis/analyze.hpp"
#include "sable/io/snapshot.hpp"
#include "sable/scenario/build.hpp"
#include "sable/scenario/config.hpp"
#include "sable/scenario/runner.hpp"

namespace fs = std::filesystem;

namespace {

// A small, lively scenario: grains inserted at random fall, collide with friction and
// damping, and settle on the floor of a box. Hertz-Mindlin with history exercises every
// piece of state a restart must carry.
std::string scenario(int dim, std::uint64_t seed, const std::string& out) {
  const bool three = dim == 3;
  std::ostringstream s;
  s << "[simulation]\ndimension = " << dim << "\nseed = " << seed << "\n"
    << "gravity = " << (three ? "[0, 0, -9.81]" : "[0, -9.81]") << "\n"
    << (three ? "" : "thickness = 0.002\n") << "[domain]\n"
    << "lo = " << (three ? "[0, 0, 0]" : "[0, 0]")
    << "\nhi = " << (three ? "[0.02, 0.02, 0.04]" : "[0.04, 0.04]") << "\n"
    << "[[material]]\nname = \"g\"\ndensity = 2500.0\nyoung = 5e6\npoisson = 0.45\n"
    << "restitution = 0.6\nfriction = 0.5\n"
    << "[[grains]]\ngenerator = \"random\"\nmaterial = \"g\"\n"
    << "radius = { distribution = \"uniform\", mean = 1e-3, spread = 0.2 }\n"
    << "region = { box = { lo = " << (three ? "[0, 0, 0.005]" : "[0, 0.005]")
    << ", hi = " << (three ? "[0.02, 0.02, 0.04]" : "[0.04, 0.04]") << " } }\n"
    << "count = " << (three ? 150 : 120) << "\n"
    << "velocity = " << (three ? "[0.05, 0, -0.1]" : "[0.05, -0.1]") << "\n"
    << "[[wall]]\nname = \"box\"\ntype = \"box\"\nmaterial = \"g\"\nlo = "
    << (three ? "[0, 0, 0]" : "[0, 0]")
    << "\nhi = " << (three ? "[0.02, 0.02, 0.04]" : "[0.04, 0.04]") << "\n"
    << "[[stage]]\nname = \"fall\"\nsteps = 300\n"
    << "[[stage]]\nname = \"push\"\nsteps = 300\n"
    << "wall_velocity = { " << (three ? "\"box.zhi\" = [0, 0, -0.05]" : "\"box.yhi\" = [0, -0.05]")
    << " }\n"
    << "[output]\ndir = \"" << out << "\"\ncsv_interval = 50\nsnapshot_interval = 100\n"
    << "vtk_interval = 200\nlog_interval = 0\n";
  return s.str();
}

sable::RunResult run(const std::string& text, const std::string& resume = "", bool outputs = true) {
  return sable::test::run_text(text, {resume, outputs, 0});
}

fs::path temp_dir(const std::string& name) {
  fs::path p = fs::temp_directory_path() / ("sable_test_run_" + name);
  fs::remove_all(p);
  fs::create_directories(p);
  return p;
}

class RunDim : public ::testing::TestWithParam<int> {};

// Same scenario, same seed: bit-identical final state; another seed: a different one.
TEST_P(RunDim, DeterministicStateHash) {
  const int dim = GetParam();
  const auto a = run(scenario(dim, 7, "unused"), "", false);
  const auto b = run(scenario(dim, 7, "unused"), "", false);
  const auto c = run(scenario(dim, 8, "unused"), "", false);
  EXPECT_EQ(a.steps, 600u);
  EXPECT_EQ(a.state_hash, b.state_hash);
  EXPECT_NE(a.state_hash, c.state_hash);
}

// A run resumed from a snapshot taken mid-stage (step 200 of stage 1) and from one taken in
// the second stage (step 400, after the wall started moving) ends bit-identical to the
// uninterrupted run; the CSV has no duplicated rows after the resume.
TEST_P(RunDim, RestartIsBitIdentical) {
  const int dim = GetParam();
  const fs::path dir = temp_dir("restart" + std::to_string(dim));
  const auto full = run(scenario(dim, 3, (dir / "full").string()));
  for (const char* snap : {"step_0000000200.h5", "step_0000000400.h5"}) {
    const fs::path snapshot = dir / "full" / "snapshots" / snap;
    ASSERT_TRUE(fs::exists(snapshot)) << snapshot;
    const fs::path resumed_dir = dir / (std::string("resumed_") + snap);
    fs::create_directories(resumed_dir);
    fs::copy_file(dir / "full" / "series.csv", resumed_dir / "series.csv");
    const auto resumed = run(scenario(dim, 3, resumed_dir.string()), snapshot.string());
    EXPECT_EQ(resumed.steps, full.steps);
    EXPECT_EQ(resumed.state_hash, full.state_hash) << "resumed from " << snap;
    // The resumed CSV equals the uninterrupted one line for line.
    std::ifstream f1(dir / "full" / "series.csv"), f2(resumed_dir / "series.csv");
    std::stringstream s1, s2;
    s1 << f1.rdbuf();
    s2 << f2.rdbuf();
    EXPECT_EQ(s1.str(), s2.str());
  }
  fs::remove_all(dir);
}

// The thread count does not change a single bit: contact forces are computed per contact and
// summed per grain in a fixed order (dem_solver_impl.hpp), never with atomics or per-thread sums.
// 3,000+ grains so that the loops really run in parallel (small loops stay serial).
TEST_P(RunDim, BitIdenticalForOneAndTwoThreads) {
  const int dim = GetParam();
  std::string text = scenario(dim, 9, "unused");
  const std::string random_block =
      text.substr(text.find("[[grains]]"), text.find("[[wall]]") - text.find("[[grains]]"));
  std::ostringstream lattice;
  lattice << "[[grains]]\ngenerator = \"lattice\"\nmaterial = \"g\"\nradius = 0.35e-3\n"
          << "spacing = 0.75e-3\njitter = 0.02e-3\nregion = { box = { lo = "
          << (dim == 3 ? "[0, 0, 0.005]" : "[0, 0.005]")
          << ", hi = " << (dim == 3 ? "[0.02, 0.02, 0.04]" : "[0.04, 0.04]") << " } }\n"
          << "count = " << (dim == 3 ? 3200 : 2400) << "\n";
  text.replace(text.find(random_block), random_block.size(), lattice.str());
  for (std::size_t at; (at = text.find("steps = 300")) != std::string::npos;)
    text.replace(at, 11, "steps = 60");  // 120 steps: enough for contacts and a rebuild
  // Three threads too: the DEM pass splits the grains into one block per thread, and the
  // grains other blocks reach are summed apart (DemSolver::dry_pair_forces); more blocks, more
  // such grains.
  std::uint64_t hashes[3];
  for (int threads : {1, 2, 3}) {
    const auto r = sable::test::run_text(text, {"", false, threads});
    EXPECT_GE(r.grains, 2400u);
    hashes[threads - 1] = r.state_hash;
  }
  EXPECT_EQ(hashes[0], hashes[1]);
  EXPECT_EQ(hashes[0], hashes[2]);
}

// The scenario on a bed in contact from the start (a hexagonal lattice of touching grains on
// the floor, sliding along x), so that many contacts roll and wind their springs before the
// first snapshot; with `rolling`, rolling resistance (contact/rolling.hpp): mu_r = 0.1,
// rolling = "epsd".
std::string bed_scenario(int dim, const std::string& out, bool rolling) {
  const bool three = dim == 3;
  std::string text = scenario(dim, 3, out);
  const std::size_t from = text.find("[[grains]]");
  std::ostringstream bed;
  if (rolling) bed << "[contact]\nrolling = \"epsd\"\n";
  bed << "[[grains]]\ngenerator = \"lattice\"\nmaterial = \"g\"\nradius = 1e-3\n"
      << "arrangement = \"hexagonal\"\nregion = { box = { lo = " << (three ? "[0, 0, 0]" : "[0, 0]")
      << ", hi = " << (three ? "[0.02, 0.02, 0.006]" : "[0.04, 0.01]") << " } }\n"
      << "count = " << (three ? 250 : 90) << "\n"
      << "velocity = " << (three ? "[0.05, 0.02, 0]" : "[0.05, 0]") << "\n";
  text.replace(from, text.find("[[wall]]") - from, bed.str());
  if (rolling)
    text.replace(text.find("friction = 0.5\n"), 15, "friction = 0.5\nrolling_friction = 0.1\n");
  return text;
}

// What a resumed run of `text` holds after loading `snapshot`: its contact-list entries
// (grain pairs and grain-wall pairs), the rolling springs the lists carry (one per entry, or
// none at all), how many of those are wound (not zero), and the lists' springs flag (set by
// the scenario, whatever the snapshot had).
struct LoadedSprings {
  std::size_t entries = 0, springs = 0, wound = 0;
  bool rolling = false;
};

template <int D>
LoadedSprings loaded_springs(const std::string& text, const fs::path& snapshot) {
  const sable::ScenarioConfig cfg = sable::parse_scenario(text, "test.toml");
  sable::World<D> w;
  sable::build_model(cfg, w);
  sable::load_snapshot(snapshot.string(), w);
  const auto& nl = w.neighbors;
  LoadedSprings out;
  out.rolling = nl.rolling;
  out.entries = nl.pairs.size() + nl.wall_pairs.size();
  out.springs = nl.pairs.roll.size() + nl.wall_pairs.roll.size();
  if (out.springs > 0) {  // then one per entry of each list
    EXPECT_EQ(nl.pairs.roll.size(), nl.pairs.size());
    EXPECT_EQ(nl.wall_pairs.roll.size(), nl.wall_pairs.size());
  }
  for (const auto& th : nl.pairs.roll) out.wound += sable::Space<D>::rot_norm2(th) > 0.0;
  for (const auto& th : nl.wall_pairs.roll) out.wound += sable::Space<D>::rot_norm2(th) > 0.0;
  return out;
}

LoadedSprings loaded_springs(int dim, const std::string& text, const fs::path& snapshot) {
  return dim == 2 ? loaded_springs<2>(text, snapshot) : loaded_springs<3>(text, snapshot);
}

// Whether a snapshot file holds the rolling springs' datasets.
bool has_springs(const fs::path& snapshot) {
  const hid_t f = H5Fopen(snapshot.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  EXPECT_GE(f, 0) << snapshot;
  const bool pairs = H5Lexists(f, "/neighbors/pairs/roll", H5P_DEFAULT) > 0;
  const bool walls = H5Lexists(f, "/neighbors/wall_pairs/roll", H5P_DEFAULT) > 0;
  H5Fclose(f);
  EXPECT_EQ(pairs, walls) << snapshot;
  return pairs;
}

// With rolling resistance, a run resumed from a snapshot mid-stage (step 200) or in the
// second stage (step 400) ends bit-identical to the uninterrupted one: the snapshots carry
// the springs (wound ones: a lost spring would show in the hash, which covers them).
// Rolling resistance changes the run (another final kinetic energy than without it).
TEST_P(RunDim, RollingRestartIsBitIdentical) {
  const int dim = GetParam();
  const fs::path dir = temp_dir("rolling_restart" + std::to_string(dim));
  const std::string full_text = bed_scenario(dim, (dir / "full").string(), true);
  const auto full = run(full_text);
  EXPECT_NE(full.kinetic_energy, run(bed_scenario(dim, "unused", false), "", false).kinetic_energy);
  for (const char* snap : {"step_0000000200.h5", "step_0000000400.h5"}) {
    const fs::path snapshot = dir / "full" / "snapshots" / snap;
    ASSERT_TRUE(fs::exists(snapshot)) << snapshot;
    EXPECT_TRUE(has_springs(snapshot));
    const LoadedSprings s = loaded_springs(dim, full_text, snapshot);
    EXPECT_GT(s.wound, 100u) << snap << ": the restart should have wound springs to carry";
    const auto resumed = run(bed_scenario(dim, (dir / snap).string(), true), snapshot.string());
    EXPECT_EQ(resumed.steps, full.steps);
    EXPECT_EQ(resumed.state_hash, full.state_hash) << "resumed from " << snap;
  }
  fs::remove_all(dir);
}

// A snapshot written without rolling resistance resumes under a scenario with it: the lists
// get springs at zero (one per pair) and the run goes on, writing springs in its snapshots.
// The other way round, the springs of a rolling snapshot are dropped: no springs, none
// written. Both runs end at the scenario's last step without an error.
TEST_P(RunDim, RollingAndPlainSnapshotsResumeEachOther) {
  const int dim = GetParam();
  const fs::path dir = temp_dir("rolling_cross" + std::to_string(dim));
  const std::string plain_text = bed_scenario(dim, (dir / "plain").string(), false);
  const std::string rolling_text = bed_scenario(dim, (dir / "rolling").string(), true);
  run(plain_text);
  run(rolling_text);
  const fs::path plain_snap = dir / "plain" / "snapshots" / "step_0000000400.h5";
  const fs::path rolling_snap = dir / "rolling" / "snapshots" / "step_0000000400.h5";
  ASSERT_TRUE(fs::exists(plain_snap) && fs::exists(rolling_snap));
  EXPECT_FALSE(has_springs(plain_snap));
  EXPECT_TRUE(has_springs(rolling_snap));

  const LoadedSprings zeroed = loaded_springs(dim, rolling_text, plain_snap);
  EXPECT_TRUE(zeroed.rolling);
  EXPECT_GT(zeroed.entries, 100u);
  EXPECT_EQ(zeroed.springs, zeroed.entries);
  EXPECT_EQ(zeroed.wound, 0u);
  // Another contact law than the snapshot's: a change of physics, accepted.
  const auto to_rolling = sable::test::run_text(
      bed_scenario(dim, (dir / "to_rolling").string(), true), {plain_snap.string(), true, 0, true});
  EXPECT_EQ(to_rolling.steps, 600u);
  EXPECT_TRUE(has_springs(dir / "to_rolling" / "snapshots" / "end_of_stage_2.h5"));

  const LoadedSprings dropped = loaded_springs(dim, plain_text, rolling_snap);
  EXPECT_FALSE(dropped.rolling);
  EXPECT_GT(dropped.entries, 100u);
  EXPECT_EQ(dropped.springs, 0u);
  const auto to_plain = sable::test::run_text(bed_scenario(dim, (dir / "to_plain").string(), false),
                                              {rolling_snap.string(), true, 0, true});
  EXPECT_EQ(to_plain.steps, 600u);
  EXPECT_FALSE(has_springs(dir / "to_plain" / "snapshots" / "end_of_stage_2.h5"));
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(TwoAndThreeD, RunDim, ::testing::Values(2, 3));

// Run the CLI, capturing its exit status and its stderr+stdout. The log is named after the
// process: ctest runs tests as parallel processes, which must not share it.
int cli(const std::string& args, std::string& output) {
  return sable::test::run_cli(
      args, fs::temp_directory_path() / ("sable_cli_test_" + std::to_string(getpid()) + ".log"),
      output);
}

// A bad scenario: exit status 2 and a message with file:line:column and the key.
TEST(Cli, BadScenarioNamesThePlace) {
  const fs::path dir = temp_dir("cli_bad");
  std::string text = scenario(3, 1, (dir / "out").string());
  text.replace(text.find("poisson = 0.45"), 14, "poisson = 0.75");
  const fs::path file = dir / "bad.toml";
  std::ofstream(file) << text;
  std::string out;
  EXPECT_EQ(cli("check " + file.string(), out), 2);
  EXPECT_NE(out.find(file.string() + ":12:"), std::string::npos) << out;
  EXPECT_NE(out.find("poisson"), std::string::npos) << out;
  EXPECT_EQ(cli("run " + file.string(), out), 2);
  EXPECT_FALSE(fs::exists(dir / "out")) << "a rejected scenario must write nothing";
  fs::remove_all(dir);
}

// `sable analyze --help` names every analysis --only accepts (the table run_analysis checks
// names against): a help text written by hand once left out janssen.
TEST(Cli, AnalyzeHelpListsEveryAnalysis) {
  std::string out;
  EXPECT_EQ(cli("analyze --help", out), 0);
  for (const char* a : sable::kAnalyses)
    EXPECT_NE(out.find(std::string(" ") + a), std::string::npos) << a << " missing from\n" << out;
}

// Missing files and foreign snapshots are input errors (status 2), not crashes.
TEST(Cli, MissingAndForeignFiles) {
  const fs::path dir = temp_dir("cli_missing");
  std::string out;
  EXPECT_EQ(cli("run " + (dir / "nope.toml").string(), out), 2);
  EXPECT_NE(out.find("nope.toml"), std::string::npos) << out;
  const fs::path fake = dir / "fake.h5";
  std::ofstream(fake) << "not a snapshot\n";
  EXPECT_EQ(cli("info " + fake.string(), out), 2);
  EXPECT_NE(out.find("fake.h5"), std::string::npos) << out;
  EXPECT_EQ(cli("run", out), 2);
  fs::remove_all(dir);
}

// `sable info` reports the state hash the run ended with, read back from the snapshot.
TEST(Cli, InfoReportsSnapshot) {
  const fs::path dir = temp_dir("cli_info");
  const auto r = run(scenario(2, 5, (dir / "out").string()));
  std::string out;
  const fs::path snap = dir / "out" / "snapshots" / "end_of_stage_2.h5";
  ASSERT_EQ(cli("info " + snap.string(), out), 0) << out;
  char hash[32];
  std::snprintf(hash, sizeof hash, "%016llx", static_cast<unsigned long long>(r.state_hash));
  EXPECT_NE(out.find(hash), std::string::npos) << out;
  EXPECT_NE(out.find("step        600"), std::string::npos) << out;
  fs::remove_all(dir);
}

}  // namespace
