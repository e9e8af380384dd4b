// The load carried across a horizontal level (analysis/load_share.hpp): the balance
// W = F_cut + sum F_wall + F_fixed - sum m a.up, exact for any state, on a paddle sweeping
// grains (2D and 3D, a turning mesh wall among the supports), and the whole weight carried by
// the cut in a box with frictionless side walls at rest; then `sable analyze --only
// load-share` end to end.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <type_traits>

#include "mesh_world.hpp"
#include "run_helpers.hpp"
#include "sable/analysis/load_share.hpp"
#include "sable/analysis/sample.hpp"
#include "sable/core/error.hpp"
#include "sable/scenario/snapshot_sample.hpp"

namespace fs = std::filesystem;
using namespace sable;

namespace {

// The size of the terms of the balance: round-off is relative to it.
double scale(const LoadShare& r) {
  double s = r.weight + std::abs(r.cut) + std::abs(r.fixed) + std::abs(r.momentum_rate);
  for (double f : r.wall_support) s += std::abs(f);
  return s;
}

template <class Dim>
class LoadShareDim : public ::testing::Test {};
using Dims = ::testing::Types<std::integral_constant<int, 2>, std::integral_constant<int, 3>>;
TYPED_TEST_SUITE(LoadShareDim, Dims);

// A paddle (a mesh wall) turning among rows of grains on a floor, mid-sweep: grains collide,
// the paddle pushes the lower rows, a level between the rows cuts contacts. Summed over the
// grains above the level, each grain's m a = sum f + m g gives the balance exactly (the
// forces between two grains above cancel by Newton's third law), so the residual is round-off
// of sums of the same forces in another order: 1e-12 of the terms' size.
TYPED_TEST(LoadShareDim, BalanceIsExactWhileAPaddleSweepsTheGrains) {
  constexpr int D = TypeParam::value;
  World<D> w = test::mesh_world<D>();
  DemSolver<D> solver(w);
  solver.initialize();
  for (int k = 0; k < 400; ++k) solver.step();
  const Sample<D> s = make_sample(w);
  // 3D: between the floor layer (z ~ 0.005) and the second (z ~ 0.015); 2D: between the rows
  // beside the paddle (y = +-0.0095) and the row above it (y = 0.02).
  const double level = D == 3 ? 0.01 : 0.015;
  const LoadShare r = load_share(s, level);
  EXPECT_GT(r.grains_above, 0u);
  EXPECT_GT(r.cut_contacts, 0u);
  EXPECT_GT(std::abs(r.momentum_rate), 1e-3 * r.weight);  // not at rest: the test has teeth
  EXPECT_LT(std::abs(r.residual()), 1e-12 * scale(r))
      << "W " << r.weight << " cut " << r.cut << " m a " << r.momentum_rate;
  // Below every grain: the whole weight, carried by the floor and the paddle (which by now
  // pushes grains of the lower rows), nothing cut.
  const LoadShare all = load_share(s, -1.0);
  EXPECT_EQ(all.grains_above, s.size());
  EXPECT_EQ(all.cut, 0.0);
  ASSERT_EQ(all.wall_names.size(), 2u);
  EXPECT_EQ(all.wall_names[test::kPaddle], "paddle");
  EXPECT_NE(all.wall_support[test::kPaddle], 0.0);
  EXPECT_GT(std::abs(all.momentum_rate), 1e-3 * all.weight);
  EXPECT_LT(std::abs(all.residual()), 1e-12 * scale(all))
      << "W " << all.weight << " paddle " << all.wall_support[test::kPaddle] << " floor "
      << all.wall_support[0] << " m a " << all.momentum_rate;
  // Above every grain: nothing.
  const LoadShare none = load_share(s, 1.0);
  EXPECT_EQ(none.grains_above, 0u);
  EXPECT_EQ(none.weight, 0.0);
}

// 150 spheres in a box whose walls are frictionless, fallen then settled to rest under the
// damping drag of the second stage (nu = 100 / s for 0.3 s). A frictionless
// plane wall pushes along its normal only, horizontal for the side walls: their vertical
// support is zero (to round-off of the normal, 1e-12 W). So the cut carries the weight above it
// less the momentum rate, and at rest that is all of it.
std::string settled_box(const std::string& out) {
  std::ostringstream s;
  s << "[simulation]\ndimension = 3\nseed = 4\ngravity = [0, 0, -9.81]\n"
    << "[domain]\nlo = [0, 0, 0]\nhi = [0.01, 0.01, 0.03]\n"
    << "[[material]]\nname = \"g\"\ndensity = 2500.0\nyoung = 5e6\npoisson = 0.45\n"
    << "restitution = 0.3\nfriction = 0.4\n"
    << "[[material]]\nname = \"slick\"\ndensity = 2500.0\nyoung = 5e6\npoisson = 0.45\n"
    << "restitution = 0.3\nfriction = 0.0\n"
    << "[[grains]]\ngenerator = \"lattice\"\nmaterial = \"g\"\n"
    << "radius = { distribution = \"uniform\", mean = 1e-3, spread = 0.1 }\nspacing = 2.5e-3\n"
    << "jitter = 1e-4\nregion = { box = { lo = [0, 0, 0], hi = [0.01, 0.01, 0.03] } }\n"
    << "count = 150\n"
    << "[[wall]]\nname = \"box\"\ntype = \"box\"\nmaterial = \"slick\"\nlo = [0, 0, 0]\n"
    << "hi = [0.01, 0.01, 0.03]\n"
    << "[[stage]]\nname = \"fall\"\nsteps = 4000\n"
    << "[[stage]]\nname = \"settle\"\nsteps = 12000\nviscous_damping = 100\n"
    << "[output]\ndir = \"" << out << "\"\ncsv_interval = 0\nsnapshot_interval = 8000\n"
    << "vtk_interval = 0\nlog_interval = 0\n";
  return s.str();
}

TEST(LoadShare, AtRestInAFrictionlessBoxTheCutCarriesTheWeightAbove) {
  const fs::path dir = fs::temp_directory_path() / "sable_test_load_share_box";
  fs::remove_all(dir);
  test::run_text(settled_box((dir / "run").string()));
  const std::string snap = (dir / "run" / "snapshots" / "end_of_stage_2.h5").string();
  const Sample<3> s = load_sample<3>(snap);
  const double level = 0.006;  // a few layers up, away from the floor
  const LoadShare r = load_share(s, level);
  ASSERT_GT(r.grains_above, 30u);
  ASSERT_LT(r.grains_above, s.size() - 30);
  EXPECT_LT(std::abs(r.residual()), 1e-12 * scale(r));
  for (std::size_t w = 0; w < r.wall_names.size(); ++w)
    EXPECT_LE(std::abs(r.wall_support[w]), 1e-12 * r.weight) << r.wall_names[w];
  // At rest (the momentum rate measures 2e-7 W here; 1e-5 leaves room for another compiler's
  // round-off in the settling): the cut carries W.
  EXPECT_LT(std::abs(r.momentum_rate), 1e-5 * r.weight);
  EXPECT_NEAR(r.cut / r.weight, 1.0, 1e-5);

  // The command: load_share.csv (one row per snapshot) and the summary, averaged over two.
  std::string out;
  const std::string snaps = (dir / "run" / "snapshots" / "step_*.h5").string();
  ASSERT_EQ(test::run_cli("analyze " + snaps + " --level 0.006 --only load-share --out " +
                              (dir / "an").string(),
                          dir / "log.txt", out),
            0)
      << out;
  const std::string csv = test::slurp(dir / "an" / "load_share.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "time_s,grains_above,weight_N,cut_N,wall_box.xlo_N,wall_box.xhi_N,wall_box.ylo_N,"
            "wall_box.yhi_N,wall_box.zlo_N,wall_box.zhi_N,fixed_grains_N,momentum_rate_N,"
            "residual_N");
  const std::string summary = test::slurp(dir / "an" / "summary.json");
  for (const char* key : {"\"load_share\"", "\"snapshots\": 2", "\"max_abs_residual_over_weight\"",
                          "\"box.zlo\"", "\"share\""})
    EXPECT_NE(summary.find(key), std::string::npos) << key << "\n" << summary;
  fs::remove_all(dir);
}

// No gravity: no vertical, an error naming the sample.
TEST(LoadShare, NeedsGravity) {
  Sample<3> s;
  s.source = "weightless.h5";
  try {
    load_share(s, 0.0);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("weightless.h5"), std::string::npos) << e.what();
  }
}

}  // namespace
