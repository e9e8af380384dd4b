// The drag analysis (analysis/drag.hpp): torque and drag F = 4 M / L per half-turn from a
// series.csv, on synthetic series whose half-turn means and fluctuations are known exactly,
// and the errors for bad series and options, through the library and through `sable analyze`.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "run_helpers.hpp"
#include "sable/analysis/drag.hpp"
#include "sable/core/error.hpp"

namespace fs = std::filesystem;
using namespace sable;

namespace {

constexpr double kPi = 3.14159265358979323846;

// A synthetic series: `before` rows of preparation (torque 99, to be left out) before t0, then
// `per` rows per half-turn for `halves` half-turns, the torque about z in half-turn h being
// level[h] + amp sin(2 omega (t - t0)) (one whole period of the sine per half-turn), then
// `tail` rows of an unfinished half-turn. The half-turn of a row is decided here by its
// integer index, independently of the analysis, which decides it by time.
struct Synthetic {
  double omega = 2.0, t0 = 0.3, amp = 0.25;
  int per = 40, before = 7, tail = 13;
  std::vector<double> level{-2.0, -1.6, -1.3, -1.2, -1.1};
  std::string text(const std::string& wall = "drum") const {
    const double p = kPi / omega, dt = p / per;
    std::ostringstream s;
    s << "step,time_s,kinetic_energy_J,wall_box_tz_Nm,wall_" << wall << "_fx_N,wall_" << wall
      << "_tx_Nm,wall_" << wall << "_ty_Nm,wall_" << wall << "_tz_Nm\n";
    auto row = [&](int step, double t, double m) {
      s << fmt::format("{},{:.17g},1.5,3.25,8,0,7.5,{:.17g}\n", step, t, m);
    };
    for (int k = 0; k < before; ++k) row(k, t0 - (before - k) * 0.01, 99.0);
    const int halves = static_cast<int>(level.size());
    for (int n = 0; n < halves * per + tail; ++n) {
      const double t = t0 + n * dt;
      const double base = n < halves * per ? level[static_cast<std::size_t>(n / per)] : 5.0;
      row(before + n, t, base + amp * std::sin(2.0 * omega * (t - t0)));
    }
    return s.str();
  }
};

fs::path temp_dir(const std::string& name) {
  fs::path p = fs::temp_directory_path() / ("sable_test_drag_" + name);
  fs::remove_all(p);
  fs::create_directories(p);
  return p;
}

std::string write(const fs::path& p, const std::string& text) {
  std::ofstream(p) << text;
  return p.string();
}

DragOptions options(const std::string& series, const Synthetic& syn) {
  DragOptions o;
  o.series = series;
  o.wall = "drum";
  o.omega = syn.omega;
  o.turn_start = syn.t0;
  o.length = 0.03;
  return o;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

// Per half-turn: the mean is the level (the sine sums to zero over its whole period, sampled
// evenly), and the rms deviation is amp / sqrt(2) (sum of sin^2 over n > 2 evenly spaced
// points of a period is n / 2): both exact but for round-off, 1e-12 relative. Drag 4 |M| / L.
TEST(AnalysisDrag, HalfTurnMeansFluctuationsAndDragAreExact) {
  const fs::path dir = temp_dir("exact");
  const Synthetic syn;
  const DragOptions o = options(write(dir / "series.csv", syn.text()), syn);
  const DragResult r = drag_per_half_turn(read_torque_series(o.series, o.wall, o.axis), o);
  EXPECT_DOUBLE_EQ(r.half_turn_s, kPi / syn.omega);
  ASSERT_EQ(r.half_turns.size(), syn.level.size());
  EXPECT_EQ(r.rows_before_start, static_cast<std::size_t>(syn.before));
  for (std::size_t h = 0; h < syn.level.size(); ++h) {
    SCOPED_TRACE(h);
    const HalfTurn& ht = r.half_turns[h];
    EXPECT_EQ(ht.index, static_cast<int>(h) + 1);
    EXPECT_EQ(ht.rows, static_cast<std::size_t>(syn.per));
    EXPECT_NEAR(ht.t_start, syn.t0 + static_cast<double>(h) * r.half_turn_s, 1e-15);
    EXPECT_NEAR(ht.torque, syn.level[h], 1e-12 * std::abs(syn.level[h]));
    EXPECT_NEAR(ht.torque_sd, syn.amp / std::sqrt(2.0), 1e-12 * syn.amp);
  }
  // The unfinished half-turn is left out and reported apart.
  ASSERT_TRUE(r.incomplete.has_value());
  EXPECT_EQ(r.incomplete->index, 6);
  EXPECT_EQ(r.incomplete->rows, static_cast<std::size_t>(syn.tail));
  // Stationary from 1 turn: half-turns 3, 4, 5; standard error = sample sd / sqrt(3).
  EXPECT_EQ(r.stationary_first, 2u);
  EXPECT_EQ(r.stationary_count, 3u);
  const double m = (syn.level[2] + syn.level[3] + syn.level[4]) / 3.0;
  double v = 0.0;
  for (std::size_t h = 2; h < 5; ++h) v += (syn.level[h] - m) * (syn.level[h] - m);
  EXPECT_NEAR(r.stationary_torque, m, 1e-12 * std::abs(m));
  EXPECT_NEAR(r.stationary_se, std::sqrt(v / 2.0) / std::sqrt(3.0), 1e-12 * std::abs(m));
  const Table t = drag_table(r, o);
  ASSERT_EQ(t.names.back(), "drag_N");
  for (std::size_t h = 0; h < t.rows(); ++h)
    EXPECT_NEAR(t.columns.back()[h], 4.0 * std::abs(syn.level[h]) / o.length,
                1e-12 * 4.0 * std::abs(syn.level[h]) / o.length);
  // Without a length: the torque only.
  DragOptions torque_only = o;
  torque_only.length = 0.0;
  EXPECT_EQ(drag_table(r, torque_only).names.back(), "torque_sd_Nm");
  // A later window: from 1.5 turns, half-turns 4 and 5.
  DragOptions later = o;
  later.stationary_from = 1.5;
  const DragResult r2 = drag_per_half_turn(read_torque_series(o.series, o.wall, o.axis), later);
  EXPECT_EQ(r2.stationary_first, 3u);
  EXPECT_NEAR(r2.stationary_torque, 0.5 * (syn.level[3] + syn.level[4]), 1e-12);
  fs::remove_all(dir);
}

// The axis picks the torque component: M = torque . u / |u|. With (0, 1, 1) the series' ty
// (7.5 in every row) and tz mix: the mean is (7.5 + level) / sqrt(2) exactly.
TEST(AnalysisDrag, TheAxisProjectsTheTorque) {
  const fs::path dir = temp_dir("axis");
  const Synthetic syn;
  DragOptions o = options(write(dir / "series.csv", syn.text()), syn);
  o.axis = {0.0, 2.0, 2.0};
  const DragResult r = drag_per_half_turn(read_torque_series(o.series, o.wall, o.axis), o);
  for (std::size_t h = 0; h < syn.level.size(); ++h)
    EXPECT_NEAR(r.half_turns[h].torque, (7.5 + syn.level[h]) / std::sqrt(2.0), 1e-12 * 10.0);
  // Default t0 (the series' first time): the preparation rows now count, in half-turn 1.
  DragOptions from_first = options(o.series, syn);
  from_first.turn_start.reset();
  const DragResult r0 =
      drag_per_half_turn(read_torque_series(o.series, o.wall, from_first.axis), from_first);
  EXPECT_EQ(r0.rows_before_start, 0u);
  EXPECT_DOUBLE_EQ(r0.turn_start_s, syn.t0 - syn.before * 0.01);
  fs::remove_all(dir);
}

// Bad series and options: an InputError naming the file and what is wrong.
TEST(AnalysisDrag, BadSeriesNameTheFileAndTheProblem) {
  const fs::path dir = temp_dir("bad");
  const Synthetic syn;
  const std::string good = write(dir / "series.csv", syn.text());
  const DragOptions o = options(good, syn);
  auto run = [&](const std::string& path, DragOptions opt) {
    opt.series = path;
    return error_of([&] { drag_per_half_turn(read_torque_series(path, opt.wall, opt.axis), opt); });
  };
  // A wall the series does not log: the message names the column and lists the walls it has.
  DragOptions other = o;
  other.wall = "paddle";
  std::string e = run(good, other);
  EXPECT_NE(e.find("series.csv"), std::string::npos) << e;
  EXPECT_NE(e.find("wall_paddle_tz_Nm"), std::string::npos) << e;
  EXPECT_NE(e.find("box, drum"), std::string::npos) << e;
  // No time column.
  std::string text = syn.text();
  text.replace(text.find("time_s"), 6, "time");
  e = run(write(dir / "notime.csv", text), o);
  EXPECT_NE(e.find("notime.csv"), std::string::npos) << e;
  EXPECT_NE(e.find("'time_s'"), std::string::npos) << e;
  // Not a number, with its line.
  e = run(write(dir / "nan.csv", "step,time_s,wall_drum_tz_Nm\n0,abc,1\n"), o);
  EXPECT_NE(e.find("line 2, column time_s"), std::string::npos) << e;
  // Time going backwards.
  e = run(write(dir / "back.csv", "step,time_s,wall_drum_tz_Nm\n0,1,1\n1,0.5,1\n"), o);
  EXPECT_NE(e.find("line 3"), std::string::npos) << e;
  // Less than a half-turn after t0.
  e = run(write(dir / "short.csv", "step,time_s,wall_drum_tz_Nm\n0,0.3,1\n1,0.4,1\n"), o);
  EXPECT_NE(e.find("no complete half-turn"), std::string::npos) << e;
  // Logged less often than every half-turn: a complete half-turn without a row.
  e = run(write(dir / "sparse.csv", "step,time_s,wall_drum_tz_Nm\n0,0.3,1\n1,4.0,1\n"), o);
  EXPECT_NE(e.find("has no row"), std::string::npos) << e;
  // Missing file, and omega <= 0.
  EXPECT_NE(run((dir / "none.csv").string(), o).find("none.csv"), std::string::npos);
  for (double w : {0.0, -1.0}) {
    DragOptions bad = o;
    bad.omega = w;
    e = run(good, bad);
    EXPECT_NE(e.find("--omega"), std::string::npos) << e;
  }
  fs::remove_all(dir);
}

// A small 3D run (a few grains in a box) to have a snapshot and the run's own series.csv.
std::string tiny_run(const std::string& out) {
  std::ostringstream s;
  s << "[simulation]\ndimension = 3\nseed = 2\ngravity = [0, 0, -9.81]\n"
    << "[domain]\nlo = [0, 0, 0]\nhi = [0.01, 0.01, 0.01]\n"
    << "[[material]]\nname = \"g\"\ndensity = 2500.0\nyoung = 5e6\npoisson = 0.45\n"
    << "restitution = 0.3\nfriction = 0.4\n"
    << "[[grains]]\ngenerator = \"lattice\"\nmaterial = \"g\"\nradius = 1e-3\n"
    << "region = { box = { lo = [0, 0, 0], hi = [0.01, 0.01, 0.01] } }\ncount = 8\n"
    << "[[wall]]\nname = \"box\"\ntype = \"box\"\nmaterial = \"g\"\nlo = [0, 0, 0]\n"
    << "hi = [0.01, 0.01, 0.01]\n"
    << "[[stage]]\nname = \"fall\"\nsteps = 400\n"
    << "[output]\ndir = \"" << out << "\"\ncsv_interval = 10\nsnapshot_interval = 0\n"
    << "vtk_interval = 0\nlog_interval = 0\n";
  return s.str();
}

// `sable analyze --only drag`: drag.csv and the summary from the synthetic series (12
// significant digits in the CSV: 1e-10 relative), the run's own series by default, and the
// option errors (exit status 2, naming the option or file).
TEST(AnalysisDrag, CommandLine) {
  const fs::path dir = temp_dir("cli");
  const Synthetic syn;
  const std::string series = write(dir / "synthetic.csv", syn.text());
  test::run_text(tiny_run((dir / "run").string()));
  const std::string snap = (dir / "run" / "snapshots" / "end_of_stage_1.h5").string();
  std::string out;
  const std::string common = "analyze " + snap + " --only drag --drag-wall drum";
  ASSERT_EQ(test::run_cli(common + fmt::format(" --omega {} --drag-length 0.03 --turn-start {} "
                                               "--series {} --out {}",
                                               syn.omega, syn.t0, series, (dir / "an").string()),
                          dir / "log.txt", out),
            0)
      << out;
  std::ifstream csv(dir / "an" / "drag.csv");
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "half_turn,t_start_s,t_end_s,rows,torque_Nm,torque_sd_Nm,drag_N");
  for (std::size_t h = 0; h < syn.level.size(); ++h) {
    ASSERT_TRUE(std::getline(csv, line));
    std::vector<double> v;
    std::stringstream ls(line);
    for (std::string f; std::getline(ls, f, ',');) v.push_back(std::stod(f));
    ASSERT_EQ(v.size(), 7u);
    EXPECT_EQ(v[0], static_cast<double>(h + 1));
    EXPECT_NEAR(v[4], syn.level[h], 1e-10 * std::abs(syn.level[h]));
    EXPECT_NEAR(v[6], 4.0 * std::abs(syn.level[h]) / 0.03, 1e-10 * 4.0 * 2.0 / 0.03);
  }
  EXPECT_FALSE(std::getline(csv, line));  // the unfinished half-turn is not a row
  const std::string summary = test::slurp(dir / "an" / "summary.json");
  for (const char* key : {"\"first_half_turn\"", "\"stationary\"", "\"incomplete_last_half_turn\"",
                          "\"torque_opposes_turning\": true", "\"half_turns\": 5"})
    EXPECT_NE(summary.find(key), std::string::npos) << key << "\n" << summary;
  // The run's own series.csv by default (beside snapshots/): its box.zlo wall, half-turns of
  // pi ms over the run's 10 ms (400 steps of 25 us, a row every 10).
  ASSERT_EQ(test::run_cli("analyze " + snap + " --drag-wall box.zlo --omega 1000 --only drag " +
                              "--out " + (dir / "own").string(),
                          dir / "log.txt", out),
            0)
      << out;
  EXPECT_NE(test::slurp(dir / "own" / "summary.json").find((dir / "run" / "series.csv").string()),
            std::string::npos);
  struct Case {
    std::string args, expect;
  };
  const Case cases[] = {
      {"analyze " + snap + " --only drag --omega 2", "--drag-wall"},
      {common + " --omega 0", "--omega"},
      {common + " --omega -3", "--omega"},
      {common + " --omega 2 --drag-axis 0,0", "--drag-axis"},
      {common + " --omega 2 --drag-length -1", "--drag-length"},
      {common + " --omega 2 --series " + (dir / "nothere.csv").string(), "nothere.csv"},
      {"analyze " + snap + " --only drag --drag-wall wheel --omega 2 --series " + series,
       "wall_wheel_tz_Nm"},
      {"analyze " + snap + " --only load-share", "--level"},
      {"analyze " + snap + " --only stress --omega 2", "--omega"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.args);
    EXPECT_EQ(test::run_cli(c.args + " --out " + (dir / "bad").string(), dir / "log.txt", out), 2)
        << out;
    EXPECT_NE(out.find(c.expect), std::string::npos) << out;
  }
  fs::remove_all(dir);
}

}  // namespace
