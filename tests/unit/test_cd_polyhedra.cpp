// Contact dynamics with polyhedral grains: each point of a contact manifold is a contact of
// the frictional problem (cd/cd_polyhedra.cpp), the grains turn with their body-frame inertia
// (core/rigid_rotation.hpp). Rigid grains at rest on rigid supports: the impulses balance the
// weight exactly (to the solver's tolerance), which is what each test asserts.
#include <gtest/gtest.h>
#include <omp.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <random>
#include <vector>

#include "polyhedra_helpers.hpp"
#include "sable/cd/cd_solver.hpp"
#include "sable/core/error.hpp"
#include "sable/dem/dem_solver.hpp"
#include "sable/geometry/polyhedron_mass.hpp"
#include "sable/io/snapshot.hpp"
#include "sable/world/polyhedral_grains.hpp"
#include "sable/world/state_hash.hpp"

namespace {

using Vec = Eigen::Vector3d;
using Quat = Eigen::Quaterniond;

constexpr double kG = 9.81;
constexpr double kA = 0.01;  // the cube's side (m)
constexpr double kRho = 2500.0;

sable::World<3> rigid_world(double mu, double dt) {
  sable::World<3> w = sable::test::polyhedra_world(kA, dt);
  w.materials.add({"grain", kRho, 0.0, 0.0, 0.0, mu, 0.0});
  w.materials.finalize();
  return w;
}

// A sticking manifold's residual stalls at its rounding, about 1.25e-12 (four points of one
// rigid body): 1e-11 is reached, and leaves velocities below 1e-13 m/s here.
sable::CdSettings tight() {
  sable::CdSettings s;
  s.nlgs.tolerance = 1e-11;
  s.nlgs.max_iterations = 100000;
  return s;
}

void add_plane(sable::World<3>& w, const Vec& point, const Vec& normal) {
  sable::Wall<3> wall;
  wall.name = "plane";
  wall.point = point;
  wall.set_plane(normal.normalized());
  w.walls.push_back(wall);
}

// The contacts' total force on grain g and their moment about its centroid, from the
// solver's stored forces (the grain's f, t: impulses / h).
struct Load {
  Vec force, moment;
};
Load load_on(const sable::World<3>& w, std::size_t g) {
  return {w.particles.f[g], w.particles.t[g]};
}

std::size_t contacts(const sable::CdSolver<3>& s) {
  std::vector<double> row;
  s.diagnostic_values(row);
  return static_cast<std::size_t>(row.at(0));
}

// The manifold of each touching contact, as the solver stored it: the normal forces of the
// points whose force is not zero (their count and their values, along +z).
std::vector<double> normal_forces(const sable::World<3>& w) {
  std::vector<double> out;
  for (const Vec& f : w.neighbors.wall_pairs.force)
    if (f.squaredNorm() > 0.0) out.push_back(f.z());
  for (const Vec& f : w.neighbors.pairs.force)
    if (f.squaredNorm() > 0.0) out.push_back(f.z());
  return out;
}

TEST(PolyhedralGrains, CubeKeepsItsAxesAndExactMass) {
  sable::World<3> w = rigid_world(0.5, 1e-4);
  const Vec lo(0.1, -0.02, 0.03);
  const auto id =
      sable::add_polyhedral_grain(w, sable::test::box_points(lo, lo + Vec::Constant(kA)), kRho, 0);
  const std::size_t g = w.particles.ids.slot(id);
  const double m = kRho * kA * kA * kA;
  // Exact: m = rho a^3, I = m a^2 / 6 about every axis through the centre (1e-12 relative:
  // the mass integrals' rounding over 12 triangles).
  EXPECT_NEAR(w.particles.mass[g], m, 1e-12 * m);
  const Vec inertia = sable::principal_inertia(w, g);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(inertia[k], m * kA * kA / 6.0, 1e-12 * m * kA * kA);
  EXPECT_LT((w.particles.x[g] - (lo + Vec::Constant(0.5 * kA))).norm(), 1e-15);
  EXPECT_EQ(w.particles.q[g].coeffs(), Quat::Identity().coeffs()) << "a box keeps its axes";
  EXPECT_NEAR(w.particles.radius[g], 0.5 * std::sqrt(3.0) * kA, 1e-15);
}

// A random hull goes into its principal frame: its corners posed by the grain's state are
// the points given (1e-12 of its size), and the body-frame inertia of the stored solid is
// diagonal with the stored moments (1e-12 of its trace).
TEST(PolyhedralGrains, RandomHullInItsPrincipalFrame) {
  std::mt19937_64 gen(7);
  std::normal_distribution<double> normal;
  std::vector<Vec> points;
  for (int k = 0; k < 14; ++k) {
    Vec v;
    for (int c = 0; c < 3; ++c) v[c] = normal(gen);
    points.push_back(Vec(0.012, 0.007, 0.005).cwiseProduct(v.normalized()) + Vec(0.3, 0, 0));
  }
  sable::World<3> w = rigid_world(0.5, 1e-4);
  const auto id = sable::add_polyhedral_grain(w, points, kRho, 0);
  const std::size_t g = w.particles.ids.slot(id);
  const sable::PolyhedronShape& s = w.shapes[w.particles.shape_index[g]];
  for (const Vec& b : s.solid.vertices()) {
    const Vec x = w.particles.q[g] * b + w.particles.x[g];
    double nearest = 1.0;
    for (const Vec& p : points) nearest = std::min(nearest, (p - x).norm());
    EXPECT_LT(nearest, 1e-12 * 0.012);
  }
  const sable::ConvexHull hull = sable::convex_hull(s.points);
  const sable::PolyhedronMass body = sable::polyhedron_mass(hull.vertices, hull.triangles);
  const double trace = body.inertia.trace();
  EXPECT_LT(body.centroid.norm(), 1e-12 * 0.012);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(body.inertia(r, c), r == c ? s.inertia[r] : 0.0, 1e-12 * trace);
  EXPECT_LT(s.inertia[0], s.inertia[1]);
  EXPECT_LT(s.inertia[1], s.inertia[2]);
  EXPECT_NEAR(body.volume, s.volume, 1e-12 * s.volume);
}

// A regular tetrahedron of side a: V = a^3 / (6 sqrt 2), I = m a^2 / 20 about any axis
// through its centroid (1e-12 relative).
TEST(PolyhedralGrains, RegularTetrahedronExactMass) {
  const double a = kA;
  const std::vector<Vec> t{Vec(1, 1, 1), Vec(1, -1, -1), Vec(-1, 1, -1), Vec(-1, -1, 1)};
  std::vector<Vec> points;  // side 2 sqrt 2 scaled to a
  for (const Vec& v : t) points.push_back(v * a / (2.0 * std::sqrt(2.0)));
  sable::World<3> w = rigid_world(0.5, 1e-4);
  const std::size_t g = w.particles.ids.slot(sable::add_polyhedral_grain(w, points, kRho, 0));
  const double m = kRho * a * a * a / (6.0 * std::sqrt(2.0));
  EXPECT_NEAR(w.particles.mass[g], m, 1e-12 * m);
  const Vec inertia = sable::principal_inertia(w, g);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(inertia[k], m * a * a / 20.0, 1e-12 * m * a * a);
}

// A cube face-down on a plane: one manifold of four points. The weight is carried: the
// points' normal forces sum to m g and their moment about the centroid is zero (to the
// solver's 1e-12), the cube does not move. The share among the four is statically
// indeterminate for rigid bodies (three equations, four unknowns): CD's Gauss-Seidel gives
// one of the solutions, so only the sum and the moment are asserted here.
TEST(CdPolyhedra, CubeRestsOnAPlaneOnFourPoints) {
  sable::World<3> w = rigid_world(0.5, 1e-4);
  add_plane(w, Vec::Zero(), Vec::UnitZ());
  sable::add_polyhedral_grain(
      w, sable::test::box_points(Vec(-0.5, -0.5, 0) * kA, Vec(0.5, 0.5, 1) * kA), kRho, 0);
  sable::CdSolver<3> solver(w, tight());
  solver.initialize();
  for (int k = 0; k < 20; ++k) solver.step();
  const double mg = w.particles.mass[0] * kG;
  EXPECT_EQ(contacts(solver), 4u);
  const Load l = load_on(w, 0);
  EXPECT_NEAR(l.force.z(), mg, 1e-10 * mg);
  EXPECT_LT(l.moment.norm(), 1e-10 * mg * kA);
  EXPECT_LT(w.particles.v[0].norm(), 1e-12);
  EXPECT_LT(w.particles.omega[0].norm(), 1e-10);
  EXPECT_NEAR(w.particles.x[0].z(), 0.5 * kA, 1e-14);
  ASSERT_EQ(normal_forces(w).size(), 1u) << "one wall entry holds the manifold's sum";
}

// A cube on a fixed cube: flush (4 points) and turned by 45 degrees about the vertical
// (the clipped octagon reduced to 4 points): the weight carried, no moment, no motion.
TEST(CdPolyhedra, CubeRestsOnACube) {
  for (const double turn : {0.0, std::numbers::pi / 4}) {
    sable::World<3> w = rigid_world(0.5, 1e-4);
    sable::add_polyhedral_grain(
        w, sable::test::box_points(Vec(-0.5, -0.5, -1) * kA, Vec(0.5, 0.5, 0) * kA), kRho, 0, true);
    const Quat q(Eigen::AngleAxisd(turn, Vec::UnitZ()));
    sable::add_polyhedral_grain(
        w, sable::test::box_points(Vec(-0.5, -0.5, 0) * kA, Vec(0.5, 0.5, 1) * kA, q), kRho, 0);
    sable::CdSolver<3> solver(w, tight());
    solver.initialize();
    for (int k = 0; k < 20; ++k) solver.step();
    const std::size_t top = w.particles.ids.slot(w.particles.id[1]);
    const double mg = w.particles.mass[top] * kG;
    EXPECT_EQ(contacts(solver), 4u) << "turn " << turn;
    const Load l = load_on(w, top);
    EXPECT_NEAR(l.force.z(), mg, 1e-10 * mg) << "turn " << turn;
    EXPECT_LT(l.moment.norm(), 1e-10 * mg * kA) << "turn " << turn;
    EXPECT_LT(w.particles.v[top].norm(), 1e-12) << "turn " << turn;
  }
}

// A regular tetrahedron on a plane resting on a face (3 points), on an edge (2) and on a
// vertex (1), its centroid above the support (equilibria, the last two unstable: checked on
// the first step, before rounding can tip them): the weight carried, no moment.
TEST(CdPolyhedra, TetrahedronOnFaceEdgeVertex) {
  const std::vector<Vec> t{Vec(1, 1, 1), Vec(1, -1, -1), Vec(-1, 1, -1), Vec(-1, -1, 1)};
  // Turns that put a face, an edge and a vertex lowest, the centroid above it.
  const Quat face = Quat::FromTwoVectors(Vec(-1, -1, -1).normalized(), -Vec::UnitZ());
  const Quat edge = Quat::Identity();  // the edge (1,-1,-1)-(-1,1,-1) lies along z = -1
  const Quat vertex = Quat::FromTwoVectors(Vec(1, 1, 1).normalized(), -Vec::UnitZ());
  const int expected[3] = {3, 2, 1};
  const Quat turns[3] = {face, edge, vertex};
  for (int c = 0; c < 3; ++c) {
    std::vector<Vec> points;
    for (const Vec& v : t) points.push_back(turns[c] * v * kA);
    double lowest = 1.0;
    for (const Vec& p : points) lowest = std::min(lowest, p.z());
    for (Vec& p : points) p.z() -= lowest;  // resting on z = 0
    sable::World<3> w = rigid_world(0.5, 1e-4);
    add_plane(w, Vec::Zero(), Vec::UnitZ());
    sable::add_polyhedral_grain(w, points, kRho, 0);
    sable::CdSolver<3> solver(w, tight());
    solver.initialize();
    solver.step();
    const double mg = w.particles.mass[0] * kG;
    EXPECT_EQ(contacts(solver), static_cast<std::size_t>(expected[c])) << "case " << c;
    const Load l = load_on(w, 0);
    EXPECT_NEAR(l.force.z(), mg, 1e-9 * mg) << "case " << c;
    EXPECT_LT(l.moment.norm(), 1e-9 * mg * kA) << "case " << c;
  }
}

// A cube on an incline of angle theta (mu = 0.5): below tan(theta) = mu it sticks; above, it
// slides from rest with a = g (sin theta - mu cos theta), which Moreau-Jean's constant
// velocity update gives exactly each step (1e-9 relative), without turning: its four points'
// normal forces take the tipping moment of the friction.
TEST(CdPolyhedra, CubeOnInclineSticksOrSlides) {
  const double mu = 0.5, h = 1e-4;
  for (const double deg : {20.0, 35.0}) {
    const double theta = deg * std::numbers::pi / 180.0;
    const Vec n(-std::sin(theta), 0.0, std::cos(theta));
    const Vec downhill(-std::cos(theta), 0.0, -std::sin(theta));
    sable::World<3> w = rigid_world(mu, h);
    add_plane(w, Vec::Zero(), n);
    const Quat q(Eigen::AngleAxisd(-theta, Vec::UnitY()));
    sable::add_polyhedral_grain(
        w, sable::test::box_points(Vec(-0.5, -0.5, 0) * kA, Vec(0.5, 0.5, 1) * kA, q), kRho, 0);
    sable::CdSolver<3> solver(w, tight());
    solver.initialize();
    const int steps = 50;
    for (int k = 0; k < steps; ++k) solver.step();
    const Vec v = w.particles.v[0];
    EXPECT_EQ(contacts(solver), 4u) << deg;
    EXPECT_LT(std::abs(v.dot(n)), 1e-12) << deg << " degrees: no motion across the plane";
    EXPECT_LT(w.particles.omega[0].norm(), 1e-9) << deg;
    if (std::tan(theta) < mu) {
      EXPECT_LT(v.norm(), 1e-12) << deg << " degrees: sticks";
    } else {
      const double a = kG * (std::sin(theta) - mu * std::cos(theta));
      EXPECT_NEAR(v.dot(downhill), a * steps * h, 1e-9 * a * steps * h) << deg;
    }
  }
}

// Torque-free: a box grain of sides 1, 2, 3 (three different moments) spun near its
// intermediate axis, alone in the solver, turns as core/rigid_rotation.hpp's splitting says
// (the same bits as the splitting called directly), and its kinetic energy is read with its
// body-frame tensor.
TEST(CdPolyhedra, LoneBoxTurnsFreelyWithItsInertiaTensor) {
  sable::World<3> w = rigid_world(0.5, 1e-4);
  w.gravity.setZero();
  sable::add_polyhedral_grain(w, sable::test::box_points(Vec::Zero(), Vec(1, 2, 3) * kA), kRho, 0);
  const Vec inertia = sable::principal_inertia(w, 0);
  EXPECT_GT(inertia[0], inertia[1]);  // x is the box's longest moment (sides 2 and 3 around it)
  w.particles.omega[0] = Vec(0.5, 0.01, 30.0);
  Quat q = w.particles.q[0];
  Vec omega = w.particles.omega[0];
  sable::CdSolver<3> solver(w, tight());
  solver.initialize();
  for (int k = 0; k < 2000; ++k) {
    solver.step();
    sable::free_rotation(q, omega, inertia, w.dt);
  }
  EXPECT_EQ(w.particles.q[0].coeffs(), q.coeffs());
  EXPECT_EQ(w.particles.omega[0], omega);
  EXPECT_DOUBLE_EQ(sable::kinetic_energy(w), sable::rotational_energy(q, inertia, omega));
}

// A heap of random polyhedra (hulls of 8 to 14 points on ellipsoids) dropped on a floor.
sable::World<3> heap(int nx, int nz, std::uint64_t seed) {
  sable::World<3> w = rigid_world(0.4, 2e-4);
  add_plane(w, Vec::Zero(), Vec::UnitZ());
  std::mt19937_64 gen(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double r = 0.5 * kA, pitch = 2.0 * r + 0.01 * kA;
  for (int k = 0; k < nx * nx * nz; ++k) {
    const Vec centre = sable::test::heap_site(k, nx, r, pitch);
    const Vec axes(r, r * (0.6 + 0.4 * std::abs(u(gen))), r * (0.5 + 0.5 * std::abs(u(gen))));
    const int corners = 8 + static_cast<int>(gen() % 7);
    const std::vector<Vec> points =
        sable::test::ellipsoid_points(centre, axes, corners, [&] { return u(gen); });
    const auto id = sable::add_polyhedral_grain(w, points, kRho, 0);
    Vec v;
    for (int i = 0; i < 3; ++i) v[i] = 0.2 * u(gen);
    w.particles.v[w.particles.ids.slot(id)] = v;
  }
  return w;
}

// A snapshot carries the shapes and their rows: loaded into a world holding neither, the
// state hashes as written, and the resumed run ends on the uninterrupted run's bits.
TEST(CdPolyhedra, SnapshotRestartIsBitIdentical) {
  const auto path = std::filesystem::temp_directory_path() / "sable_cd_polyhedra.h5";
  sable::World<3> a = heap(4, 3, 11);
  sable::CdSolver<3> sa(a, {});
  sa.initialize();
  for (int k = 0; k < 200; ++k) sa.step();  // 40 ms: the heap has fallen onto the floor
  sable::save_snapshot(a, {}, "scenario", path.string());
  for (int k = 0; k < 30; ++k) sa.step();
  sable::World<3> b = rigid_world(0.4, 2e-4);
  add_plane(b, Vec::Zero(), Vec::UnitZ());
  sable::load_snapshot(path.string(), b);
  ASSERT_EQ(b.shapes.size(), a.shapes.size());
  sable::CdSolver<3> sb(b, {});  // no initialize(): a resumed run carries on (runner.cpp)
  for (int k = 0; k < 30; ++k) sb.step();
  EXPECT_EQ(sable::state_hash(b), sable::state_hash(a));
  EXPECT_GE(normal_forces(a).size(), 16u) << "the heap rests on the floor and on itself";
  std::filesystem::remove(path);
}

// Threads: the manifolds are found and the coloured sweep solves them in parallel; one and
// two threads give the same bits. 1,152 grains: enough list entries (over 2,048) for the
// contact build's loops to run on both threads. The contacts' stored normals, points and
// depths (outputs, outside the hash) too.
TEST(CdPolyhedra, ThreadCountGivesTheSameBits) {
  std::uint64_t hash[2];
  sable::ContactPoints<3> geometry[2];
  for (int threads = 1; threads <= 2; ++threads) {
    omp_set_num_threads(threads);
    sable::World<3> w = heap(12, 8, 5);
    sable::CdSettings s;
    s.nlgs.order = sable::cd::SweepOrder::kColoured;
    sable::CdSolver<3> solver(w, s);
    solver.initialize();
    for (int k = 0; k < 40; ++k) solver.step();
    EXPECT_GT(w.neighbors.pairs.size(), 2048u);
    EXPECT_GT(contacts(solver), 50u);  // the problem the sweeps solve is not empty
    hash[threads - 1] = sable::state_hash(w);
    geometry[threads - 1] = w.contact_geometry;
  }
  omp_set_num_threads(1);
  EXPECT_EQ(hash[0], hash[1]);
  for (const auto member :
       {&sable::ContactPoints<3>::pairs, &sable::ContactPoints<3>::wall_pairs}) {
    const sable::EntryGeometry<3>&a = geometry[0].*member, &b = geometry[1].*member;
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(a.normal, b.normal);
    EXPECT_EQ(a.arm, b.arm);
    EXPECT_EQ(a.depth, b.depth);
  }
}

// What is not built yet says so: contact dynamics refuses a sphere among polyhedra and walls
// other than planes; DEM takes them with the linear law only (this world's is Hertz).
TEST(CdPolyhedra, RefusesWhatItDoesNotHandle) {
  sable::World<3> w = rigid_world(0.5, 1e-4);
  sable::add_polyhedral_grain(w, sable::test::box_points(Vec::Zero(), Vec::Constant(kA)), kRho, 0);
  EXPECT_THROW(sable::DemSolver<3>(w).initialize(), sable::InputError);
  sable::World<3> mixed = w;
  mixed.particles.add(Vec(0.1, 0, 0), 0.5 * kA, kRho, 0, 1.0);
  EXPECT_THROW(sable::CdSolver<3>(mixed, {}).initialize(), sable::InputError);
  sable::World<3> drum = w;
  sable::Wall<3> cylinder;
  cylinder.set_cylinder(0.1);
  drum.walls.push_back(cylinder);
  EXPECT_THROW(sable::CdSolver<3>(drum, {}).initialize(), sable::InputError);
}

}  // namespace
