// The rules of a run's life (docs/reliability.md): what it does with its output folder, what
// a resume may change, how it ends on a signal, a full disk or a bad command line, and the
// exit code of each ending. Through the library where the rule lives there, through the
// `sable` executable where it is the CLI's.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "run_helpers.hpp"
#include "sable/core/error.hpp"
#include "sable/io/snapshot.hpp"
#include "sable/scenario/output_folder.hpp"
#include "sable/scenario/resume_changes.hpp"

extern char** environ;

namespace fs = std::filesystem;

namespace {

fs::path fresh_dir(const std::string& name) {
  fs::path p =
      fs::temp_directory_path() / ("sable_rules_" + std::to_string(::getpid()) + "_" + name);
  fs::remove_all(p);
  fs::create_directories(p);
  return p;
}

std::string read(const fs::path& p) {
  return sable::test::slurp(p);
}

bool has(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

// 60 disks falling in a box: cheap, and every step has contacts. `steps` in one stage.
std::string pour(const fs::path& out, int steps, const std::string& density = "2500.0",
                 const std::string& young = "5e6", const std::string& output_extra = "") {
  std::ostringstream s;
  s << "[simulation]\ndimension = 2\nseed = 3\ngravity = [0, -9.81]\nthickness = 0.002\n"
    << "[domain]\nlo = [0, 0]\nhi = [0.02, 0.03]\n"
    << "[[material]]\nname = \"g\"\ndensity = " << density << "\nyoung = " << young
    << "\npoisson = 0.45\nrestitution = 0.3\nfriction = 0.4\n"
    << "[[grains]]\ngenerator = \"random\"\nmaterial = \"g\"\n"
    << "radius = { distribution = \"uniform\", mean = 1e-3, spread = 0.2 }\n"
    << "region = { box = { lo = [0, 0], hi = [0.02, 0.03] } }\ncount = 60\n"
    << "[[wall]]\nname = \"box\"\ntype = \"box\"\nmaterial = \"g\"\nlo = [0, 0]\n"
    << "hi = [0.02, 0.03]\n"
    << "[[stage]]\nname = \"fall\"\nsteps = " << steps << "\n"
    << "[output]\ndir = \"" << out.string() << "\"\ncsv_interval = 100\n"
    << "snapshot_interval = 500\nvtk_interval = 0\nlog_interval = 0\n"
    << output_extra;
  return s.str();
}

sable::RunResult run(const std::string& text, const std::string& resume = "",
                     bool overwrite = false, bool accept = false) {
  const sable::ScenarioConfig cfg = sable::parse_scenario(text, "pour.toml");
  sable::RunOptions opt;
  std::ostringstream log;
  opt.log = &log;
  opt.live_progress = false;
  opt.resume = resume;
  opt.overwrite = overwrite;
  opt.accept_changes = accept;
  return sable::run_scenario(cfg, opt);
}

std::string input_error(const std::function<void()>& f) {
  try {
    f();
  } catch (const sable::InputError& e) {
    return e.what();
  }
  return "(no InputError)";
}

int cli(const std::string& args, std::string& output) {
  return sable::test::run_cli(
      args, fs::temp_directory_path() / ("sable_rules_" + std::to_string(::getpid()) + ".log"),
      output);
}

// --- output folders ---------------------------------------------------------------------------

// A fresh run into a folder that holds another run's outputs is refused, naming what is there;
// --overwrite deletes exactly the run's own entries (a user's notes stay) and runs.
TEST(OutputFolder, AFreshRunRefusesAnotherRunsOutputs) {
  const fs::path dir = fresh_dir("fresh");
  const std::string text = pour(dir / "out", 1000);
  const auto first = run(text);
  std::ofstream(dir / "out" / "notes.txt") << "mine\n";
  const std::string e = input_error([&] { run(pour(dir / "out", 600)); });
  EXPECT_TRUE(has(e,
                  "already holds a run's outputs (series.csv, grains.pvd, contacts.pvd, "
                  "walls.pvd, vtk/, snapshots/, xdmf/)"))
      << e;
  EXPECT_TRUE(has(e, "--overwrite")) << e;
  EXPECT_TRUE(fs::exists(dir / "out" / "snapshots" / "step_0000001000.h5"));  // untouched
  const auto second = run(pour(dir / "out", 600), "", true);
  EXPECT_EQ(second.steps, 600u);
  EXPECT_FALSE(fs::exists(dir / "out" / "snapshots" / "step_0000001000.h5"));  // the first's
  EXPECT_TRUE(fs::exists(dir / "out" / "snapshots" / "step_0000000500.h5"));
  EXPECT_EQ(read(dir / "out" / "notes.txt"), "mine\n");
  EXPECT_EQ(first.steps, 1000u);
  fs::remove_all(dir);
}

// A resume into its own folder continues it: temporaries of a killed write are deleted;
// snapshots past the resume point (and their sidecars) are refused (they belong to another
// continuation), and with --overwrite deleted, never the snapshot resumed from. The series
// keeps its rows.
TEST(OutputFolder, AResumeTidiesItsFolder) {
  const fs::path dir = fresh_dir("resume");
  const std::string text = pour(dir / "out", 1500);
  const auto full = run(text);
  const fs::path snaps = dir / "out" / "snapshots";
  const fs::path snap = snaps / "step_0000000500.h5";
  const fs::path stale = snaps / "step_0000001000.h5.tmp-2147483646";  // no such process
  std::ofstream(stale) << "half a snapshot";
  const std::string e = input_error([&] { run(text, snap.string()); });
  // The later snapshots, VTK frames and the snapshots' XDMF sidecars (the end-of-stage one
  // has no step in its name: its sidecar goes by its snapshot's header).
  EXPECT_TRUE(has(e,
                  "holds 9 outputs of steps after the resumed step 500 "
                  "(snapshots/end_of_stage_1.h5, snapshots/step_0000001000.h5, "
                  "snapshots/step_0000001500.h5, vtk/contacts_0000001500.vtp, "
                  "vtk/grains_0000001500.vtp, vtk/walls_0000001500.vtp, "
                  "xdmf/end_of_stage_1.xmf, xdmf/step_0000001000.xmf and 1 more)"))
      << e;
  EXPECT_FALSE(fs::exists(stale));
  fs::remove(snaps / "step_0000001000.h5");  // an orphan sidecar goes by the step in its name
  const auto resumed = run(text, snap.string(), true);
  EXPECT_EQ(resumed.state_hash, full.state_hash);
  EXPECT_TRUE(fs::exists(snap));
  EXPECT_TRUE(fs::exists(dir / "out" / "xdmf" / "step_0000000500.xmf"));  // the resumed one's
  EXPECT_TRUE(fs::exists(snaps / "step_0000001000.h5"));  // written again by the resume
  const std::string csv = read(dir / "out" / "series.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 16) << csv;  // header, steps 0..1500
  fs::remove_all(dir);
}

// The step a file name carries decides "after the resume point".
TEST(OutputFolder, StepsInFileNames) {
  EXPECT_EQ(sable::step_in_file_name("step_0000000100.h5"), 100u);
  EXPECT_EQ(sable::step_in_file_name("crash_step_0000000007.h5"), 7u);
  EXPECT_EQ(sable::step_in_file_name("interrupted_step_0000012345.h5"), 12345u);
  EXPECT_EQ(sable::step_in_file_name("grains_0000000200.vtp"), 200u);
  EXPECT_EQ(sable::step_in_file_name("polyhedra_0000000300.vtp"), 300u);
  EXPECT_EQ(sable::step_in_file_name("end_of_stage_2.h5"), std::nullopt);
  EXPECT_EQ(sable::step_in_file_name("step_12x.h5"), std::nullopt);
  EXPECT_EQ(sable::step_in_file_name("mine_0000000200.vtp"), std::nullopt);
}

// --- what a resume may change -----------------------------------------------------------------

// Key by key: [output] and [[stage]] change freely; 2500 and 2500.0 are one value; a changed
// density cannot act on a resumed state (the masses are in the snapshot), a changed Young's
// modulus can.
TEST(ResumeChanges, KeyByKey) {
  const fs::path out = "o";
  const std::string a = pour(out, 100);
  EXPECT_TRUE(
      sable::scenario_changes(a, "a", pour(out, 900, "2500", "5e6", "csv_interval2 = 1\n"), "b")
          .empty());
  const auto c = sable::scenario_changes(a, "a", pour(out, 100, "2600.0", "6e6"), "b");
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c[0].key, "material[0].density");
  EXPECT_EQ(c[0].before, "2500.0");
  EXPECT_EQ(c[0].after, "2600.0");
  EXPECT_TRUE(has(c[0].kept_because, "the grains' masses come from the snapshot"));
  EXPECT_EQ(c[1].key, "material[0].young");
  EXPECT_EQ(c[1].kept_because, "");
  EXPECT_EQ(sable::describe_changes(c),
            "material[0].density (2500.0 -> 2600.0), material[0].young (5e+06 -> 6e+06)");
}

// A resume under an edited density is refused, naming the key; accepted, it runs and says the
// density was not applied: with a fixed time step (an automatic one follows the density) the
// state is the unedited run's, bit for bit.
std::string fixed_dt(std::string text) {
  return text.replace(text.find("[simulation]\n"), 13, "[simulation]\ndt = 1e-6\n");
}

TEST(ResumeChanges, ChangedPhysicsIsRefusedUnlessAccepted) {
  const fs::path dir = fresh_dir("changes");
  const std::string text = fixed_dt(pour(dir / "out", 1000));
  const auto full = run(text);
  const std::string snap = (dir / "out" / "snapshots" / "step_0000000500.h5").string();
  const std::string edited = fixed_dt(pour(dir / "again", 1000, "2600.0"));
  const std::string e = input_error([&] { run(edited, snap); });
  EXPECT_TRUE(has(e,
                  "whose physics differs from pour.toml: material[0].density (2500.0 -> "
                  "2600.0)"))
      << e;
  EXPECT_TRUE(has(e, "--accept-changes")) << e;
  EXPECT_FALSE(fs::exists(dir / "again")) << "a refused resume must write nothing";
  const auto accepted = run(edited, snap, false, true);
  EXPECT_EQ(accepted.state_hash, full.state_hash);
  fs::remove_all(dir);
}

// --- signals ------------------------------------------------------------------------------------

pid_t spawn_cli(const std::vector<std::string>& args, const fs::path& log) {
  std::vector<std::string> all{SABLE_CLI};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&fa, 1, 2);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, SABLE_CLI, &fa, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  return rc == 0 ? pid : -1;
}

std::size_t lines_in(const fs::path& p) {
  const std::string s = read(p);
  return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n'));
}

// SIGTERM, SIGINT and SIGHUP: the run finishes its step, writes interrupted_step_N.h5, says
// how to continue and exits with 128 + the signal; resumed into the same folder it ends on
// the uninterrupted run's state hash.
TEST(Signals, StopWritesASnapshotAndTheResumeIsBitIdentical) {
  const fs::path dir = fresh_dir("signals");
  const fs::path scen = dir / "pour.toml";
  std::ofstream(scen) << pour("out", 30000);
  std::string out;
  ASSERT_EQ(cli("run " + scen.string() + " --out " + (dir / "full").string(), out), 0) << out;
  const std::string hash = out.substr(out.find("state hash ") + 11, 16);
  for (int sig : {SIGTERM, SIGINT, SIGHUP}) {
    SCOPED_TRACE(sig);
    const fs::path run_dir = dir / ("run" + std::to_string(sig));
    const fs::path log = dir / "log.txt";
    const pid_t pid = spawn_cli({"run", scen.string(), "--out", run_dir.string()}, log);
    ASSERT_GT(pid, 0);
    // Wait until the run is stepping (its series has rows), then signal it.
    for (int k = 0; k < 2000 && lines_in(run_dir / "series.csv") < 4; ++k)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    ::kill(pid, sig);
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFEXITED(status)) << read(log);
    EXPECT_EQ(WEXITSTATUS(status), 128 + sig) << read(log);
    const std::string said = read(log);
    ASSERT_TRUE(has(said, "interrupted by SIG")) << said;
    const auto at = said.find("state written to ") + 17;
    const std::string snap = said.substr(at, said.find(';', at) - at);
    EXPECT_TRUE(has(snap, "interrupted_step_")) << said;
    EXPECT_TRUE(has(said, "continue with: sable run")) << said;
    ASSERT_EQ(cli("run " + scen.string() + " --out " + run_dir.string() + " --resume " + snap, out),
              0)
        << out;
    EXPECT_TRUE(has(out, "state hash " + hash)) << out;
  }
  fs::remove_all(dir);
}

// --- a full disk --------------------------------------------------------------------------------

// A file-size limit (ulimit -f, as a full disk would) stops the run with exit code 3 and
// the file named; the snapshots written before it are whole (`sable info` verifies them) and
// no temporary is left.
TEST(DiskFull, ExitsThreeAndKeepsWhatWasWritten) {
  const fs::path dir = fresh_dir("full");
  const fs::path scen = dir / "pour.toml";
  std::ofstream(scen) << pour("out", 20000, "2500.0", "5e6", "");
  std::string text = read(scen);
  text.replace(text.find("csv_interval = 100"), 18, "csv_interval = 1");
  std::ofstream(scen) << text;
  // The limit needs a shell around the executable.
  const std::string cmd = "bash -c 'ulimit -f 96; exec " + std::string(SABLE_CLI) + " run " +
                          scen.string() + " --out " + (dir / "out").string() + "' > " +
                          (dir / "log.txt").string() + " 2>&1";
  const int status = std::system(cmd.c_str());
  std::string out = read(dir / "log.txt");
  EXPECT_EQ(WEXITSTATUS(status), 3) << out;
  EXPECT_TRUE(has(out, "error: cannot write output: cannot write CSV log")) << out;
  EXPECT_TRUE(has(out, "series.csv")) << out;
  int whole = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir / "out")) {
    EXPECT_FALSE(has(e.path().string(), ".tmp-")) << e.path();
    if (e.path().extension() == ".h5") {
      EXPECT_EQ(cli("info " + e.path().string(), out), 0) << out;
      ++whole;
    }
  }
  EXPECT_GE(whole, 1);
  EXPECT_TRUE(fs::exists(dir / "out" / "snapshots" / "step_0000000500.h5"));
  fs::remove_all(dir);
}

// --- the command line ---------------------------------------------------------------------------

TEST(CliRules, VersionThreadsAndFolders) {
  std::string out;
  EXPECT_EQ(cli("--version", out), 0);
  EXPECT_TRUE(has(out, "sable 0.1.0 (")) << out;
  const fs::path dir = fresh_dir("cli");
  const fs::path scen = dir / "pour.toml";
  std::ofstream(scen) << pour("out", 10);
  EXPECT_EQ(cli("run " + scen.string() + " --threads 0", out), 2);
  EXPECT_TRUE(has(out, "--threads: '0': expected a number of threads from 1 to 4096")) << out;
  EXPECT_LT(out.size(), 300u) << out;
  EXPECT_EQ(cli("analyze " + dir.string(), out), 2);
  EXPECT_TRUE(has(out, ": a folder, expected snapshot files (.h5)")) << out;
  fs::remove_all(dir);
}

// `sable fc3d` exits 1 when the NLGS stops above the tolerance (two coupled contacts need
// more than one sweep), 0 when it converges.
TEST(CliRules, Fc3dExitsOneWhenNotConverged) {
  const fs::path dir = fresh_dir("fc3d");
  std::ostringstream p;
  p << "3\n2\n0\n6\n6\n6 6\n";
  for (int j = 0; j < 6; ++j) {
    for (int i = 0; i < 6; ++i) p << (i == j ? "2" : (i + j == 3 && i != j ? "1" : "0")) << ' ';
    p << '\n';
  }
  p << "-1 0.1 0.2 -1 0 0\n0.5 0.5\n";
  std::ofstream(dir / "p.dat") << p.str();
  std::string out;
  EXPECT_EQ(cli("fc3d " + (dir / "p.dat").string() +
                    " --max-iterations 1 --newton-iterations 0 --tolerance 1e-14",
                out),
            1)
      << out;
  EXPECT_TRUE(has(out, "not converged")) << out;
  EXPECT_EQ(cli("fc3d " + (dir / "p.dat").string() + " --tolerance 1e-10 --reactions " +
                    (dir / "r.txt").string(),
                out),
            0)
      << out;
  // --reactions: one line per contact, its three components. Both contacts are pressed
  // (q_N = -1, nothing else pulling them open): r_N > 0 for each.
  std::ifstream in(dir / "r.txt");
  double r[6] = {};
  for (double& v : r) in >> v;
  EXPECT_TRUE(in) << "six values";
  EXPECT_GT(r[0], 0.0);
  EXPECT_GT(r[3], 0.0);
  fs::remove_all(dir);
}

}  // namespace
