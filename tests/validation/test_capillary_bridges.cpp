// Capillary bridges in DEM (contact/capillary.hpp, world/liquid.hpp): two wetted spheres
// pulled apart and brought back, a wet pair settling where elastic repulsion balances the
// capillary attraction, and the liquid balance of a wet packing that rearranges.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include "../unit/run_helpers.hpp"
#include "sable/dem/dem_solver.hpp"
#include "sable/io/snapshot.hpp"
#include "sable/scenario/build.hpp"
#include "sable/world/liquid.hpp"
#include "sable/world/state_hash.hpp"

namespace fs = std::filesystem;
using namespace sable;

namespace {

constexpr double kPi = 3.14159265358979323846;

// Two spheres on the x axis, grain 0 (radius r0) optionally fixed, grain 1 (radius r1) free,
// `gap` apart; linear law (kn), no gravity, capillary cohesion.
std::string pair_scenario(double r0, double r1, double gap, bool fix_first, double kn,
                          const std::string& ruptured = "grains") {
  std::ostringstream s;
  s.precision(17);
  s << "[simulation]\ndimension = 3\nseed = 1\n"
    << "[domain]\nlo = [0, 0, 0]\nhi = [0.02, 0.01, 0.01]\n"
    << "[[material]]\nname = \"g\"\ndensity = 2500.0\nyoung = 1e8\npoisson = 0.3\n"
    << "restitution = 0.3\nfriction = 0.4\n"
    << "[contact]\nnormal = \"linear\"\nkn = " << kn << "\nkt = " << kn
    << "\ncohesion = \"capillary\"\nruptured_liquid = \"" << ruptured << "\"\n"
    << "[[grains]]\ngenerator = \"list\"\nmaterial = \"g\"\nradius = " << r0
    << "\npositions = [[0.005, 0.005, 0.005]]\nfixed = " << (fix_first ? "true" : "false") << "\n"
    << "[[grains]]\ngenerator = \"list\"\nmaterial = \"g\"\nradius = " << r1 << "\npositions = [["
    << 0.005 + r0 + r1 + gap << ", 0.005, 0.005]]\n"
    << "[[stage]]\nsteps = 1\n";
  return s.str();
}

void build(const std::string& text, World<3>& w) {
  const ScenarioConfig cfg = parse_scenario(text, "pair.toml");
  build_model(cfg, w);
  build_grains(cfg, w);
}

double total_liquid(const World<3>& w) {
  const LiquidBalance b = liquid_balance(w);
  return b.bridges + b.films + b.lost;
}

}  // namespace

// Grain 1 is moved away from the fixed grain 0 in small steps, at rest (quasi-static: no
// dashpot force), then brought back. Pulling: the force on it is the law's -kappa R
// exp(-gap / lambda) at every gap up to delta_max = V^(1/3), to 1e-12 relative (the same
// formula evaluated along another path: rounding only), and 0 from the first position beyond
// delta_max on (rupture within one displacement step). Its liquid goes half to each grain.
// Coming back: no attraction at any gap > 0 (no bridge forms at a distance: hysteresis), the
// contact attraction -kappa R once they touch, with a new bridge holding half of the films.
// The sample's liquid is conserved throughout to 1e-15 relative (additions of a few terms).
TEST(CapillaryBridges, PullApartFollowsTheLawAndConservesLiquid) {
  const double r0 = 1e-3, r1 = 1.5e-3;
  World<3> w;
  build(pair_scenario(r0, r1, -1e-7, true, 100.0), w);
  DemSolver<3> dem(w);
  dem.initialize();
  const double wc = 1e-3;
  const WettingResult wet = wet_grains(w, wc, 1000.0);
  dem.initialize();
  const double volume = wc * w.particles.mass[1] / 1000.0;  // grain 0 is fixed: not counted
  ASSERT_EQ(wet.bridges, 1u);
  EXPECT_NEAR(wet.volume, volume, 1e-15 * volume);
  EXPECT_NEAR(w.neighbors.pairs.bridge[0], volume, 1e-15 * volume);

  const CapillaryParams cap = w.model.capillary;
  const double kappa_r = 2.0 * kPi * 0.0728 * std::sqrt(r0 * r1);
  const double d_max = std::cbrt(volume);
  const double lambda =
      0.9 / std::sqrt(2.0) * std::sqrt((1.0 / r0 + 1.0 / r1) / std::max(r0 / r1, r1 / r0) * volume);
  EXPECT_LE(d_max, w.neighbors.skin) << "the skin must hold the bridge until it breaks";
  const double dx = d_max / 499.5;  // no position at exactly delta_max
  auto move_to = [&](double gap) {
    w.particles.x[1].x() = 0.005 + r0 + r1 + gap;
    if (w.neighbors.needs_rebuild(w.particles, w.walls)) w.neighbors.build(w.particles, w.walls);
    dem.compute_forces();
    return w.particles.f[1].x();
  };
  double rupture = -1.0;
  for (int k = 0; k <= 750; ++k) {
    const double gap = k * dx;
    const double f = move_to(gap);
    EXPECT_NEAR(total_liquid(w), volume, 1e-15 * volume);
    if (gap <= d_max) {
      ASSERT_NEAR(f, -kappa_r * std::exp(-gap / lambda), 1e-12 * kappa_r) << "gap " << gap;
      EXPECT_NEAR(f, Capillary::force(cap, r0, r1, volume, gap), 1e-12 * kappa_r);
    } else {
      ASSERT_EQ(f, 0.0) << "gap " << gap << " beyond delta_max " << d_max;
      if (rupture < 0.0) rupture = gap;
    }
  }
  EXPECT_GT(rupture, d_max);
  EXPECT_LE(rupture, d_max + dx);
  EXPECT_EQ(liquid_balance(w).bridge_count, 0u);
  EXPECT_NEAR(w.liquid.film[0], 0.5 * volume, 1e-15 * volume);
  EXPECT_NEAR(w.liquid.film[1], 0.5 * volume, 1e-15 * volume);

  for (int k = 750; k > 0; --k) ASSERT_EQ(move_to(k * dx), 0.0) << "attraction at a distance";
  const double overlap = 1e-7;
  const double f = move_to(-overlap);
  EXPECT_NEAR(f, 100.0 * overlap - kappa_r, 1e-12 * kappa_r);
  EXPECT_NEAR(w.neighbors.pairs.bridge[0], 0.5 * volume, 1e-15 * volume);
  EXPECT_NEAR(total_liquid(w), volume, 1e-15 * volume);
}

// With ruptured_liquid = "lost" the liquid of the broken bridge leaves the sample and is
// counted as lost: bridges + films + lost still equals the liquid put in.
TEST(CapillaryBridges, RupturedLiquidLostIsCounted) {
  World<3> w;
  build(pair_scenario(1e-3, 1e-3, -1e-7, true, 100.0, "lost"), w);
  DemSolver<3> dem(w);
  dem.initialize();
  const WettingResult wet = wet_grains(w, 1e-3, 1000.0);
  dem.initialize();
  w.particles.x[1].x() += 2.0 * std::cbrt(wet.volume);
  w.neighbors.build(w.particles, w.walls);
  dem.compute_forces();
  EXPECT_EQ(w.particles.f[1].x(), 0.0);
  EXPECT_EQ(w.liquid.film[0] + w.liquid.film[1], 0.0);
  EXPECT_NEAR(w.liquid.lost, wet.volume, 1e-15 * wet.volume);
}

// Two free wet spheres, no gravity, linear law with damping: they settle where the elastic
// repulsion balances the capillary attraction, k_n delta_n = kappa R (Richefeu et al. 2009:
// the weak forces "where capillary attraction is balanced by elastic repulsion"). The
// oscillation decays by the restitution 0.3 per cycle: after 200 periods the residual is far
// below the 1e-6 relative tolerance asserted (rounding in the force sum is ~1e-13).
TEST(CapillaryBridges, WetPairRestsWhereElasticityBalancesCapillarity) {
  const double r = 1e-3, kn = 50.0;
  World<3> w;
  build(pair_scenario(r, r, -1e-8, false, kn), w);
  DemSolver<3> dem(w);
  dem.initialize();
  wet_grains(w, 1e-3, 1000.0);
  dem.initialize();
  const double m_eff = 0.5 * w.particles.mass[0];
  const double period = 2.0 * kPi * std::sqrt(m_eff / kn);
  const auto steps = static_cast<int>(200.0 * period / w.dt);
  for (int k = 0; k < steps; ++k) dem.step();
  const double overlap = 2.0 * r - (w.particles.x[1] - w.particles.x[0]).norm();
  const double expected = 2.0 * kPi * 0.0728 * r / kn;
  EXPECT_NEAR(overlap, expected, 1e-6 * expected);
  EXPECT_LT(w.particles.v[0].norm() + w.particles.v[1].norm(), 1e-9);
  EXPECT_EQ(liquid_balance(w).bridge_count, 1u);
}

namespace {

// 700 spheres settled in a box under gravity, wetted (water content 0.007, the paper's), then
// the floor drops away at 0.05 m/s: the packing falls apart and rearranges, bridges break and
// form. Snapshots every 2,000 steps for the resume check.
std::string wet_drop(const std::string& out) {
  std::ostringstream s;
  s << "[simulation]\ndimension = 3\nseed = 11\ngravity = [0, 0, -9.81]\n"
    << "[domain]\nlo = [0, 0, -0.02]\nhi = [0.012, 0.012, 0.03]\n"
    << "[[material]]\nname = \"g\"\ndensity = 2500.0\nyoung = 1e6\npoisson = 0.3\n"
    << "restitution = 0.3\nfriction = 0.4\n"
    << "[contact]\ncohesion = \"capillary\"\n"
    << "[[grains]]\ngenerator = \"random\"\nmaterial = \"g\"\n"
    << "radius = { distribution = \"uniform\", mean = 4e-4, spread = 0.3 }\n"
    << "region = { box = { lo = [0, 0, 0], hi = [0.012, 0.012, 0.03] } }\ncount = 700\n"
    << "[[wall]]\nname = \"box\"\ntype = \"box\"\nmaterial = \"g\"\n"
    << "lo = [0, 0, 0]\nhi = [0.012, 0.012, 0.04]\n"
    << "[[stage]]\nname = \"settle\"\nsteps = 6000\n"
    << "[[stage]]\nname = \"wet-drop\"\nsteps = 6000\nwater_content = 0.007\n"
    << "wall_velocity = { \"box.xhi\" = [-0.05, 0, 0] }\n"
    << "[output]\ndir = \"" << out << "\"\ncsv_interval = 0\nlog_interval = 0\n"
    << "vtk_interval = 0\nsnapshot_interval = 2000\n";
  return s.str();
}

}  // namespace

// The liquid balance of a rearranging wet packing (one wall pushed in by 4.6 mm): bridges +
// films = the liquid put in, to 1e-12 relative (thousands of additions), with bridges broken
// (films > 0: only ruptures feed them). A run resumed from a mid-stage snapshot ends
// bit-identical (bridges and films are saved state), and 1 and 2 threads agree to the bit.
TEST(CapillaryBridges, WetPackingConservesLiquidAndResumesBitIdentical) {
  const fs::path dir = fs::temp_directory_path() / "sable_test_wet_drop";
  fs::remove_all(dir);
  const std::string text = wet_drop(dir.string());
  test::QuietRun one;
  one.threads = 1;
  const auto full = test::run_text(text, one);
  const ScenarioConfig cfg = parse_scenario(text, "drop.toml");
  World<3> w;
  build_model(cfg, w);
  load_snapshot((dir / "snapshots" / "end_of_stage_2.h5").string(), w);
  const LiquidBalance b = liquid_balance(w);
  const double volume = 0.007 * [&] {
    double m = 0.0;
    for (double x : w.particles.mass) m += x;
    return m;
  }() / 1000.0;
  EXPECT_NEAR(b.total, volume, 1e-12 * volume);
  EXPECT_NEAR(b.bridges + b.films + b.lost, b.total, 1e-12 * b.total);
  EXPECT_GT(b.films, 0.0) << "no bridge broke: the test does not exercise rupture";
  EXPECT_GT(b.bridge_count, 0u);
  // The bond network goes to ParaView with each bond's bridge volume.
  std::ifstream vtp(dir / "vtk" / "contacts_0000012000.vtp");
  const std::string frame((std::istreambuf_iterator<char>(vtp)), std::istreambuf_iterator<char>());
  EXPECT_NE(frame.find("Name=\"bridge_volume\""), std::string::npos);

  test::QuietRun resume = one;
  resume.resume = (dir / "snapshots" / "step_0000010000.h5").string();
  resume.overwrite = true;  // the full run's later snapshots are in the folder
  const auto resumed = test::run_text(text, resume);
  EXPECT_EQ(resumed.state_hash, full.state_hash);
  // Bridge events are flagged in the parallel pass and applied in list order: the thread count
  // does not change a bit (the list has more than the 2,048 pairs that make the loop parallel).
  EXPECT_GT(w.neighbors.pairs.size(), 2048u);
  test::QuietRun two;
  two.threads = 2;
  two.outputs = false;
  EXPECT_EQ(test::run_text(text, two).state_hash, full.state_hash);
  fs::remove_all(dir);
}
