// Contact dynamics (Moreau-Jean + NLGS) against rigid-body statics and dynamics solved by hand.
// Rigid grains make these exact: the only errors are the NLGS tolerance (set tight here,
// 1e-12 on the natural-map residual) and round-off, hence tolerances of 1e-6 or tighter.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <numbers>
#include <string>

#include "sable/cd/cd_solver.hpp"

namespace {

using sable::cd::LocalSolver;

template <int D>
sable::World<D> rigid_world(double mu, double dt) {
  sable::World<D> w;
  w.materials.add({"grain", 2500.0, 0.0, 0.0, 0.0, mu});
  w.materials.finalize();
  w.neighbors.skin = 0.2e-3;
  w.neighbors.domain_lo.setConstant(-0.05);
  w.neighbors.domain_hi.setConstant(0.05);
  w.dt = dt;
  return w;
}

template <int D>
void add_plane(sable::World<D>& w, typename sable::Space<D>::Vec point,
               typename sable::Space<D>::Vec normal) {
  sable::Wall<D> wall;
  wall.point = point;
  wall.set_plane(normal.normalized());
  w.walls.push_back(wall);
}

sable::CdSettings tight(LocalSolver local = LocalSolver::kBipotential) {
  sable::CdSettings s;
  s.nlgs.tolerance = 1e-12;
  s.nlgs.max_iterations = 100000;
  s.nlgs.local = local;
  return s;
}

// Force carried by the candidate pair (i, j) (either order), along +n from j to i.
template <int D>
double pair_normal_force(const sable::World<D>& w, std::uint32_t a, std::uint32_t b) {
  const auto& pl = w.neighbors.pairs;
  for (std::size_t k = 0; k < pl.size(); ++k)
    if ((pl.i[k] == a && pl.j[k] == b) || (pl.i[k] == b && pl.j[k] == a)) {
      const auto n = (w.particles.x[pl.i[k]] - w.particles.x[pl.j[k]]).normalized();
      return pl.force[k].dot(n);
    }
  return 0.0;
}

class ColumnTest : public ::testing::TestWithParam<LocalSolver> {};

void column_of_disks(LocalSolver local, sable::cd::SweepOrder order);

// A frictionless column of N touching disks between two side walls that touch them, on a
// floor: the contact between the k-th and (k+1)-th disk from the top carries k m g, the floor
// N m g, the side walls nothing (Dumont-Fortin-Ouafik's regular arrays, the simplest one).
// In the forward order and in the coloured one (one contact per block: neighbours along the
// column take alternate colours).
TEST_P(ColumnTest, FrictionlessColumnOfDisks) {
  for (const auto order : {sable::cd::SweepOrder::kForward, sable::cd::SweepOrder::kColoured}) {
    SCOPED_TRACE(std::string(sable::cd::to_string(order)));
    column_of_disks(GetParam(), order);
  }
}

void column_of_disks(LocalSolver local, sable::cd::SweepOrder order) {
  const int n = 10;
  const double r = 1e-3, g = 9.81;
  auto w = rigid_world<2>(0.0, 1e-4);
  w.gravity = {0, -g};
  for (int k = 0; k < n; ++k) w.particles.add({0.0, r + 2 * r * k}, r, 2500.0, 0, 1.0);
  add_plane<2>(w, {0, 0}, {0, 1});   // floor
  add_plane<2>(w, {-r, 0}, {1, 0});  // left wall, touching
  add_plane<2>(w, {r, 0}, {-1, 0});  // right wall, touching
  sable::CdSettings cs = tight(local);
  cs.nlgs.order = order;
  cs.colour_block = 1;
  sable::CdSolver<2> s(w, cs);
  s.initialize();
  for (int step = 0; step < 5; ++step) s.step();
  ASSERT_TRUE(s.last_solve().converged) << s.last_solve().residual;
  const double mg = w.particles.mass[0] * g;
  for (int k = 1; k < n; ++k) {
    // Slot n - k is the k-th disk from the top; it rests on slot n - k - 1.
    const double f = pair_normal_force(w, static_cast<std::uint32_t>(n - k),
                                       static_cast<std::uint32_t>(n - k - 1));
    EXPECT_NEAR(f, k * mg, 1e-6 * k * mg) << "contact " << k << " from the top";
  }
  EXPECT_NEAR(-w.walls[0].force.y(), n * mg, 1e-6 * n * mg);
  EXPECT_NEAR(w.walls[1].force.norm(), 0.0, 1e-9 * mg);
  EXPECT_NEAR(w.walls[2].force.norm(), 0.0, 1e-9 * mg);
}

INSTANTIATE_TEST_SUITE_P(LocalSolvers, ColumnTest,
                         ::testing::Values(LocalSolver::kBipotential, LocalSolver::kExact));

// The coloured, threaded sweep (cd/colouring.hpp) on the column's problem many times over: a
// simple cubic stack of 12 x 12 x 12 touching frictionless spheres in a box whose side walls
// touch it. Each column carries its own weight (the k-th contact from the top k m g, the
// floor 12 m g per column); the sideways contacts and walls nothing. About 5,500 contacts:
// the sweep runs on the threads (above nlgs_impl.hpp's kMinParallelContacts), in blocks of 4
// contacts, and two threads give the one thread's forces to the bit.
TEST(CdStatics, ColouredSweepOnThreadsCarriesEachColumnsWeight) {
  const int n = 12;
  const double r = 1e-3, g = 9.81;
  const auto run = [&](int threads) {
    auto w = rigid_world<3>(0.0, 1e-4);
    w.gravity = {0, 0, -g};
    w.reorder_every = 0;  // slots stay where they were added (slot() below)
    for (int z = 0; z < n; ++z)
      for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
          w.particles.add({r + 2 * r * x, r + 2 * r * y, r + 2 * r * z}, r, 2500.0, 0, 1.0);
    add_plane<3>(w, {0, 0, 0}, {0, 0, 1});
    add_plane<3>(w, {0, 0, 0}, {1, 0, 0});
    add_plane<3>(w, {2 * r * n, 0, 0}, {-1, 0, 0});
    add_plane<3>(w, {0, 0, 0}, {0, 1, 0});
    add_plane<3>(w, {0, 2 * r * n, 0}, {0, -1, 0});
    sable::CdSettings cs = tight(LocalSolver::kExact);
    cs.nlgs.order = sable::cd::SweepOrder::kColoured;
    cs.colour_block = 4;
    const int before = omp_get_max_threads();
    omp_set_num_threads(threads);
    sable::CdSolver<3> s(w, cs);
    s.initialize();
    for (int step = 0; step < 3; ++step) s.step();
    omp_set_num_threads(before);
    EXPECT_TRUE(s.last_solve().converged) << s.last_solve().residual;
    EXPECT_GT(s.diagnostics().touching, 0u);
    return w;
  };
  const auto w = run(1);
  const double mg = w.particles.mass[0] * g;
  const auto slot = [&](int x, int y, int z) {
    return static_cast<std::uint32_t>(x + n * (y + n * z));
  };
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x)
      for (int z = 1; z < n; ++z) {
        const int above = n - z;  // grains resting on this contact
        EXPECT_NEAR(pair_normal_force(w, slot(x, y, z), slot(x, y, z - 1)), above * mg,
                    1e-6 * above * mg);
        if (x > 0) {
          EXPECT_NEAR(pair_normal_force(w, slot(x, y, z), slot(x - 1, y, z)), 0.0, 1e-9 * mg);
        }
      }
  EXPECT_NEAR(-w.walls[0].force.z(), n * n * n * mg, 1e-6 * n * n * n * mg);
  for (int k = 1; k < 5; ++k) EXPECT_NEAR(w.walls[k].force.norm(), 0.0, 1e-9 * mg) << "wall " << k;
  // Two threads: the same forces, bit for bit.
  const auto w2 = run(2);
  const auto& pl = w.neighbors.pairs;
  ASSERT_EQ(pl.size(), w2.neighbors.pairs.size());
  for (std::size_t k = 0; k < pl.size(); ++k)
    ASSERT_EQ(pl.force[k], w2.neighbors.pairs.force[k]) << k;
  for (std::size_t k = 0; k < w.particles.size(); ++k)
    ASSERT_EQ(w.particles.x[k], w2.particles.x[k]);
}

// Cannon ball in 2D: a disk on two disks held apart by walls, frictionless. Each upper
// contact carries W / (2 cos 30), each wall W tan 30 / 2, and the lower disks (separated by
// 1e-9 R, so the split of horizontal forces is unique) do not push each other.
TEST(CdStatics, CannonBall2D) {
  const double r = 1e-3, g = 9.81, eps = 1e-9 * r;
  auto w = rigid_world<2>(0.0, 1e-4);
  w.gravity = {0, -g};
  const double half = r + 0.5 * eps;  // half the distance between the lower centres
  w.particles.add({-half, r}, r, 2500.0, 0, 1.0);
  w.particles.add({half, r}, r, 2500.0, 0, 1.0);
  w.particles.add({0.0, r + std::sqrt(4 * r * r - half * half)}, r, 2500.0, 0, 1.0);
  add_plane<2>(w, {0, 0}, {0, 1});
  add_plane<2>(w, {-half - r, 0}, {1, 0});
  add_plane<2>(w, {half + r, 0}, {-1, 0});
  sable::CdSolver<2> s(w, tight());
  s.initialize();
  for (int step = 0; step < 5; ++step) s.step();
  const double W = w.particles.mass[2] * g;
  const double c30 = std::cos(std::numbers::pi / 6), t30 = std::tan(std::numbers::pi / 6);
  EXPECT_NEAR(pair_normal_force(w, 2, 0), W / (2 * c30), 1e-6 * W);
  EXPECT_NEAR(pair_normal_force(w, 2, 1), W / (2 * c30), 1e-6 * W);
  EXPECT_NEAR(pair_normal_force(w, 0, 1), 0.0, 1e-9 * W);
  EXPECT_NEAR(w.walls[1].force.norm(), W * t30 / 2, 1e-6 * W);
  EXPECT_NEAR(w.walls[2].force.norm(), W * t30 / 2, 1e-6 * W);
  EXPECT_NEAR(-w.walls[0].force.y(), 3 * w.particles.mass[0] * g, 1e-6 * W);
}

// A sphere resting on a plane: normal force m g, and no drift of its position over 10,000
// steps (rigid contact, gap-based Signorini: it neither sinks nor jitters).
TEST(CdStatics, SphereRestsOnPlaneWithoutDrift) {
  const double r = 1e-3, g = 9.81;
  auto w = rigid_world<3>(0.5, 1e-4);
  w.gravity = {0, 0, -g};
  w.particles.add({0.001, -0.002, r}, r, 2500.0, 0, 1.0);
  add_plane<3>(w, {0, 0, 0}, {0, 0, 1});
  sable::CdSolver<3> s(w, tight());
  s.initialize();
  const Eigen::Vector3d x0 = w.particles.x[0];
  for (int step = 0; step < 10000; ++step) s.step();
  EXPECT_NEAR(-w.walls[0].force.z(), w.particles.mass[0] * g, 1e-9 * w.particles.mass[0] * g);
  EXPECT_LT((w.particles.x[0] - x0).norm(), 1e-12 * r);
}

// An overlap is kept (overlap_recovery = 0, the default) or a share beta of it removed in a
// step (CdSettings::overlap_recovery): a sphere at rest overlapping a plane by g0, no gravity,
// must leave the step with U_N + beta g0 / h = 0 (its normal unknown at zero, the impulse
// positive), so it separates at beta g0 / h and moves out by beta g0: overlap (1 - beta) g0.
// Exact for a rigid sphere: 1e-12 relative (a few roundings).
TEST(CdStatics, OverlapRecoveryRemovesItsShare) {
  const double r = 1e-3, g0 = 1e-5, h = 1e-4;
  for (const double beta : {0.0, 0.25}) {
    auto w = rigid_world<3>(0.5, h);
    w.particles.add({0.0, 0.0, r - g0}, r, 2500.0, 0, 1.0);
    add_plane<3>(w, {0, 0, 0}, {0, 0, 1});
    sable::CdSettings cs = tight();
    cs.overlap_recovery = beta;
    sable::CdSolver<3> s(w, cs);
    s.initialize();
    s.step();
    EXPECT_NEAR(w.particles.x[0].z(), r - (1.0 - beta) * g0, 1e-12 * r) << beta;
    EXPECT_NEAR(w.particles.v[0].z(), beta * g0 / h, 1e-12 * std::max(beta * g0 / h, 1e-6)) << beta;
    EXPECT_NEAR(w.particles.v[0].x(), 0.0, 1e-15);
  }
}

// A sphere dropped from 5 mm onto a plane stops there: no bounce (Moreau's impact law with
// zero restitution) and no penetration (the gap closes exactly within the step).
TEST(CdStatics, PerfectlyInelasticImpact) {
  const double r = 1e-3, g = 9.81;
  auto w = rigid_world<3>(0.3, 1e-4);
  w.gravity = {0, 0, -g};
  w.particles.add({0, 0, r + 5e-3}, r, 2500.0, 0, 1.0);
  add_plane<3>(w, {0, 0, 0}, {0, 0, 1});
  sable::CdSolver<3> s(w, tight());
  s.initialize();
  double min_z = 1.0;
  for (int step = 0; step < 1000; ++step) {
    s.step();
    min_z = std::min(min_z, w.particles.x[0].z());
  }
  EXPECT_GE(min_z, r * (1 - 1e-12));                // never below the plane
  EXPECT_NEAR(w.particles.x[0].z(), r, 1e-12 * r);  // resting on it
  EXPECT_LT(w.particles.v[0].norm(), 1e-12);        // at rest, no bounce
}

// Rolling and sliding on an incline, rigid-body theory: rolling without slip
// a = g sin / (1 + I/(m R^2)) (2/3 g sin for a disk, 5/7 g sin for a sphere) when
// mu >= tan / (1 + m R^2 / I); otherwise sliding with a = g (sin - mu cos). Rigid contact
// makes the motion uniformly accelerated: the velocity after n steps is checked to 1e-6.
template <int D>
double incline_acceleration(double theta, double mu) {
  const double r = 1e-3, g = 9.81;
  auto w = rigid_world<D>(mu, 1e-4);
  typename sable::Space<D>::Vec down = sable::Space<D>::Vec::Zero(), normal = down;
  down[0] = std::sin(theta);
  down[D - 1] = -std::cos(theta);
  normal[D - 1] = 1.0;
  w.gravity = g * down;  // the incline is the plane z = 0 (y = 0 in 2D), gravity tilted
  typename sable::Space<D>::Vec x = sable::Space<D>::Vec::Zero();
  x[D - 1] = r;
  w.particles.add(x, r, 2500.0, 0, 1.0);
  add_plane<D>(w, sable::Space<D>::Vec::Zero(), normal);
  sable::CdSolver<D> s(w, tight());
  s.initialize();
  const int n = 2000;
  for (int step = 0; step < n; ++step) s.step();
  return w.particles.v[0][0] / (n * w.dt);
}

TEST(CdDynamics, DiskAndSphereOnIncline) {
  const double g = 9.81, theta = 20.0 * std::numbers::pi / 180.0;
  const double sn = std::sin(theta), cs = std::cos(theta);
  // Rolling: mu = 0.5 is above tan/3 (disk) = 0.121 and 2 tan/7 (sphere) = 0.104.
  EXPECT_NEAR(incline_acceleration<2>(theta, 0.5), 2.0 / 3.0 * g * sn, 1e-6 * g);
  EXPECT_NEAR(incline_acceleration<3>(theta, 0.5), 5.0 / 7.0 * g * sn, 1e-6 * g);
  // Sliding: mu = 0.05 is below both thresholds.
  EXPECT_NEAR(incline_acceleration<2>(theta, 0.05), g * (sn - 0.05 * cs), 1e-6 * g);
  EXPECT_NEAR(incline_acceleration<3>(theta, 0.05), g * (sn - 0.05 * cs), 1e-6 * g);
}

}  // namespace
