// The DEM step's per-grain kernels (src/sable/dem/passes.hpp) and the run guard's two halves
// (src/sable/world/guards.hpp): what the drift measures for the lists' staleness tests must
// be exactly what a separate scan would measure (the lists are rebuilt on it), the kick and
// drift must be the textbook operations, and the guard must refuse exactly the non-finite or
// runaway states. Exact comparisons throughout: the same operations in the same order.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "sable/collision/neighbor_list.hpp"
#include "sable/core/particles.hpp"
#include "sable/core/rng.hpp"
#include "sable/dem/dem_solver.hpp"
#include "sable/dem/passes.hpp"
#include "sable/world/guards.hpp"

#include "geometry_helpers.hpp"

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// position_ok: every finite position passes, even the largest (x - x is 0 there too); an
// infinite or NaN coordinate fails, in any component, in 2D and 3D. motion_ok: a speed up to
// max_speed passes, above it fails, and so does any non-finite velocity or spin.
TEST(Guards, PositionAndMotionTests) {
  const double big = std::numeric_limits<double>::max();
  EXPECT_TRUE(sable::position_ok<3>(Eigen::Vector3d(1.0, -2.0, 3.0)));
  EXPECT_TRUE(sable::position_ok<3>(Eigen::Vector3d(big, -big, big)));
  EXPECT_TRUE(sable::position_ok<2>(Eigen::Vector2d(-big, 0.0)));
  for (int c = 0; c < 3; ++c)
    for (double bad : {kInf, -kInf, kNaN}) {
      Eigen::Vector3d x(1.0, 2.0, 3.0);
      x[c] = bad;
      EXPECT_FALSE(sable::position_ok<3>(x)) << "component " << c << " = " << bad;
      if (c < 2) {
        Eigen::Vector2d x2(1.0, 2.0);
        x2[c] = bad;
        EXPECT_FALSE(sable::position_ok<2>(x2)) << "2D component " << c << " = " << bad;
      }
    }
  const Eigen::Vector3d w(1.0, 2.0, 3.0);
  EXPECT_TRUE(sable::motion_ok<3>(Eigen::Vector3d(3.0, 4.0, 0.0), w, 5.0));  // |v| = max
  EXPECT_FALSE(sable::motion_ok<3>(Eigen::Vector3d(3.0, 4.0, 1e-6), w, 5.0));
  EXPECT_FALSE(sable::motion_ok<3>(Eigen::Vector3d(kNaN, 0.0, 0.0), w, 5.0));
  EXPECT_FALSE(
      sable::motion_ok<3>(Eigen::Vector3d(0.0, 0.0, 0.0), Eigen::Vector3d(0, kInf, 0), 5.0));
  EXPECT_FALSE(sable::motion_ok<2>(Eigen::Vector2d(0.0, 0.0), kNaN, 5.0));
  // Spins are only required finite, tested through their square (so up to ~1e154 rad/s).
  EXPECT_TRUE(sable::motion_ok<2>(Eigen::Vector2d(0.0, 1.0), 1e150, 5.0));
}

// The opening half of a DEM step over random grains, one of them fixed: velocities and
// positions are the half kick and drift written out (with background damping), the fixed
// grain stays, and the displacements since the two references are exactly the maxima a
// separate scan (max_displacement2, what the lists' own tests use) finds. Without references
// of the right size the maxima are infinite (the lists are stale anyway); a non-finite
// position sets the flag.
template <int D>
void check_drift_pass() {
  using Vec = typename sable::Space<D>::Vec;
  using Rot = typename sable::Space<D>::Rot;
  sable::Rng rng(42);
  sable::ParticleStore<D> p;
  sable::test::add_random_grains(p, rng, 500, 0.01, 0.02);
  for (std::size_t k = 0; k < p.size(); ++k) {
    p.v[k] = sable::test::random_vec<D>(rng, -1.0, 1.0);
    p.f[k] = sable::test::random_vec<D>(rng, -1e-3, 1e-3);
    if constexpr (D == 3) {
      p.w[k] = sable::test::random_vec<3>(rng, -10.0, 10.0);
      p.t[k] = sable::test::random_vec<3>(rng, -1e-6, 1e-6);
    } else {
      p.w[k] = rng.uniform(-10.0, 10.0);
      p.t[k] = rng.uniform(-1e-6, 1e-6);
    }
  }
  p.inv_mass[7] = 0.0;  // a fixed grain
  p.inv_inertia[7] = 0.0;
  std::vector<Vec> ref_build = p.x, ref_near = p.x;
  for (auto& x : ref_build) x += sable::test::random_vec<D>(rng, -1e-3, 1e-3);
  for (auto& x : ref_near) x += sable::test::random_vec<D>(rng, -1e-4, 1e-4);
  const sable::ParticleStore<D> before = p;
  const Vec g = sable::test::random_vec<D>(rng, -10.0, 10.0);
  const double h = 0.5e-4, h_drift = 1e-4, keep = 1.0 / (1.0 + 3.0 * h);
  const sable::dem::DriftPass<D> pass{p.x.data(),
                                      p.v.data(),
                                      p.q.data(),
                                      p.w.data(),
                                      p.f.data(),
                                      p.t.data(),
                                      p.inv_mass.data(),
                                      p.inv_inertia.data(),
                                      ref_build.data(),
                                      ref_near.data(),
                                      g,
                                      h,
                                      h_drift,
                                      keep,
                                      false};
  sable::dem::DriftMax m;
  for (std::size_t k = 0; k < p.size(); ++k) pass.grain(k, m);
  m = pass.settle(m);
  for (std::size_t k = 0; k < p.size(); ++k) {
    if (k == 7) {
      EXPECT_TRUE(p.x[k] == before.x[k] && p.v[k] == before.v[k]) << "the fixed grain moved";
      continue;
    }
    const Vec v = (before.v[k] + h * (before.f[k] * before.inv_mass[k] + g)) * keep;
    const Rot w = (before.w[k] + h * before.inv_inertia[k] * before.t[k]) * keep;
    ASSERT_TRUE(p.v[k] == v) << "grain " << k;
    ASSERT_TRUE(p.w[k] == w) << "grain " << k;
    ASSERT_TRUE(p.x[k] == before.x[k] + h_drift * v) << "grain " << k;
  }
  EXPECT_EQ(m.since_build, sable::max_displacement2<D>(p.x, ref_build));
  EXPECT_EQ(m.since_near, sable::max_displacement2<D>(p.x, ref_near));
  EXPECT_GT(m.since_near, 0.0);
  EXPECT_EQ(m.bad, 0);

  sable::dem::DriftPass<D> unreferenced = pass;
  unreferenced.x_build = nullptr;
  unreferenced.x_near = nullptr;
  p.x[3][0] = kNaN;
  sable::dem::DriftMax n;
  for (std::size_t k = 0; k < p.size(); ++k) unreferenced.grain(k, n);
  n = unreferenced.settle(n);
  EXPECT_EQ(n.since_build, kInf);
  EXPECT_EQ(n.since_near, kInf);
  EXPECT_NE(n.bad, 0);
}

TEST(DemPasses, DriftMeasuresWhatTheListsTestIn3D) {
  check_drift_pass<3>();
}
TEST(DemPasses, DriftMeasuresWhatTheListsTestIn2D) {
  check_drift_pass<2>();
}

// needs_rebuild_after / stale_after, given the displacement a separate scan measures, decide
// exactly as needs_rebuild / stale, which measure it themselves: random walks that cross both
// criteria many times.
TEST(DemPasses, StalenessFromAMeasuredDisplacementDecidesAlike) {
  sable::Rng rng(5);
  sable::ParticleStore<3> p;
  sable::test::add_random_grains(p, rng, 200, 0.04, 0.06);
  sable::NeighborList<3> nl;
  nl.skin = 0.01;
  nl.domain_hi = Eigen::Vector3d::Ones();
  nl.build(p, {});
  sable::NearList<3> near;
  near.remake(p, nl, 1.0, false, [](std::size_t) {});
  int rebuilds = 0, stale = 0;
  for (int step = 0; step < 300; ++step) {
    for (auto& x : p.x) x += sable::test::random_vec<3>(rng, -4e-4, 4e-4);
    const bool rebuild = nl.needs_rebuild(p, {});
    EXPECT_EQ(nl.needs_rebuild_after(sable::max_displacement2<3>(p.x, nl.x_ref), p, {}), rebuild);
    if (rebuild) {
      nl.build(p, {});
      ++rebuilds;
    }
    const bool is_stale = near.stale(p, nl, false);
    if (near.reference().size() == p.size()) {
      EXPECT_EQ(near.stale_after(sable::max_displacement2<3>(p.x, near.reference()), p, nl, false),
                is_stale);
    }
    if (is_stale) {
      near.remake(p, nl, 1.0, false, [](std::size_t) {});
      ++stale;
    }
  }
  EXPECT_GT(rebuilds, 5);  // both criteria were crossed often
  EXPECT_GT(stale, 20);
}

}  // namespace
