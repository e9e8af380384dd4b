// Wetting a sample (world/liquid.hpp): how the liquid of a water content is shared among
// the eligible pairs, and the scenario and snapshot errors around capillary cohesion.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <vector>

#include "sable/core/error.hpp"
#include "sable/io/snapshot.hpp"
#include "sable/scenario/build.hpp"
#include "sable/world/liquid.hpp"

using namespace sable;

namespace {

// Spheres of radii `r` in a row along x, touching or `gaps` apart (gaps[k]: between k and
// k+1), no gravity, capillary cohesion.
std::string chain(const std::vector<double>& r, const std::vector<double>& gaps,
                  const std::string& cohesion = "capillary") {
  std::ostringstream s;
  s.precision(17);
  s << "[simulation]\ndimension = 3\n[domain]\nlo = [0, 0, 0]\nhi = [0.03, 0.01, 0.01]\n"
    << "[[material]]\nname = \"g\"\ndensity = 2500.0\nyoung = 1e8\npoisson = 0.3\n"
    << "[contact]\ncohesion = \"" << cohesion << "\"\n";
  double x = 0.002;
  for (std::size_t k = 0; k < r.size(); ++k) {
    if (k > 0) x += r[k - 1] + gaps[k - 1] + r[k];
    s << "[[grains]]\ngenerator = \"list\"\nmaterial = \"g\"\nradius = " << r[k]
      << "\npositions = [[" << x << ", 0.005, 0.005]]\n";
  }
  s << "[[stage]]\nsteps = 1\n";
  return s.str();
}

void build(const std::string& text, World<3>& w) {
  const ScenarioConfig cfg = parse_scenario(text, "chain.toml");
  build_model(cfg, w);
  build_grains(cfg, w);
  w.neighbors.build(w.particles, w.walls);
}

double gap_of(const World<3>& w, std::size_t k) {
  const auto& p = w.particles;
  const auto i = w.neighbors.pairs.i[k], j = w.neighbors.pairs.j[k];
  return (p.x[i] - p.x[j]).norm() - p.radius[i] - p.radius[j];
}

double share_of(const World<3>& w, std::size_t k) {
  const auto& p = w.particles;
  return Capillary::reduced_diameter(p.radius[w.neighbors.pairs.i[k]],
                                     p.radius[w.neighbors.pairs.j[k]]);
}

// The rule of liquid.hpp, checked from its definition: the bridges hold the whole volume
// (1e-15 relative: a sum of a few terms), each in proportion to its reduced diameter, each
// bridged pair's gap is within its own rupture distance, and any unbridged pair would be
// beyond the rupture distance of the share it would get by joining.
void check_distribution(const World<3>& w, double volume) {
  const auto& pl = w.neighbors.pairs;
  double sum = 0.0, shares = 0.0;
  for (std::size_t k = 0; k < pl.size(); ++k)
    if (pl.bridge[k] >= 0.0) {
      sum += pl.bridge[k];
      shares += share_of(w, k);
    }
  EXPECT_NEAR(sum, volume, 1e-15 * volume);
  for (std::size_t k = 0; k < pl.size(); ++k) {
    const double gap = gap_of(w, k);
    if (pl.bridge[k] >= 0.0) {
      EXPECT_NEAR(pl.bridge[k], volume * share_of(w, k) / shares, 1e-15 * volume);
      EXPECT_LE(gap, std::cbrt(pl.bridge[k]) * (1.0 + 1e-12));
    } else {
      const double joined = volume * share_of(w, k) / (shares + share_of(w, k));
      EXPECT_GT(gap, std::cbrt(joined)) << "pair " << k << " should have a bridge";
    }
  }
}

}  // namespace

// Equal spheres A-B touching, B-C 20 um apart, C-D 600 um apart, water content 0.01: V/2 per
// bridge reaches (V/2)^(1/3) = 594 um, so A-B and B-C share the liquid equally and C-D (it
// would need 600 um <= (V/3)^(1/3) = 519 um) stays dry. With C-D 500 um apart instead, it
// qualifies even with a third of the liquid and all three get V/3.
TEST(Wetting, SharesTheLiquidAmongTheEligiblePairs) {
  const double r = 1e-3;
  for (double g2 : {6e-4, 5e-4}) {
    SCOPED_TRACE(g2);
    World<3> w;
    build(chain({r, r, r, r}, {-1e-9, 2e-5, g2}), w);
    const double mass = 4.0 * w.particles.mass[0];
    const WettingResult res = wet_grains(w, 0.01, 1000.0);
    const double volume = 0.01 * mass / 1000.0;
    EXPECT_NEAR(res.volume, volume, 1e-15 * volume);
    EXPECT_EQ(res.contacts, 1u);
    EXPECT_EQ(res.bridges, g2 > 5.5e-4 ? 2u : 3u);
    EXPECT_GE(w.neighbors.skin, res.max_rupture) << "a bridged pair must stay in the list";
    check_distribution(w, volume);
    EXPECT_EQ(w.liquid.total, res.volume);
    EXPECT_EQ(w.liquid.film, std::vector<double>(4, 0.0));
  }
}

// Unequal spheres: the shares follow the reduced diameters 4 R_i R_j / (R_i + R_j).
TEST(Wetting, PolydisperseSharesFollowTheReducedDiameter) {
  World<3> w;
  build(chain({1e-3, 1.5e-3, 0.8e-3, 2e-3, 1.2e-3}, {-1e-9, 1e-5, -2e-9, 3e-4}), w);
  const WettingResult res = wet_grains(w, 0.005, 1000.0);
  EXPECT_GE(res.bridges, 3u);
  check_distribution(w, res.volume);
}

// liquid_pairs = "contacts": equal spheres A-B touching, B-C 20 um apart (within reach of any
// share, as above), C-D touching: only A-B and C-D get a bridge, V/2 each (exact shares of
// two equal terms: 1e-15), B-C stays dry; a chain with no touching pair is refused.
TEST(Wetting, ContactsOnlyBridgesTheTouchingPairs) {
  const double r = 1e-3;
  World<3> w;
  build(chain({r, r, r, r}, {-1e-9, 2e-5, -1e-9}), w);
  const WettingResult res = wet_grains(w, 0.01, 1000.0, LiquidPairs::kContacts);
  EXPECT_EQ(res.bridges, 2u);
  EXPECT_EQ(res.contacts, 2u);
  EXPECT_LE(res.debonding_distance, 0.0) << "no bridge at a gap";
  const auto& pl = w.neighbors.pairs;
  std::size_t bridged = 0;
  for (std::size_t k = 0; k < pl.size(); ++k) {
    if (gap_of(w, k) > 0.0) {
      EXPECT_LT(pl.bridge[k], 0.0) << "pair " << k << " is apart: no bridge";
    } else {
      EXPECT_NEAR(pl.bridge[k], 0.5 * res.volume, 1e-15 * res.volume);
      ++bridged;
    }
  }
  EXPECT_EQ(bridged, 2u);
  EXPECT_GE(w.neighbors.skin, res.max_rupture) << "a bridged pair must stay in the list";
  // The default rule bridges B-C too: the option is what changes the set.
  World<3> all;
  build(chain({r, r, r, r}, {-1e-9, 2e-5, -1e-9}), all);
  EXPECT_EQ(wet_grains(all, 0.01, 1000.0).bridges, 3u);
  World<3> apart;
  build(chain({r, r}, {2e-5}), apart);
  try {
    wet_grains(apart, 0.01, 1000.0, LiquidPairs::kContacts);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("touching"), std::string::npos) << e.what();
  }
}

TEST(Wetting, RefusesADryLawAndASampleWithNoClosePairs) {
  World<3> dry;
  build(chain({1e-3, 1e-3}, {-1e-9}, "none"), dry);
  EXPECT_THROW(wet_grains(dry, 0.01, 1000.0), InputError);
  World<3> far;
  build(chain({1e-3, 1e-3}, {0.02}), far);
  try {
    wet_grains(far, 1e-6, 1000.0);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no pair of grains"), std::string::npos) << e.what();
  }
}

namespace {

void expect_parse_error(const std::string& text, const std::string& needle) {
  try {
    parse_scenario(text, "wet.toml");
    FAIL() << "expected an InputError mentioning " << needle;
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("wet.toml:"), std::string::npos) << msg;
    EXPECT_NE(msg.find(needle), std::string::npos) << msg;
  }
}

std::string with(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

}  // namespace

TEST(Wetting, ScenarioErrorsNameTheKey) {
  const std::string ok = chain({1e-3, 1e-3}, {-1e-9});
  EXPECT_NO_THROW(parse_scenario(with(ok, "steps = 1", "steps = 1\nwater_content = 0.007"), "w"));
  expect_parse_error(with(ok, "\"capillary\"", "\"glue\""), "cohesion");
  expect_parse_error(
      with(chain({1e-3, 1e-3}, {-1e-9}, "none"), "steps = 1", "steps = 1\nwater_content = 0.007"),
      "water_content");
  expect_parse_error(with(ok, "steps = 1", "steps = 1\nliquid_density = 1000.0"), "liquid_density");
  expect_parse_error(with(ok, "steps = 1", "steps = 1\nliquid_pairs = \"contacts\""),
                     "liquid_pairs");
  expect_parse_error(
      with(ok, "steps = 1", "steps = 1\nwater_content = 0.007\nliquid_pairs = \"gaps\""),
      "liquid_pairs");
  EXPECT_TRUE(parse_scenario(with(ok, "steps = 1",
                                  "steps = 1\nwater_content = 0.007\nliquid_pairs = \"contacts\""),
                             "w")
                  .stages[0]
                  .liquid_at_contacts_only);
  expect_parse_error(with(ok, "steps = 1", "steps = 1\nwater_content = -0.1"), "water_content");
  expect_parse_error(
      with(ok, "cohesion = \"capillary\"", "cohesion = \"capillary\"\ncontact_angle = 120.0"),
      "contact_angle");
  expect_parse_error(with(ok, "cohesion = \"capillary\"",
                          "cohesion = \"capillary\"\nruptured_liquid = \"evaporates\""),
                     "ruptured_liquid");
  expect_parse_error(with(chain({1e-3, 1e-3}, {-1e-9}, "none"), "cohesion = \"none\"",
                          "cohesion = \"none\"\nsurface_tension = 0.07"),
                     "surface_tension");
  expect_parse_error(with(ok, "dimension = 3", "dimension = 3\nsolver = \"cd\"\ndt = 1e-4"),
                     "cohesion");
}

// A snapshot holding bridges cannot be resumed by a dry scenario (its liquid would vanish):
// the error names the file; the world is left as it was.
TEST(Wetting, DryScenarioRefusesAWetSnapshot) {
  const auto path = std::filesystem::temp_directory_path() / "sable_test_wet_snapshot.h5";
  World<3> wet;
  build(chain({1e-3, 1e-3}, {-1e-9}), wet);
  wet_grains(wet, 0.01, 1000.0);
  save_snapshot(wet, RunPosition{}, "text", path.string());
  World<3> dry;
  build(chain({1e-3, 1e-3}, {-1e-9}, "none"), dry);
  const auto x0 = dry.particles.x;
  try {
    load_snapshot(path.string(), dry);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(path.string()), std::string::npos) << msg;
    EXPECT_NE(msg.find("cohesion"), std::string::npos) << msg;
  }
  EXPECT_EQ(dry.particles.x, x0);
  World<3> again;
  build(chain({1e-3, 1e-3}, {-1e-9}), again);
  load_snapshot(path.string(), again);
  EXPECT_EQ(again.neighbors.pairs.bridge, wet.neighbors.pairs.bridge);
  EXPECT_EQ(again.liquid.total, wet.liquid.total);
  std::filesystem::remove(path);
}

// A dry snapshot continued by a wet scenario (a dry deposit, then wetted by a stage's
// water_content) loads: its state hash is checked as the file was written (without bridges,
// which a dry law does not hash), and every pair starts without a bridge.
TEST(Wetting, WetScenarioResumesADrySnapshot) {
  const auto path = std::filesystem::temp_directory_path() / "sable_test_dry_snapshot.h5";
  World<3> dry;
  build(chain({1e-3, 1e-3, 1e-3}, {-1e-9, 2e-5}, "none"), dry);
  dry.particles.v[1] = {1e-3, -2e-3, 0.5e-3};  // a state the wet world does not have
  save_snapshot(dry, RunPosition{}, "text", path.string());
  World<3> wet;
  build(chain({1e-3, 1e-3, 1e-3}, {-1e-9, 2e-5}), wet);
  ASSERT_TRUE(wet.neighbors.bridges);
  ASSERT_NO_THROW(load_snapshot(path.string(), wet));
  EXPECT_EQ(wet.particles.v, dry.particles.v);
  EXPECT_EQ(wet.neighbors.pairs.i, dry.neighbors.pairs.i);
  ASSERT_EQ(wet.neighbors.pairs.bridge.size(), wet.neighbors.pairs.size());
  for (const double b : wet.neighbors.pairs.bridge) EXPECT_EQ(b, PairList<3>::kNoBridge);
  EXPECT_EQ(wet.liquid.total, 0.0);
  std::filesystem::remove(path);
}
