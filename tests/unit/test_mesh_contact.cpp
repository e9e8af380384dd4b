// Contact with mesh walls (geometry/mesh_wall.hpp, dem/wall_contacts_impl.hpp): a mesh acts
// as the surface it describes. Over a flat mesh a grain feels exactly what a plane gives it,
// wherever it sits over faces, shared edges and shared vertices and while it slides across
// them; a faceted cylinder pushes along the nearest point's normal with the Hertz force of
// the overlap; a concave corner gives one contact per face; a turning mesh carries grains
// and its force and torque balance the grains'.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "sable/core/hash.hpp"
#include "sable/core/rng.hpp"
#include "sable/dem/dem_solver.hpp"
#include "sable/geometry/surface_mesh.hpp"
#include "sable/world/state_hash.hpp"

namespace {

using V3 = Eigen::Vector3d;
using sable::SurfaceMesh;
using sable::Wall;
using sable::World;

constexpr double kR = 1e-3;  // grain radius (m)

template <int D>
World<D> bare_world(double mu = 0.5, double mu_r = 0.0) {
  World<D> w;
  w.materials.add({"g", 2500.0, 1e7, 0.3, 0.5, mu, mu_r});
  w.materials.finalize();
  w.neighbors.skin = 0.2 * kR;
  w.neighbors.domain_lo = -0.02 * Eigen::Matrix<double, D, 1>::Ones();
  w.neighbors.domain_hi = 0.02 * Eigen::Matrix<double, D, 1>::Ones();
  w.dt = 1e-6;
  w.reorder_every = 0;
  return w;
}

// The square [-h, h]^2 in z = 0 as two triangles sharing the diagonal (-h,-h)-(h,h).
SurfaceMesh<3> flat_square(double h) {
  return sable::build_surface<3>({V3(-h, -h, 0), V3(h, -h, 0), V3(h, h, 0), V3(-h, h, 0)},
                                 {{0, 1, 2}, {0, 2, 3}}, "flat square");
}

Wall<3> plane_floor() {
  Wall<3> w;
  w.name = "plane";
  w.set_plane(V3(0, 0, 1));
  return w;
}

Wall<3> mesh_wall(SurfaceMesh<3> m) {
  Wall<3> w;
  w.name = "mesh";
  w.set_mesh(std::move(m));
  return w;
}

// The wall entries of grain 0 that touch (non-zero force), and the sum of their forces.
int touching(const World<3>& w, V3* total = nullptr) {
  const auto& wl = w.neighbors.wall_pairs;
  int n = 0;
  if (total) total->setZero();
  for (std::size_t k = 0; k < wl.size(); ++k) {
    if (wl.force[k] == V3::Zero()) continue;
    ++n;
    if (total) *total += wl.force[k];
  }
  return n;
}

// The grains' motion and the walls' loads, bit for bit (the lists themselves differ between
// rebuild schedules).
std::uint64_t motion_hash(const World<3>& w) {
  sable::Hasher h;
  for (const auto* a : {&w.particles.x, &w.particles.v, &w.particles.omega})
    h.bytes(a->data(), a->size() * sizeof(V3));
  for (const auto& wall : w.walls) {
    h.bytes(wall.force.data(), sizeof(V3));
    h.bytes(wall.torque.data(), sizeof(V3));
  }
  return h.digest();
}

double rel(const V3& a, const V3& b) {
  return (a - b).norm() / std::max(b.norm(), 1e-300);
}

// A sphere pressed onto a flat mesh of two triangles over a face, over their shared edge and
// over each shared vertex: one contact, whose force is the plane's to 1e-12 relative (the
// face's normal is the plane's to the bit; an edge's or vertex's normal, from the centre to
// the nearest point, is vertical to round-off).
TEST(MeshContact, FlatMeshGivesThePlanesForceOverFaceEdgeAndVertex) {
  const double h = 5 * kR, delta = 1e-2 * kR;
  const std::vector<V3> spots = {V3(0.5 * h, -0.4 * h, 0),  // face of triangle 0
                                 V3(-0.3 * h, 0.6 * h, 0),  // face of triangle 1
                                 V3(0.2 * h, 0.2 * h, 0),   // the shared edge
                                 V3(h, h, 0),               // a shared vertex
                                 V3(-h, -h, 0)};            // the other
  for (const V3& s : spots) {
    V3 forces[2];
    for (int mesh = 0; mesh < 2; ++mesh) {
      auto w = bare_world<3>();
      w.walls.push_back(mesh ? mesh_wall(flat_square(h)) : plane_floor());
      w.particles.add(s + V3(0, 0, kR - delta), kR, 2500.0, 0, 1.0);
      sable::DemSolver<3> solver(w);
      solver.initialize();
      ASSERT_EQ(touching(w, &forces[mesh]), 1) << "spot " << s.transpose();
    }
    EXPECT_LT(rel(forces[1], forces[0]), 1e-12) << "spot " << s.transpose();
    EXPECT_GT(forces[0].z(), 0.0);
  }
}

// A sphere sliding (and rolling) across the flat mesh's shared edge under gravity, bouncing
// a little from its start: at every step it touches the mesh when it touches the plane, and
// its wall force and the contact's tangential history are the plane's to 1e-12 relative: the
// history moves with the sphere from one triangle to the next.
TEST(MeshContact, SlidingAcrossASharedEdgeKeepsThePlanesHistory) {
  const double h = 5 * kR;
  World<3> worlds[2] = {bare_world<3>(), bare_world<3>()};
  worlds[0].walls.push_back(plane_floor());
  worlds[1].walls.push_back(mesh_wall(flat_square(h)));
  for (auto& w : worlds) {
    w.gravity = V3(0, 0, -9.81);
    w.particles.add(V3(0.15 * h, -0.1 * h, kR - 6e-4 * kR), kR, 2500.0, 0, 1.0);
    w.particles.v[0] = V3(-0.3, 0.3, 0);  // crosses the diagonal y = x
  }
  sable::DemSolver<3> a(worlds[0]), b(worlds[1]);
  a.initialize();
  b.initialize();
  bool crossed = false;
  int touching_steps = 0, crossed_touching = 0;
  for (int step = 0; step < 6000; ++step) {
    a.step();
    b.step();
    V3 fa, fb;
    const int on_plane = touching(worlds[0], &fa);
    ASSERT_LE(on_plane, 1);
    ASSERT_EQ(touching(worlds[1], &fb), on_plane) << "step " << step;
    if (on_plane == 0) continue;
    ++touching_steps;
    crossed_touching += crossed ? 1 : 0;
    ASSERT_LT(rel(fb, fa), 1e-12) << "step " << step;
    V3 shear_b = V3::Zero();
    const auto& wl = worlds[1].neighbors.wall_pairs;
    for (std::size_t k = 0; k < wl.size(); ++k)
      if (wl.force[k] != V3::Zero()) shear_b = wl.shear[k];
    ASSERT_LT(rel(shear_b, worlds[0].neighbors.wall_pairs.shear[0]), 1e-12) << "step " << step;
    const V3 x = worlds[1].particles.x[0];
    crossed = crossed || x.y() > x.x() + 0.1 * kR;
  }
  EXPECT_TRUE(crossed);              // it did go over the edge ...
  EXPECT_GT(touching_steps, 3000);   // ... touching most of the time,
  EXPECT_GT(crossed_touching, 500);  // after the crossing too
}

// A faceted cylinder of 32 facets (radius 5 R, its axis along x): at 10,000 random places
// round it, over the facets, beside the convex edges between them and near its caps' rims,
// a sphere overlapping the surface by delta gets one contact, pushing along the normal from
// the nearest surface point with the Hertz force of delta: F = 4/3 E* sqrt(R delta) delta
// (the wall has the grain's material), to 1e-9 relative (the normal is rebuilt from
// coordinates of size 5e-3 m to resolve a 1e-5 m overlap: a few 1e-12 relative).
TEST(MeshContact, FacetedCylinderPushesWithHertzAlongTheNearestNormal) {
  const double rc = 5 * kR, length = 20 * kR, delta = 1e-2 * kR;
  auto w = bare_world<3>();
  w.walls.push_back(mesh_wall(
      sable::cylinder_surface(V3::Zero(), V3(1, 0, 0), rc, length, 32, 4, true, "cylinder")));
  const auto& mesh = *w.walls[0].mesh();
  const auto& pp = w.materials.pair(0, 0);
  const double hertz = 4.0 / 3.0 * pp.y_star * std::sqrt(kR * delta) * delta;
  w.particles.add(V3(0, 0, 0), kR, 2500.0, 0, 1.0);
  sable::DemSolver<3> solver(w);
  sable::Rng rng(38);
  int edges = 0;
  for (int trial = 0; trial < 10000; ++trial) {
    // A random direction from a random point on the axis; the surface point nearest to a
    // centre placed out along it is found by the mesh's own distance (exact, brute force).
    // (Drawn one per statement: the order of a call's arguments is unspecified, and clang and
    // gcc differ, which would give each compiler other trials.)
    const double ax = rng.uniform(-0.2, 0.2), ay = rng.uniform(-1, 1), az = rng.uniform(-1, 1);
    const V3 dir = V3(ax, ay, az).normalized();
    const V3 base(rng.uniform(-0.45, 0.45) * length, 0, 0);
    // Newton's method along the ray for the place at distance kR - delta, from beyond reach
    // of the surface whichever way the ray leaves (caps included): outside a convex body the
    // distance along a ray from inside is convex and increasing, its slope n . dir, so each
    // step lands short of the root's far side, never past it, and converges to it.
    double hi = 2 * rc + length;
    V3 n;
    for (int it = 0; it < 100; ++it) {
      const double g = mesh.distance(w.walls[0].point, base + hi * dir, n) - (kR - delta);
      if (g <= 1e-14 * rc) break;
      hi -= g / n.dot(dir);
    }
    const V3 c = base + hi * dir;
    const double dist = mesh.distance(w.walls[0].point, c, n);
    ASSERT_NEAR(dist, kR - delta, 1e-12 * rc) << "trial " << trial << " from " << base.transpose()
                                              << " along " << dir.transpose() << " out to " << hi;
    w.particles.x[0] = c;
    w.particles.v[0].setZero();
    w.neighbors.x_ref.clear();  // a new place: rebuild the lists
    solver.initialize();
    V3 f;
    ASSERT_EQ(touching(w, &f), 1) << "trial " << trial << " at " << c.transpose();
    const double expected_delta = kR - dist;
    const double expected = 4.0 / 3.0 * pp.y_star * std::sqrt(kR * expected_delta) * expected_delta;
    ASSERT_LT(rel(f, expected * n), 1e-9) << "trial " << trial;
    ASSERT_NEAR(expected, hertz, 1e-9 * hertz);
    for (std::size_t k = 0; k < w.neighbors.wall_pairs.size(); ++k)
      if (w.neighbors.wall_pairs.force[k] != V3::Zero())
        edges += w.neighbors.wall_pairs.feature[k] >= mesh.elements() ? 1 : 0;
  }
  EXPECT_GT(edges, 500);  // edges and vertices were met, not only faces
}

// A concave 90-degree edge (a floor z = 0 meeting a wall x = 0 along y): a sphere in the
// corner touching both gets two contacts, each the force of the plane it touches.
TEST(MeshContact, ConcaveRightAngleGivesOneContactPerFace) {
  const double a = 6 * kR, d1 = 1e-2 * kR, d2 = 2e-2 * kR;
  auto corner = sable::build_surface<3>(
      {V3(0, -a, 0), V3(a, -a, 0), V3(a, a, 0), V3(0, a, 0), V3(0, -a, a), V3(0, a, a)},
      {{0, 1, 2}, {0, 2, 3}, {0, 3, 5}, {0, 5, 4}}, "corner");
  const V3 c(kR - d2, 0.3 * kR, kR - d1);
  auto w = bare_world<3>();
  w.walls.push_back(mesh_wall(std::move(corner)));
  w.particles.add(c, kR, 2500.0, 0, 1.0);
  sable::DemSolver<3> s(w);
  s.initialize();
  ASSERT_EQ(touching(w), 2);
  // The planes alone.
  V3 expected[2];
  for (int k = 0; k < 2; ++k) {
    auto p = bare_world<3>();
    Wall<3> wall;
    wall.set_plane(k == 0 ? V3(0, 0, 1) : V3(1, 0, 0));
    p.walls.push_back(wall);
    p.particles.add(c, kR, 2500.0, 0, 1.0);
    sable::DemSolver<3> ps(p);
    ps.initialize();
    ASSERT_EQ(touching(p, &expected[k]), 1);
  }
  std::vector<V3> got;
  for (const V3& f : w.neighbors.wall_pairs.force)
    if (f != V3::Zero()) got.push_back(f);
  ASSERT_EQ(got.size(), 2u);
  const bool floor_first = got[0].z() > got[0].x();
  EXPECT_LT(rel(got[floor_first ? 0 : 1], expected[0]), 1e-12);
  EXPECT_LT(rel(got[floor_first ? 1 : 0], expected[1]), 1e-12);
}

// A disk-shaped mesh (a fan of 24 triangles, radius 10 R) turning about its axis z at
// omega: its velocity at a point is omega x r + v exactly, and a grain resting on it at
// radius r0 goes round with it: omega^2 r0 = 0.04 g, below mu g (no slip), and rolling
// resistance mu_r = 0.5 holds the couple R m omega^2 r0 that would set a free sphere rolling
// (a rolling ball on a turntable circles at 2/7 of its rate instead). After a quarter turn,
// its speed within 1 % of omega r0, its radius within 1 % of r0, its angle within 0.05 rad of
// the disk's, less the start's slip.
TEST(MeshContact, TurningDiskCarriesAGrainRound) {
  const double rd = 10 * kR, r0 = 6 * kR;
  const double omega = std::sqrt(0.04 * 9.81 / r0);
  std::vector<V3> v = {V3::Zero()};
  std::vector<std::array<std::uint32_t, 3>> tris;
  for (std::uint32_t k = 0; k < 24; ++k) {
    const double a = 2 * std::numbers::pi * k / 24;
    v.push_back(V3(rd * std::cos(a), rd * std::sin(a), 0));
    tris.push_back({0, k + 1, k == 23 ? 1u : k + 2});
  }
  auto w = bare_world<3>(0.5, 0.5);
  w.model.rolling = sable::RollingModel::kEpsd;
  w.neighbors.rolling = true;
  w.gravity = V3(0, 0, -9.81);
  w.walls.push_back(mesh_wall(sable::build_surface<3>(v, tris, "disk")));
  w.walls[0].set_rotation(V3::Zero(), V3(0, 0, 1), omega);
  const V3 x(0.7 * rd, 0.1 * rd, 3 * kR);
  EXPECT_EQ(w.walls[0].velocity_at(x), V3(-omega * x.y(), omega * x.x(), 0));
  w.walls[0].velocity = V3(0.1, 0, 0);
  EXPECT_EQ(w.walls[0].velocity_at(x), V3(0.1 - omega * x.y(), omega * x.x(), 0));
  w.walls[0].velocity.setZero();
  w.particles.add(V3(r0, 0, kR - 6e-4 * kR), kR, 2500.0, 0, 1.0);
  sable::DemSolver<3> s(w);
  s.initialize();
  const int steps = static_cast<int>(0.5 * std::numbers::pi / omega / w.dt);
  for (int k = 0; k < steps; ++k) s.step();
  const V3 g = w.particles.x[0];
  EXPECT_NEAR(g.head<2>().norm(), r0, 1e-2 * r0);
  EXPECT_NEAR(w.particles.v[0].head<2>().norm(), omega * r0, 1e-2 * omega * r0);
  // The start's slip: the grain reaches the disk's speed within omega r0 / (mu g).
  const double slip = 0.5 * omega * r0 / (0.5 * 9.81) * omega;
  EXPECT_NEAR(std::atan2(g.y(), g.x()), 0.5 * std::numbers::pi - slip, 0.05);
}

// Grains on a tilted, turning faceted cylinder: the force and torque on the mesh (about its
// pivot) are minus the sums of the contact forces on the grains and of their moments about
// the pivot at the contact points, to round-off (1e-12 of the sums of magnitudes).
TEST(MeshContact, ForceAndTorqueOnAMeshBalanceTheGrains) {
  auto w = bare_world<3>();
  w.gravity = V3(0, 0, -9.81);
  w.walls.push_back(mesh_wall(
      sable::cylinder_surface(V3(0, 0, 0), V3(1, 0.2, 0), 4 * kR, 16 * kR, 16, 3, true, "drum")));
  w.walls[0].set_rotation(V3(0, 0, -kR), V3(0, 0, 1), 3.0);
  // Twelve grains overlapping the drum's facets a little, all round it.
  const V3 axis = V3(1, 0.2, 0).normalized(), u = axis.unitOrthogonal(), v = axis.cross(u);
  const double inner = 4 * kR * std::cos(std::numbers::pi / 16);
  sable::Rng rng(6);
  for (int k = 0; k < 12; ++k) {
    const double a = 2 * std::numbers::pi * (k + rng.uniform(0.2, 0.8)) / 12;
    const V3 x =
        rng.uniform(-6, 6) * kR * axis + (inner + 0.995 * kR) * (std::cos(a) * u + std::sin(a) * v);
    w.particles.add(x, kR, 2500.0, 0, 1.0);
  }
  sable::DemSolver<3> s(w);
  s.initialize();
  for (int step = 0; step < 50; ++step) s.step();
  const auto& wall = w.walls[0];
  const auto& wl = w.neighbors.wall_pairs;
  V3 force = V3::Zero(), torque = V3::Zero();
  double scale_f = 0.0, scale_t = 0.0;
  int contacts = 0;
  for (std::size_t k = 0; k < wl.size(); ++k) {
    if (wl.force[k] == V3::Zero()) continue;
    ++contacts;
    const V3& x = w.particles.x[wl.i[k]];
    const auto f = wall.contact(x, wl.element[k]);
    const double r = w.particles.radius[wl.i[k]];
    const V3 xc = x - (r - 0.5 * (r - f.dist)) * f.n;
    force -= wl.force[k];
    torque -= (xc - wall.pivot).cross(wl.force[k]);
    scale_f += wl.force[k].norm();
    scale_t += (xc - wall.pivot).norm() * wl.force[k].norm();
  }
  ASSERT_GT(contacts, 3);
  EXPECT_LT((wall.force - force).norm(), 1e-12 * scale_f);
  EXPECT_LT((wall.torque - torque).norm(), 1e-12 * scale_t);
  EXPECT_GT(wall.torque.norm(), 0.0);
}

// With a turning mesh, the lists rebuilt when the rebuild test asks (its bound on the far
// end's motion included) give the same bits as lists rebuilt at every step: no contact is
// missed between rebuilds, and the history carries over each rebuild.
TEST(MeshContact, RebuildWhenAskedEqualsRebuildEveryStep) {
  std::uint64_t hashes[2];
  std::uint64_t builds[2];
  for (int every = 0; every < 2; ++every) {
    auto w = bare_world<3>();
    w.gravity = V3(0, 0, -9.81);
    // A paddle: a flat box, 12 R long, turning fast about z through one end.
    w.walls.push_back(
        mesh_wall(sable::box_surface<3>(V3(0, -kR, 0), V3(12 * kR, kR, 2 * kR), "paddle")));
    w.walls[0].set_rotation(V3::Zero(), V3(0, 0, 1), 20.0);
    Wall<3> floor = plane_floor();
    floor.point = V3(0, 0, -0.1 * kR);
    w.walls.push_back(floor);
    sable::Rng rng(42);
    for (int k = 0; k < 40; ++k) {
      const double x = rng.uniform(-14, 14), y = rng.uniform(-14, 14), z = rng.uniform(0.9, 4);
      w.particles.add(V3(x, y, z) * kR, 0.9 * kR, 2500.0, 0, 1.0);
    }
    sable::DemSolver<3> s(w);
    s.initialize();
    for (int step = 0; step < 3000; ++step) {
      if (every) w.neighbors.x_ref.clear();
      s.step();
    }
    hashes[every] = motion_hash(w);
    builds[every] = w.neighbors.builds;
  }
  EXPECT_EQ(hashes[0], hashes[1]);
  EXPECT_LT(builds[0], builds[1] / 5);  // the test did save rebuilds
}

// 2D: a disk over the shared vertex of two collinear segments gets one contact, the line's
// force; in the concave right-angle corner of a polyline, two, each a line's.
TEST(MeshContact, PolylineActsAsItsLines) {
  using V2 = Eigen::Vector2d;
  const double a = 5 * kR, delta = 1e-2 * kR;
  auto force_on = [&](Wall<2> wall, const V2& c, int expect) {
    auto w = bare_world<2>();
    w.walls.push_back(std::move(wall));
    w.particles.add(c, kR, 2500.0, 0, 1.0);
    sable::DemSolver<2> s(w);
    s.initialize();
    std::vector<V2> f;
    for (const V2& x : w.neighbors.wall_pairs.force)
      if (x != V2::Zero()) f.push_back(x);
    EXPECT_EQ(static_cast<int>(f.size()), expect);
    return f;
  };
  Wall<2> line, ledge, side;
  line.set_plane(V2(0, 1));
  side.set_plane(V2(1, 0));
  ledge.set_mesh(
      sable::build_surface<2>({V2(-a, 0), V2(0, 0), V2(a, 0)}, {{0, 1}, {1, 2}}, "ledge"));
  const V2 top(0, kR - delta);
  EXPECT_LT((force_on(ledge, top, 1)[0] - force_on(line, top, 1)[0]).norm(),
            1e-12 * force_on(line, top, 1)[0].norm());
  Wall<2> corner;
  corner.set_mesh(
      sable::build_surface<2>({V2(0, a), V2(0, 0), V2(a, 0)}, {{0, 1}, {1, 2}}, "corner"));
  const V2 c(kR - 2 * delta, kR - delta);
  const auto two = force_on(corner, c, 2);
  const V2 fy = force_on(line, c, 1)[0], fx = force_on(side, c, 1)[0];
  ASSERT_EQ(two.size(), 2u);
  const V2& on_floor = two[0].y() > two[0].x() ? two[0] : two[1];
  const V2& on_side = two[0].y() > two[0].x() ? two[1] : two[0];
  EXPECT_LT((on_floor - fy).norm(), 1e-12 * fy.norm());
  EXPECT_LT((on_side - fx).norm(), 1e-12 * fx.norm());
}

}  // namespace
