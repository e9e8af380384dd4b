// The silo of Dumont, Fortin & Ouafik (2010, section 5.2, Figure 7) end to end, on the
// example scenarios themselves (examples/silo-janssen/silo-{cd,dem}-2d.toml): 350 disks,
// friction 0.25, deposited, then the bottom wall lowered at 5 mm/s. The wall stresses are
// analysed by `sable analyze` (run_analysis) exactly as examples/silo-janssen/run.sh does, and
// compared with Janssen's model, the global balance and Coulomb's law at the walls.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <regex>
#include <sstream>
#include <thread>

#include "sable/analysis/analyze.hpp"
#include "sable/analysis/sample.hpp"
#include "sable/io/snapshot.hpp"
#include "sable/scenario/snapshot_sample.hpp"

namespace fs = std::filesystem;
using namespace sable;

namespace {

constexpr double kMuWall = 0.25;
constexpr double kDescent = 0.005;  // bottom-wall speed (m/s)

// The number after a sequence of keys in a JSON text written by Summary (keys in order; each
// searched after the previous one), e.g. {"janssen", "K"}.
double json_number(const std::string& text, const std::vector<std::string>& keys) {
  std::size_t pos = 0;
  for (const auto& k : keys) {
    pos = text.find("\"" + k + "\":", pos);
    if (pos == std::string::npos) throw std::runtime_error("no key " + k);
    pos += k.size() + 3;
  }
  return std::stod(text.substr(pos));
}

std::string read(const fs::path& p) {
  std::ifstream f(p);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

struct Study {
  std::string before, relax, after;  // summary.json texts
  fs::path snapshots;
  bool dem = false;
};

// One example scenario run for an ensemble of seeds into `dir` (dir/seed-N for each seed).
struct Case {
  std::string name;  // examples/silo-janssen/silo-NAME.toml
  fs::path dir;
  std::vector<std::uint64_t> seeds;
};

// Run every seed of every case as examples/silo-janssen/run.sh does: each run is its own
// `sable run` process on one thread (the results do not depend on the thread count), with
// the scenario's seed line replaced, as many at once as there are cores. The runs share
// nothing, and run one after the other they made this file's tests the longest of the suite
// (9 minutes for the rolling ensembles on the project's 2-core machine, a third of CI).
void run_all(const std::vector<Case>& cases) {
  struct Job {
    fs::path toml, out;
  };
  std::vector<Job> jobs;
  for (const Case& c : cases) {
    const std::string text = read(fs::path(SABLE_SOURCE_DIR) / "examples" / "silo-janssen" /
                                  ("silo-" + c.name + ".toml"));
    const std::regex seed_line("^seed = .*$", std::regex::multiline);
    ASSERT_EQ(std::distance(std::sregex_iterator(text.begin(), text.end(), seed_line),
                            std::sregex_iterator()),
              1)
        << c.name << ": expected one line 'seed = N' (the scenario's [simulation] seed)";
    fs::remove_all(c.dir);  // a run refuses a folder that holds another run's outputs
    fs::create_directories(c.dir);
    for (const std::uint64_t seed : c.seeds) {
      const fs::path run = c.dir / ("seed-" + std::to_string(seed));
      std::ofstream(run.string() + ".toml")
          << std::regex_replace(text, seed_line, "seed = " + std::to_string(seed));
      jobs.push_back({run.string() + ".toml", run});
    }
  }
  ASSERT_TRUE(fs::exists(SABLE_CLI)) << SABLE_CLI << " not built";
  std::atomic<std::size_t> next{0};
  std::vector<int> status(jobs.size(), -1);
  auto worker = [&] {
    for (std::size_t k = next++; k < jobs.size(); k = next++) {
      const std::string cmd = std::string(SABLE_CLI) + " run '" + jobs[k].toml.string() +
                              "' --out '" + jobs[k].out.string() + "' --threads 1 > '" +
                              jobs[k].out.string() + ".log' 2>&1";
      status[k] = std::system(cmd.c_str());  // glibc's system() is thread-safe
    }
  };
  const std::size_t n_workers =
      std::clamp<std::size_t>(std::thread::hardware_concurrency(), 1, jobs.size());
  std::vector<std::thread> pool;
  for (std::size_t t = 0; t < n_workers; ++t) pool.emplace_back(worker);
  for (auto& t : pool) t.join();
  for (std::size_t k = 0; k < jobs.size(); ++k)
    ASSERT_EQ(status[k], 0) << "sable run " << jobs[k].toml << " failed; its log:\n"
                            << read(jobs[k].out.string() + ".log");
}

// Analyse one case's runs as run.sh does: the snapshots before, during and after the descent
// of all the seeds pooled.
Study analyse_case(const Case& c) {
  Study st;
  st.dem = c.name.rfind("dem", 0) == 0;
  std::vector<std::string> before, relax, after;
  for (const std::uint64_t seed : c.seeds) {
    const fs::path snaps = c.dir / ("seed-" + std::to_string(seed)) / "snapshots";
    if (st.snapshots.empty()) st.snapshots = snaps;
    const auto s1 = read_snapshot_info((snaps / "end_of_stage_1.h5").string()).step;
    const auto s2 = read_snapshot_info((snaps / "end_of_stage_2.h5").string()).step;
    std::vector<std::string> descent;
    for (const auto& e : fs::directory_iterator(snaps)) {
      const std::string f = e.path().filename().string();
      if (f.rfind("step_", 0) != 0) continue;
      const auto step = std::stoull(f.substr(5));
      if (step > s1 && step < s2) descent.push_back(e.path().string());
    }
    std::sort(descent.begin(), descent.end());
    descent.push_back((snaps / "end_of_stage_2.h5").string());
    relax.insert(relax.end(), descent.begin(), descent.end());
    before.push_back((snaps / "end_of_stage_1.h5").string());
    after.push_back((snaps / "end_of_stage_3.h5").string());
  }
  auto analyse = [&](std::vector<std::string> in, const std::string& out) {
    AnalyzeOptions a;
    a.snapshots = std::move(in);
    a.only = {"walls", "janssen", "polarization", "stress"};
    a.wall_bin = 0.018;
    a.out_dir = (c.dir / out).string();
    run_analysis(a, snapshot_loaders());
    return read(c.dir / out / "summary.json");
  };
  st.before = analyse(before, "before");
  st.relax = analyse(relax, "relax");
  st.after = analyse(after, "after");
  return st;
}

double wall_ratio(const std::string& summary) {
  double n = 0.0, t = 0.0;
  for (const char* w : {"left", "right"}) {
    n += json_number(summary, {"walls", w, "total_normal_force_N"});
    t += json_number(summary, {"walls", w, "total_shear_force_N"});
  }
  return t / n;
}

double on_cone(const std::string& summary) {
  double sliding = 0.0, count = 0.0;
  for (const char* w : {"wall_left", "wall_right"}) {
    sliding += json_number(summary, {"polarization", w, "sliding"});
    count += json_number(summary, {"polarization", w, "count"});
  }
  return sliding / count;
}

// Coulomb's law at the side walls during the descent: a contact whose point slips along the
// wall carries |ft| = mu fn exactly (DEM: the capped spring; CD: the cone), and a contact below
// the cone does not slip (its grain rolls down the wall or sticks). Slip: the tangential
// velocity of the grain's surface point at the wall (the walls are still).
void check_coulomb_at_walls(const fs::path& snapshot, double cone_tolerance) {
  const Sample<2> s = load_sample<2>(snapshot.string());
  const auto& c = s.contacts;
  int sliding = 0, below = 0;
  for (std::size_t k = 0; k < c.size(); ++k) {
    if (!c.is_wall(k) || s.walls[c.j[k]].name == "bottom") continue;
    const Eigen::Vector2d arm = c.arm_i[k], n = c.n[k];
    const Eigen::Vector2d vp =
        s.v[c.i[k]] + Eigen::Vector2d(-s.omega[c.i[k]] * arm.y(), s.omega[c.i[k]] * arm.x());
    const double slip = (vp - vp.dot(n) * n).norm();
    const double m = c.ft[k].norm() / (c.friction[k] * c.fn[k]);
    if (slip > 0.05 * kDescent) {
      ++sliding;
      EXPECT_GT(m, 1.0 - cone_tolerance) << "slipping contact below the cone, slip " << slip;
    } else {
      ++below;
    }
  }
  EXPECT_GT(sliding, 10);
  std::cout << snapshot.filename() << ": " << sliding << " slipping and " << below
            << " rolling or sticking side-wall contacts\n";
}

// What a study must show, before and during the descent.
struct Bounds {
  double min_on_cone;  // fraction of side-wall contacts on the Coulomb cone, descent
  double min_ratio;    // wall shear / normal during the descent, in [min, max] * mu_w
  double max_ratio;
  double max_ratio_before;    // wall shear / normal at rest before the descent, below this * mu_w
  double max_on_cone_before;  // fraction on the cone at rest before the descent, below this
  double floor_tolerance;     // floor stress / Janssen's (mobilised friction) within 1 +- this
};

// The checks common to every variant, on one solver's study.
void check_study(const Study& st, const Bounds& b) {
  // Global balance: at rest, floor support plus wall friction carry the weight (1 %: the
  // issue's bound; DEM's residual vibration and CD's 1e-4 tolerance are far below it).
  EXPECT_NEAR(json_number(st.before, {"janssen", "support_over_weight"}), 1.0, 0.01);
  EXPECT_NEAR(json_number(st.after, {"janssen", "support_over_weight"}), 1.0, 0.01);
  // During the descent the grains' momentum changes too; with it the balance is exact.
  EXPECT_NEAR(json_number(st.relax, {"janssen", "support_minus_momentum_rate_over_weight"}), 1.0,
              1e-6);
  // Lowering the bottom mobilises wall friction: before, the walls carry almost nothing
  // (shear / normal and the fraction on the cone small); during the descent, wall contacts
  // slide and shear / normal approaches mu_w.
  const double ratio_before = wall_ratio(st.before), ratio_relax = wall_ratio(st.relax);
  std::cout << "wall shear / normal: before " << ratio_before << ", descent " << ratio_relax
            << "; on the cone: before " << on_cone(st.before) << ", descent " << on_cone(st.relax)
            << "\n";
  EXPECT_LT(ratio_before, b.max_ratio_before * kMuWall);
  EXPECT_GE(ratio_relax, b.min_ratio * kMuWall);
  EXPECT_LE(ratio_relax, b.max_ratio * kMuWall);
  EXPECT_LT(on_cone(st.before), b.max_on_cone_before);
  EXPECT_GE(on_cone(st.relax), b.min_on_cone);
  // Janssen with the friction the walls mobilise (sum ft / sum fn) predicts the floor's
  // stress (within the averaged profile's scatter), far below the hydrostatic rho_b g H.
  const double floor = json_number(st.relax, {"janssen", "floor_stress_Pa"});
  const double janssen =
      json_number(st.relax, {"with_mobilised_friction", "janssen_sigma_zz_bottom_Pa"});
  const double hydrostatic = json_number(st.relax, {"janssen", "hydrostatic_bottom_Pa"});
  EXPECT_NEAR(floor / janssen, 1.0, b.floor_tolerance);
  EXPECT_LT(floor, 0.6 * hydrostatic);
  // The descent's last snapshot obeys Coulomb's law at the walls (DEM: the capped spring,
  // exact; CD: the cone, to the solver's tolerance).
  check_coulomb_at_walls(st.snapshots / "end_of_stage_2.h5", st.dem ? 1e-9 : 1e-3);
}

// Both solvers give the same K within two combined standard errors.
void check_same_k(const Study& dem, const Study& cd) {
  const double k_dem = json_number(dem.relax, {"janssen", "K"});
  const double k_cd = json_number(cd.relax, {"janssen", "K"});
  const double se = std::hypot(json_number(dem.relax, {"janssen", "K_stderr"}),
                               json_number(cd.relax, {"janssen", "K_stderr"}));
  std::cout << "K: DEM " << k_dem << ", CD " << k_cd << ", combined standard error " << se
            << "; R2: DEM " << json_number(dem.relax, {"janssen", "r2"}) << ", CD "
            << json_number(cd.relax, {"janssen", "r2"}) << "\n";
  EXPECT_LT(std::abs(k_dem - k_cd), 2.0 * se);
}

// The paper's set-up as given: freely rotating disks. A quarter of the wall grains roll down
// the wall instead of sliding (docs/examples.md), so 71-77 % of the wall contacts reach the
// cone and shear / normal is ~0.20: bounds 0.6 and 0.75 mu_w, met with margin. At rest before
// the descent the walls carry almost no shear (< mu_w / 4); the floor stress is Janssen's
// within 5 % (measured: 0.1 % CD, 4 % DEM).
TEST(SiloJanssen, DumontFortinOuafikSiloByDemAndCd) {
  const fs::path dir = fs::temp_directory_path() / "sable_test_silo";
  fs::remove_all(dir);
  const Case dem_case{"dem-2d", dir / "dem", {2010}}, cd_case{"cd-2d", dir / "cd", {2010}};
  ASSERT_NO_FATAL_FAILURE(run_all({dem_case, cd_case}));
  const Study dem = analyse_case(dem_case), cd = analyse_case(cd_case);
  for (const auto* st : {&dem, &cd}) {
    SCOPED_TRACE(st == &dem ? "DEM" : "CD");
    check_study(*st, {0.6, 0.75, 1.0, 0.25, 0.1, 0.05});
  }
  check_same_k(dem, cd);
  // The profile has Janssen's shape (R^2 of the fit; CD averages 13 snapshots of a slowly
  // rearranging network).
  EXPECT_GE(json_number(cd.relax, {"janssen", "r2"}), 0.9);
  fs::remove_all(dir);
}

// With a rolling friction of 0.1 (silo-{cd,dem}-2d-rolling.toml) the wall grains slide, and
// every item of the issue holds on the ensembles that examples/silo-janssen/run.sh pools
// (DEM: 4 seeds, CD: 8; a 350-grain silo's wall stress rides on a few force chains, so a
// single seed's profile is too patchy to test a shape: R^2 0.05-0.86 for one CD seed).
// Measured on these ensembles (run.sh, at the commit that added this test): on the cone
// DEM 99.2 %, CD 97.9 %; shear / normal 0.248 and 0.245; K 0.78 +- 0.04 and 0.81 +- 0.04;
// R^2 0.98 and 0.98; floor / Janssen 0.96 and 1.01.
// Bounds: the (>= 90 % on the cone, mu_w within 5 %, R^2 >= 0.9, balance within
// 1 %). Rolling resistance lets the deposit at rest hold some wall shear and keep some wall
// contacts at the cone (CD: 0.078 and 15 %), still far below the descent's: bounds mu_w / 2
// and 30 %, a third of the descent's 90 %. Floor within 10 % of Janssen's (single DEM seeds
// scatter by 0.91-1.07, descent_scan.sh).
TEST(SiloJanssen, RollingResistantEnsemblesMeetEveryItem) {
  const fs::path dir = fs::temp_directory_path() / "sable_test_silo_rolling";
  fs::remove_all(dir);
  const Case dem_case{"dem-2d-rolling", dir / "dem", {2010, 2011, 2012, 2013}};
  const Case cd_case{"cd-2d-rolling", dir / "cd", {2010, 2011, 2012, 2013, 2014, 2015, 2016, 2017}};
  ASSERT_NO_FATAL_FAILURE(run_all({cd_case, dem_case}));  // CD's runs are the longer: first
  const Study dem = analyse_case(dem_case), cd = analyse_case(cd_case);
  for (const auto* st : {&dem, &cd}) {
    SCOPED_TRACE(st == &dem ? "DEM" : "CD");
    check_study(*st, {0.9, 0.95, 1.05, 0.5, 0.3, 0.1});
    // Janssen's shape explains the wall-normal-stress profile (the bound).
    EXPECT_GE(json_number(st->relax, {"janssen", "r2"}), 0.9);
  }
  check_same_k(dem, cd);
  fs::remove_all(dir);
}

}  // namespace
