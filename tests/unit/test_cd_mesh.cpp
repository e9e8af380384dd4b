// Contact dynamics against mesh walls and turning walls: a mesh contact is a wall contact at
// the feature its list entry answers for (one contact on a flat mesh, one per face in a
// concave corner), the wall has infinite mass and its prescribed velocity at the contact
// point, and its torque about its pivot balances the grains' moments.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "sable/cd/cd_solver.hpp"
#include "sable/geometry/surface_mesh.hpp"
#include "sable/world/element_forces.hpp"

namespace {

using Vec3 = sable::Space<3>::Vec;
using Tri = sable::SurfaceMesh<3>::Element;

constexpr double kR = 1e-3;  // grain radius (m)
constexpr double kG = 9.81;

template <int D = 3>
sable::World<D> rigid_world(double mu, double dt, double mu_r = 0.0) {
  sable::World<D> w;
  w.materials.add({"grain", 2500.0, 0.0, 0.0, 0.0, mu, mu_r});
  w.materials.finalize();
  w.neighbors.skin = 0.2e-3;
  w.neighbors.domain_lo.setConstant(-0.05);
  w.neighbors.domain_hi.setConstant(0.05);
  w.dt = dt;
  return w;
}

sable::CdSettings tight(sable::cd::LocalSolver local = sable::cd::LocalSolver::kBipotential) {
  sable::CdSettings s;
  s.nlgs.tolerance = 1e-12;
  s.nlgs.max_iterations = 100000;
  s.nlgs.local = local;
  return s;
}

void add_mesh(sable::World<3>& w, std::vector<Vec3> vertices, std::vector<Tri> triangles) {
  sable::Wall<3> wall;
  wall.name = "mesh";
  wall.set_mesh(sable::build_surface<3>(std::move(vertices), std::move(triangles), "test mesh"));
  w.walls.push_back(wall);
}

// The square [-l, l]^2 at z = 0 as two triangles sharing the diagonal (-l, -l)-(l, l).
void add_square(sable::World<3>& w, double l) {
  add_mesh(w, {{-l, -l, 0}, {l, -l, 0}, {l, l, 0}, {-l, l, 0}}, {Tri{0, 1, 2}, Tri{0, 2, 3}});
}

// A flat disk of radius `radius` about the z axis through `centre`: a fan of `n` triangles.
void add_disk(sable::World<3>& w, const Vec3& centre, double radius, int n) {
  std::vector<Vec3> v{centre};
  std::vector<Tri> t;
  for (int k = 0; k < n; ++k) {
    const double a = 2.0 * std::numbers::pi * (k + 0.5) / n;
    v.push_back(centre + Vec3(radius * std::cos(a), radius * std::sin(a), 0.0));
    t.push_back(
        Tri{0, static_cast<std::uint32_t>(1 + k), static_cast<std::uint32_t>(1 + (k + 1) % n)});
  }
  add_mesh(w, std::move(v), std::move(t));
}

std::size_t problem_contacts(const sable::CdSolver<3>& s) {
  std::vector<double> row;
  s.diagnostic_values(row);
  return static_cast<std::size_t>(row.at(0));
}

// (a) A sphere resting over the shared edge of a flat two-triangle mesh, sliding along that
// edge and braked by friction, against the same sphere on a plane: one contact (the edge's,
// kept by its owner's entry; the other triangle's entry stays out), and the same impulses,
// wall force and velocities to 1e-12.
TEST(CdMesh, FlatMeshOverSharedEdgeActsLikePlane) {
  auto mesh_world = rigid_world(0.5, 1e-4);
  auto plane_world = rigid_world(0.5, 1e-4);
  for (auto* w : {&mesh_world, &plane_world}) {
    w->gravity = {0, 0, -kG};
    w->particles.add({1e-3, 1e-3, kR}, kR, 2500.0, 0, 1.0);
    w->particles.v[0] = {0.01, 0.01, 0.0};
  }
  add_square(mesh_world, 0.01);
  sable::Wall<3> plane;
  plane.set_plane({0, 0, 1});
  plane_world.walls.push_back(plane);
  sable::CdSolver<3> sm(mesh_world, tight(sable::cd::LocalSolver::kExact));
  sable::CdSolver<3> sp(plane_world, tight(sable::cd::LocalSolver::kExact));
  sm.initialize();
  sp.initialize();
  const auto& pm = mesh_world.particles;
  const auto& pp = plane_world.particles;
  const double mg = pp.mass[0] * kG;
  for (int step = 0; step < 200; ++step) {
    sm.step();
    sp.step();
    ASSERT_EQ(problem_contacts(sm), 1u) << "step " << step;
    ASSERT_EQ(mesh_world.neighbors.wall_pairs.size(), 2u);
    EXPECT_LT((mesh_world.walls[0].force - plane_world.walls[0].force).norm(), 1e-12 * mg);
    EXPECT_LT((pm.v[0] - pp.v[0]).norm(), 1e-12 * 0.01);
    EXPECT_LT((pm.omega[0] - pp.omega[0]).norm(), 1e-12 * 0.01 / kR);
  }
  EXPECT_NEAR(-plane_world.walls[0].force.z(), mg, 1e-9 * mg);
  EXPECT_GT(pp.omega[0].norm(), 1.0);  // friction made it roll
  // The touching entry holds a feature of the mesh: a face (0, 1) or the shared edge.
  const auto& wl = mesh_world.neighbors.wall_pairs;
  std::size_t loaded = 0;
  for (std::size_t k = 0; k < wl.size(); ++k) loaded += wl.force[k] != Vec3::Zero() ? 1 : 0;
  EXPECT_EQ(loaded, 1u);
  // The mesh's force per element adds up to its total.
  const auto ef = sable::element_forces(mesh_world, 0);
  ASSERT_EQ(ef.size(), 2u);
  EXPECT_LT((ef[0] + ef[1] - mesh_world.walls[0].force).norm(), 1e-15 * mg);
}

// (b) A sphere in a concave right-angle corner (floor z = 0, side x = 0, two triangles each),
// gravity tilted 30 degrees towards the side: one contact per face, at rest, and the wall's
// force is the weight. Frictionless, the faces carry m g cos and m g sin.
TEST(CdMesh, ConcaveCornerTwoContactsBalanceTheWeight) {
  const double l = 0.01, tilt = std::numbers::pi / 6.0;
  for (const double mu : {0.0, 0.4}) {
    auto w = rigid_world(mu, 1e-4);
    w.gravity = {-kG * std::sin(tilt), 0.0, -kG * std::cos(tilt)};
    w.particles.add({kR, 0.0, kR}, kR, 2500.0, 0, 1.0);
    // Floor A B C D, side A D E F; A D the shared (concave) edge along y.
    add_mesh(w, {{0, -l, 0}, {l, -l, 0}, {l, l, 0}, {0, l, 0}, {0, l, l}, {0, -l, l}},
             {Tri{0, 1, 2}, Tri{0, 2, 3}, Tri{0, 3, 4}, Tri{0, 4, 5}});
    sable::CdSolver<3> s(w, tight());
    s.initialize();
    const Vec3 x0 = w.particles.x[0];
    for (int step = 0; step < 100; ++step) s.step();
    const double m = w.particles.mass[0];
    EXPECT_EQ(problem_contacts(s), 2u);
    EXPECT_EQ(s.diagnostics().touching, 2u);
    EXPECT_LT((w.walls[0].force - m * w.gravity).norm(), 1e-9 * m * kG) << "mu " << mu;
    EXPECT_LT((w.particles.x[0] - x0).norm(), 1e-12 * kR);
    EXPECT_LT(w.particles.v[0].norm(), 1e-12);
    if (mu == 0.0) {
      const auto ef = sable::element_forces(w, 0);
      EXPECT_NEAR(-(ef[0] + ef[1]).z(), m * kG * std::cos(tilt), 1e-9 * m * kG);
      EXPECT_NEAR(-(ef[2] + ef[3]).x(), m * kG * std::sin(tilt), 1e-9 * m * kG);
    }
  }
}

// (c) A grain resting on a disk-shaped mesh turning about z at omega, for the time of half a
// turn. A grain that cannot turn (a block: inverse inertia 0) goes round with the disk:
// omega^2 r = 0.02 m/s^2 is far below mu g, so friction holds it, and it ends half way round
// at the disk's speed omega r. A free sphere rolls instead: the classic ball on a turntable.
// Its first impulse P makes the contact point move with the disk, P / m + (5 / 2) P / m =
// omega r, so its centre takes 2/7 of the disk's speed, and it then circles the axis at 2/7
// of the disk's rate (rolling without slipping keeps it on that circle).
TEST(CdMesh, GrainGoesRoundOnTurningMesh) {
  const double omega = 2.0, r0 = 5e-3, dt = 5e-4;
  for (const bool block : {true, false}) {
    auto w = rigid_world(0.5, dt);
    w.gravity = {0, 0, -kG};
    w.particles.add({r0, 0.0, kR}, kR, 2500.0, 0, 1.0);
    if (block) w.particles.inv_inertia[0] = 0.0;
    add_disk(w, Vec3::Zero(), 0.01, 16);
    w.walls[0].set_rotation(Vec3::Zero(), {0, 0, 1}, omega);
    sable::CdSolver<3> s(w, tight());
    s.initialize();
    const int steps = static_cast<int>(std::lround(std::numbers::pi / omega / dt));
    for (int step = 0; step < steps; ++step) s.step();
    const auto& p = w.particles;
    const Vec3 x = p.x[0];
    const double radius = std::hypot(x.x(), x.y()), share = block ? 1.0 : 2.0 / 7.0;
    EXPECT_NEAR(p.v[0].norm(), share * omega * radius, 0.02 * share * omega * radius) << block;
    EXPECT_NEAR(radius, r0, 0.02 * r0) << block;
    // Half way round (the block) or 2/7 of that (the sphere), +-3 degrees.
    EXPECT_NEAR(std::atan2(x.y(), x.x()), share * std::numbers::pi, 0.05) << block;
    EXPECT_NEAR(x.z(), kR, 1e-9 * kR);
    EXPECT_NEAR(-w.walls[0].force.z(), p.mass[0] * kG, 1e-6 * p.mass[0] * kG);
  }
}

// (d) The torque the grains exert on a turning mesh about its pivot is minus the moment of
// their contact forces about it: summed over the grains (which touch only the mesh), each
// grain's contact force at its centre plus its contact torque.
TEST(CdMesh, TorqueOnTurningMeshBalancesTheGrainsMoments) {
  const Vec3 centre(2e-3, -1e-3, 0.0);
  auto w = rigid_world(0.5, 2e-4);
  w.gravity = {0, 0, -kG};
  for (const Vec3& at : {Vec3(6e-3, 1e-3, kR), Vec3(-2e-3, 3e-3, kR), Vec3(1e-3, -6e-3, kR)})
    w.particles.add(at, kR, 2500.0, 0, 1.0);
  add_disk(w, centre, 0.01, 12);
  w.walls[0].set_rotation(centre, {0, 0, 1}, 30.0);  // fast: the grains slide at first
  sable::CdSolver<3> s(w, tight());
  s.initialize();
  const auto& p = w.particles;
  for (int step = 0; step < 20; ++step) {
    const std::vector<Vec3> x = p.x;  // the start-of-step positions the forces belong to
    s.step();
    Vec3 moment = Vec3::Zero();
    double scale = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      moment += (x[i] - centre).cross(p.f[i]) + p.t[i];
      scale += (x[i] - centre).norm() * p.f[i].norm();
    }
    ASSERT_GT(scale, 0.0);
    EXPECT_LT((w.walls[0].torque + moment).norm(), 1e-13 * scale) << "step " << step;
    EXPECT_GT(std::abs(w.walls[0].torque.z()), 1e-3 * scale);  // friction turns the grains
  }
}

// (e) Rolling resistance against a turning wall resists the relative spin, the grain's less
// the wall's. A disk (2D) on a flat two-segment mesh that turns about the disk's contact
// point, with rolling friction far above what the slow turn asks for: the disk turns with the
// wall as one body, at the wall's spin and with the wall's velocity at its centre.
TEST(CdMesh, RollingResistanceHoldsTheSpinOfATurningWall) {
  using Vec2 = sable::Space<2>::Vec;
  const double spin = 0.5;
  auto w = rigid_world<2>(0.5, 1e-4, 0.5);
  w.model.rolling = sable::RollingModel::kEpsd;
  w.gravity = {0, -kG};
  w.particles.add({2e-3, kR}, kR, 2500.0, 0, 1.0);
  sable::Wall<2> wall;
  wall.set_mesh(sable::build_surface<2>(
      {{-0.01, 0}, {0, 0}, {0.01, 0}},
      {sable::SurfaceMesh<2>::Element{0, 1}, sable::SurfaceMesh<2>::Element{1, 2}}, "test line"));
  wall.set_rotation({2e-3, 0}, Vec2::Zero(), spin);
  w.walls.push_back(wall);
  sable::CdSolver<2> s(w, tight());
  s.initialize();
  const auto& p = w.particles;
  Vec2 x = p.x[0];  // at the start of the last step, where its velocity was solved
  for (int step = 0; step < 100; ++step) {
    x = p.x[0];
    s.step();
  }
  EXPECT_NEAR(p.omega[0], spin, 1e-9 * spin);
  // Its centre's velocity is the wall's there: exactly across the radius from the pivot; along
  // it, up to the speed that closes the gap the straight position update opened on the turn
  // (h v^2 / (2 R) per step, so v^2 / (2 R), a share spin h / 2 of v).
  const Vec2 radial = (x - w.walls[0].pivot).normalized();
  const Vec2 dv = p.v[0] - w.walls[0].velocity_at(x);
  EXPECT_LT(std::abs(dv.dot(Vec2(-radial.y(), radial.x()))), 1e-9 * spin * kR);
  EXPECT_LT(std::abs(dv.dot(radial)), spin * w.dt * spin * kR);
  EXPECT_GT(p.v[0].norm(), 0.9 * spin * kR);  // it moves: about the pivot, a radius away
}

}  // namespace
