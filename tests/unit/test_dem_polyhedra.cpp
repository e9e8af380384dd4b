// DEM with polyhedral grains (dem/polyhedral_dem.hpp): a linear spring per overlapping point
// of the contact manifold, acting as one contact at the points' depth-weighted centre. Each
// test checks the law against statics or an exact solution of its own equations.
#include <gtest/gtest.h>
#include <omp.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <random>
#include <vector>

#include "polyhedra_helpers.hpp"
#include "sable/contact/registry.hpp"
#include "sable/core/error.hpp"
#include "sable/dem/dem_solver.hpp"
#include "sable/geometry/polyhedron_contact.hpp"
#include "sable/geometry/polyhedron_plane.hpp"
#include "sable/io/snapshot.hpp"
#include "sable/world/critical_time.hpp"
#include "sable/world/polyhedral_grains.hpp"
#include "sable/world/state_hash.hpp"

namespace {

using Vec = Eigen::Vector3d;
using Quat = Eigen::Quaterniond;

constexpr double kG = 9.81;
constexpr double kA = 0.01;  // cube side (m)
constexpr double kRho = 2500.0;
constexpr double kKn = 1e4;  // N/m per contact point

// Linear law, restitution e, friction mu; dt a fiftieth of a four-point contact's
// sqrt(m / 4 kn) = 2.5e-4 s.
sable::World<3> soft_world(double e, double mu, double dt = 5e-6) {
  sable::World<3> w = sable::test::polyhedra_world(kA, dt, 0.1);
  w.materials.add({"grain", kRho, 1e7, 0.3, e, mu, 0.0});
  w.materials.finalize();
  w.model.normal = sable::NormalLaws::id<sable::LinearNormal>();
  w.model.kn = kKn;
  w.model.kt = 0.8 * kKn;
  return w;
}

void add_plane(sable::World<3>& w, const Vec& normal) {
  sable::Wall<3> wall;
  wall.name = "plane";
  wall.set_plane(normal.normalized());
  w.walls.push_back(wall);
}

// The four springs' forces k_n delta_p of a grain's manifold against the plane z = 0.
std::vector<double> corner_loads_on_plane(const sable::World<3>& w, std::size_t g) {
  const auto& p = w.particles;
  const sable::PolyhedronContact c = sable::polyhedron_plane_contact(
      w.shapes[p.shape_index[g]].solid, p.x[g], p.q[g], Vec::Zero(), Vec::UnitZ(), 0.0);
  std::vector<double> loads;
  for (int t = 0; t < c.count; ++t) loads.push_back(-kKn * c.points[t].gap);
  return loads;
}

// A cube settled face-down on a plane: four corners, each carrying m g / 4 within 1 % (the
// residual oscillation after 60 damped periods is far below that), the wall's force m g.
TEST(DemPolyhedra, CubeAtRestPutsAQuarterOfItsWeightOnEachCorner) {
  sable::World<3> w = soft_world(0.2, 0.5);
  add_plane(w, Vec::UnitZ());
  sable::add_polyhedral_grain(
      w, sable::test::box_points(Vec(-0.5, -0.5, 0) * kA, Vec(0.5, 0.5, 1) * kA), kRho, 0);
  sable::DemSolver<3> s(w);
  s.initialize();
  for (int k = 0; k < 3000; ++k) s.step();  // 15 ms: 60 periods of the four springs
  const double mg = w.particles.mass[0] * kG;
  const std::vector<double> loads = corner_loads_on_plane(w, 0);
  ASSERT_EQ(loads.size(), 4u);
  for (double f : loads) EXPECT_NEAR(f, 0.25 * mg, 0.01 * 0.25 * mg);
  EXPECT_NEAR(-w.walls[0].force.z(), mg, 0.01 * mg);
}

// A cube on a fixed cube, flush: the manifold's four points each carry m g / 4 (1 %).
TEST(DemPolyhedra, CubeAtRestOnACube) {
  sable::World<3> w = soft_world(0.2, 0.5);
  w.gravity = Vec(0.0, 0.0, -kG);
  sable::add_polyhedral_grain(
      w, sable::test::box_points(Vec(-0.5, -0.5, -1) * kA, Vec(0.5, 0.5, 0) * kA), kRho, 0, true);
  sable::add_polyhedral_grain(
      w, sable::test::box_points(Vec(-0.5, -0.5, 0) * kA, Vec(0.5, 0.5, 1) * kA), kRho, 0);
  sable::DemSolver<3> s(w);
  s.initialize();
  for (int k = 0; k < 3000; ++k) s.step();
  const auto& p = w.particles;
  const std::size_t top = p.ids.slot(p.id[1]), bottom = 1 - top;
  const double mg = p.mass[top] * kG;
  const sable::PolyhedronContact c = sable::polyhedron_contact(
      w.shapes[p.shape_index[top]].solid, p.x[top], p.q[top], w.shapes[p.shape_index[bottom]].solid,
      p.x[bottom], p.q[bottom], 0.0);
  ASSERT_EQ(c.count, 4);
  for (int t = 0; t < 4; ++t) EXPECT_NEAR(-kKn * c.points[t].gap, 0.25 * mg, 0.01 * 0.25 * mg);
  EXPECT_NEAR(w.neighbors.pairs.force[0].norm(), mg, 0.01 * mg);
}

// A cube dropped flat on a plane (no gravity, no friction): its four corners land together and
// it leaves with e times its speed. The dashpot of four springs in parallel makes e exact for
// the linear law with attractive damping (the force is then linear for the whole contact);
// 1 % covers the step's discretisation (50 steps per contact period).
TEST(DemPolyhedra, FlatImpactKeepsTheRestitution) {
  for (const double e : {0.3, 0.8}) {
    sable::World<3> w = soft_world(e, 0.0);
    w.gravity.setZero();
    w.model.attractive_damping = true;
    add_plane(w, Vec::UnitZ());
    sable::add_polyhedral_grain(
        w, sable::test::box_points(Vec(-0.5, -0.5, 0.001) * kA, Vec(0.5, 0.5, 1.001) * kA), kRho,
        0);
    w.particles.v[0] = Vec(0.0, 0.0, -0.1);
    sable::DemSolver<3> s(w);
    s.initialize();
    for (int k = 0; k < 2000; ++k) s.step();
    EXPECT_NEAR(w.particles.v[0].z(), 0.1 * e, 0.01 * 0.1 * e) << "e = " << e;
    EXPECT_LT(w.particles.omega[0].norm(), 1e-9) << "a flat landing does not turn it";
  }
}

// A cube on an incline (mu = 0.5): at 20 degrees (tan < mu) it holds (its speed dies out);
// at 35 degrees it slides with a = g (sin - mu cos), measured over the last 20 ms (1 %: the
// normal springs' settling is damped out by then).
TEST(DemPolyhedra, CubeOnInclineSticksOrSlides) {
  const double mu = 0.5;
  for (const double deg : {20.0, 35.0}) {
    const double theta = deg * std::numbers::pi / 180.0;
    const Vec downhill(-std::cos(theta), 0.0, -std::sin(theta));
    sable::World<3> w = soft_world(0.2, mu);
    add_plane(w, Vec(-std::sin(theta), 0.0, std::cos(theta)));
    const Quat q(Eigen::AngleAxisd(-theta, Vec::UnitY()));
    sable::add_polyhedral_grain(
        w, sable::test::box_points(Vec(-0.5, -0.5, 0) * kA, Vec(0.5, 0.5, 1) * kA, q), kRho, 0);
    sable::DemSolver<3> s(w);
    s.initialize();
    for (int k = 0; k < 4000; ++k) s.step();
    const double v1 = w.particles.v[0].dot(downhill);
    for (int k = 0; k < 4000; ++k) s.step();
    const double v2 = w.particles.v[0].dot(downhill);
    if (std::tan(theta) < mu) {
      EXPECT_LT(std::abs(v2), 1e-4) << deg << " degrees: held by its tangential spring";
    } else {
      const double a = kG * (std::sin(theta) - mu * std::cos(theta));
      EXPECT_NEAR((v2 - v1) / (4000 * w.dt), a, 0.01 * a) << deg;
    }
  }
}

// Torque-free: a lone box turns as core/rigid_rotation.hpp's splitting (the same bits: no
// torque, so the kicks add zero).
TEST(DemPolyhedra, LoneBoxTurnsFreely) {
  sable::World<3> w = soft_world(0.5, 0.5);
  w.gravity.setZero();
  sable::add_polyhedral_grain(w, sable::test::box_points(Vec::Zero(), Vec(1, 2, 3) * kA), kRho, 0);
  const Vec inertia = sable::principal_inertia(w, 0);
  w.particles.omega[0] = Vec(0.5, 0.01, 30.0);
  Quat q = w.particles.q[0];
  Vec omega = w.particles.omega[0];
  sable::DemSolver<3> s(w);
  s.initialize();
  for (int k = 0; k < 1000; ++k) {
    s.step();
    sable::free_rotation(q, omega, inertia, w.dt);
  }
  EXPECT_EQ(w.particles.q[0].coeffs(), q.coeffs());
  EXPECT_EQ(w.particles.omega[0], omega);
}

sable::World<3> heap(int nx, int nz, std::uint64_t seed) {
  sable::World<3> w = soft_world(0.3, 0.4, 2e-5);
  add_plane(w, Vec::UnitZ());
  std::mt19937_64 gen(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double r = 0.5 * kA, pitch = 2.0 * r + 0.01 * kA;
  for (int k = 0; k < nx * nx * nz; ++k) {
    const std::vector<Vec> points = sable::test::ellipsoid_points(
        sable::test::heap_site(k, nx, r, pitch), Vec::Constant(r), 10, [&] { return u(gen); });
    const auto id = sable::add_polyhedral_grain(w, points, kRho, 0);
    Vec v;
    for (int i = 0; i < 3; ++i) v[i] = u(gen);  // 1 m/s: they meet within a few hundred steps
    w.particles.v[w.particles.ids.slot(id)] = v;
  }
  return w;
}

// Restart and threads: a heap of random polyhedra, resumed from a snapshot and stepped on
// one or two threads, ends on the same bits (1,152 grains: enough list entries, over 2,048,
// for the force loops to share the work).
TEST(DemPolyhedra, RestartAndThreadsGiveTheSameBits) {
  const auto path = std::filesystem::temp_directory_path() / "sable_dem_polyhedra.h5";
  std::uint64_t hash[3];
  for (int run = 0; run < 3; ++run) {
    omp_set_num_threads(run == 1 ? 2 : 1);
    sable::World<3> w = heap(12, 8, 3);
    sable::DemSolver<3> s(w);
    s.initialize();
    for (int k = 0; k < 60; ++k) s.step();
    if (run == 2) {  // resumed: a fresh world from the snapshot, no initialize()
      sable::save_snapshot(w, {}, "scenario", path.string());
      sable::World<3> b = soft_world(0.3, 0.4, 2e-5);
      add_plane(b, Vec::UnitZ());
      sable::load_snapshot(path.string(), b);
      sable::DemSolver<3> sb(b);
      for (int k = 0; k < 60; ++k) sb.step();
      hash[run] = sable::state_hash(b);
      continue;
    }
    for (int k = 0; k < 60; ++k) s.step();
    EXPECT_GT(w.neighbors.pairs.size(), 2048u);
    EXPECT_GT(s.diagnostics().touching, 50u);  // the steps compared hold contacts
    hash[run] = sable::state_hash(w);
  }
  omp_set_num_threads(1);
  EXPECT_EQ(hash[0], hash[1]) << "one and two threads";
  EXPECT_EQ(hash[0], hash[2]) << "resumed";
  std::filesystem::remove(path);
}

// The time-step check's critical time: a face on a face is four springs in parallel, so the
// estimate sqrt(m / 2k) takes k = 4 max(k_n, k_t) (exact: the same formula).
TEST(DemPolyhedra, CriticalTimeCountsFourSpringsPerContact) {
  sable::World<3> w = soft_world(0.5, 0.5);
  sable::add_polyhedral_grain(w, sable::test::box_points(Vec::Zero(), Vec::Constant(kA)), kRho, 0);
  EXPECT_DOUBLE_EQ(sable::critical_time(w),
                   std::sqrt(0.5 * w.particles.mass[0] / (4.0 * std::max(kKn, 0.8 * kKn))));
}

// What the law does not cover is refused, naming it: a Hertz law, a cylinder wall.
TEST(DemPolyhedra, RefusesHertzAndCurvedWalls) {
  sable::World<3> w = soft_world(0.5, 0.5);
  sable::add_polyhedral_grain(w, sable::test::box_points(Vec::Zero(), Vec::Constant(kA)), kRho, 0);
  sable::World<3> hertz = w;
  hertz.model.normal = sable::NormalLaws::id<sable::HertzNormal>();
  EXPECT_THROW(sable::DemSolver<3>(hertz).initialize(), sable::InputError);
  sable::World<3> drum = w;
  sable::Wall<3> cylinder;
  cylinder.set_cylinder(0.1);
  drum.walls.push_back(cylinder);
  EXPECT_THROW(sable::DemSolver<3>(drum).initialize(), sable::InputError);
}

}  // namespace
