// The shortcuts of mesh contacts in the DEM (dem/wall_contacts_impl.hpp, update_mesh_reach):
// entries beyond reach at a near-list remake are skipped until the next, and the others are
// tested first against the bound their values at the remake give (MeshShape::
// may_touch_within). Both only skip elements the exact test would reject, so the bits do not
// depend on when the lists are remade. And the list itself: a still mesh's reach.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "sable/collision/neighbor_list.hpp"
#include "sable/core/hash.hpp"
#include "sable/core/rng.hpp"
#include "sable/dem/dem_solver.hpp"
#include "sable/geometry/surface_mesh.hpp"

namespace {

using V3 = Eigen::Vector3d;
using sable::World;

constexpr double kR = 1e-3;  // grain radius (m)

// An n x n grid of squares of side a, two triangles each, in z = 0 centred on the origin.
sable::SurfaceMesh<3> grid(int n, double a) {
  std::vector<V3> v;
  std::vector<std::array<std::uint32_t, 3>> t;
  const double x0 = -0.5 * n * a;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) v.emplace_back(x0 + i * a, x0 + j * a, 0.0);
  const auto id = [n](int i, int j) { return static_cast<std::uint32_t>(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      t.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      t.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return sable::build_surface<3>(std::move(v), std::move(t), "grid");
}

// Shape 0: a faceted cylinder, 32 sides of 5 R round the x axis (convex edges and vertices);
// 1: a fine flat grid (flat edges and vertices).
sable::SurfaceMesh<3> test_surface(int shape) {
  return shape == 0 ? sable::cylinder_surface(V3::Zero(), V3(1, 0, 0), 5 * kR, 20 * kR, 32, 4, true,
                                              "cylinder")
                    : grid(40, 0.5 * kR);
}

// A place in the box round both shapes (and beyond the cylinder's caps).
V3 random_place(sable::Rng& rng) {
  const double x = rng.uniform(-12, 12), y = rng.uniform(-8, 8), z = rng.uniform(-8, 8);
  return V3(x, y, z) * kR;
}

// For grains placed anywhere near a faceted cylinder and a fine grid, moved by up to d from
// where the values were taken: wherever the bound rejects an element, the exact test at the
// new place rejects it too (the bound is a bound, with the solver's slack). The bound must
// also reject most elements far from the grain, or it would spare nothing.
TEST(MeshReach, TheBoundRejectsOnlyWhatTheExactTestRejects) {
  for (int shape = 0; shape < 2; ++shape) {
    V3 origin;
    const sable::MeshShape<3> mesh(test_surface(shape), origin);
    sable::Rng rng(7 + static_cast<std::uint64_t>(shape));
    long rejected = 0, checked = 0;
    for (int trial = 0; trial < 400; ++trial) {
      const V3 x0 = random_place(rng);
      const double r = rng.uniform(0.5, 1.5) * kR, d = rng.uniform(0.0, 0.3) * kR;
      const double ux = rng.uniform(-1, 1), uy = rng.uniform(-1, 1), uz = rng.uniform(-1, 1);
      const V3 x = x0 + d * rng.uniform() * V3(ux, uy, uz).normalized();
      const double slack = mesh.tolerance() + 1e-13 * (3.0 * x.cwiseAbs().maxCoeff() + r);
      for (std::uint32_t e = 0; e < mesh.elements(); ++e) {
        if (sable::MeshShape<3>::may_touch_within(mesh.reach_values(x0, e), d, r, slack)) continue;
        ++rejected;
        ASSERT_FALSE(mesh.may_touch(x, r, e)) << "shape " << shape << " trial " << trial;
      }
      checked += mesh.elements();
    }
    EXPECT_GT(rejected, checked / 2) << "shape " << shape;
  }
}

// An element that answers for no feature at c answers for none anywhere within its margin of
// c (less the solver's slack): each region test's value moves by at most the distance moved.
// Near a faceted cylinder (convex edges and vertices) and a fine flat grid (flat ones).
TEST(MeshReach, NoFeatureWithinTheMargin) {
  for (int shape = 0; shape < 2; ++shape) {
    V3 origin;
    const sable::MeshShape<3> mesh(test_surface(shape), origin);
    sable::Rng rng(11 + static_cast<std::uint64_t>(shape));
    long kept = 0;
    for (int trial = 0; trial < 300; ++trial) {
      const V3 c = random_place(rng);
      const double slack = mesh.tolerance() + 1e-13 * (3.0 * c.cwiseAbs().maxCoeff() + kR);
      for (std::uint32_t e = 0; e < mesh.elements(); ++e) {
        double margin = 0.0;
        if (mesh.contact(origin, c, e, margin).active) {
          EXPECT_EQ(margin, 0.0);
          continue;
        }
        ASSERT_GE(margin, 0.0);
        if (margin <= slack) continue;
        // Out to the border of the margin (0.999 of it), in a random direction.
        const double ux = rng.uniform(-1, 1), uy = rng.uniform(-1, 1), uz = rng.uniform(-1, 1);
        const V3 c2 = c + 0.999 * (margin - slack) * V3(ux, uy, uz).normalized();
        ASSERT_FALSE(mesh.contact(origin, c2, e).active) << "shape " << shape << " trial " << trial;
        ++kept;
      }
    }
    EXPECT_GT(kept, 1000) << "shape " << shape;
  }
}

// A fine floor: in 3D the grid of 3,200 triangles of 0.5 R; in 2D 80 segments of 0.25 R.
template <int D>
sable::SurfaceMesh<D> fine_floor() {
  if constexpr (D == 3) {
    return grid(40, 0.5 * kR);
  } else {
    std::vector<Eigen::Vector2d> v;
    std::vector<std::array<std::uint32_t, 2>> t;
    for (int i = 0; i <= 80; ++i) v.emplace_back((-10.0 + 0.25 * i) * kR, 0.0);
    for (std::uint32_t i = 0; i < 80; ++i) t.push_back({i, i + 1});
    return sable::build_surface<2>(std::move(v), std::move(t), "fine line");
  }
}

// Grains at about their resting overlap (5e-4 R) on a fine still floor, sliding across its
// edges at up to 0.1 m/s for 2,000 steps of 2 us (0.4 R, about one edge each; the Rayleigh
// time is 43 steps), the lists remade at every step (`every`: the
// skipped entries, bounds and margins then taken afresh at each step) or only when due. The
// grains' motion and the floor's force, hashed.
template <int D>
std::uint64_t fine_floor_run(bool every) {
  using Vec = Eigen::Matrix<double, D, 1>;
  World<D> w;
  w.materials.add({"g", 2500.0, 1e7, 0.3, 0.5, 0.5, 0.0});
  w.materials.finalize();
  w.neighbors.skin = 0.2 * kR;
  w.neighbors.domain_lo = -0.02 * Vec::Ones();
  w.neighbors.domain_hi = 0.02 * Vec::Ones();
  w.dt = 2e-6;
  w.reorder_every = 0;
  w.gravity = -9.81 * Vec::Unit(D - 1);
  sable::Wall<D> floor;
  floor.name = "floor";
  floor.set_mesh(fine_floor<D>());
  w.walls.push_back(std::move(floor));
  sable::Rng rng(3);
  const int n = D == 3 ? 36 : 6;  // 3D: a 6 x 6 square, 2D: a row, 2.5 R apart
  for (int k = 0; k < n; ++k) {
    const double height = rng.uniform(0.8994, 0.8996);
    const int col = k % 6;
    Vec x = Vec::Zero();
    x[0] = 2.5 * (col - 2.5);
    if constexpr (D == 3) {
      const int row = k / 6;
      x[1] = 2.5 * (row - 2.5);
    }
    x[D - 1] = height;
    w.particles.add(x * kR, 0.9 * kR, 2500.0, 0, 1.0);
    Vec v = Vec::Zero();
    for (int d = 0; d + 1 < D; ++d) v[d] = rng.uniform(-0.1, 0.1);
    w.particles.v.back() = v;
  }
  sable::DemSolver<D> s(w);
  s.initialize();
  for (int step = 0; step < 2000; ++step) {
    if (every) w.neighbors.x_ref.clear();
    s.step();
  }
  // The grains still press on the floor (gravity holds them): it pushes up, on each of them.
  EXPECT_LT(w.walls[0].force[D - 1], 0.0);
  int touching = 0;
  for (std::size_t k = 0; k < w.neighbors.wall_pairs.size(); ++k)
    touching += w.neighbors.wall_pairs.force[k] != Vec::Zero() ? 1 : 0;
  EXPECT_GE(touching, n);
  sable::Hasher h;
  for (const auto* a : {&w.particles.x, &w.particles.v})
    h.bytes(a->data(), a->size() * sizeof(Vec));
  h.bytes(w.particles.omega.data(), w.particles.omega.size() * sizeof(w.particles.omega[0]));
  h.bytes(w.walls[0].force.data(), sizeof(Vec));
  return h.digest();
}

// The same bits whether the lists are remade at every step or when due: the shortcuts skip
// only what the exact tests reject.
TEST(MeshReach, FineFloorGivesTheSameBitsWhateverTheRemakes3D) {
  EXPECT_EQ(fine_floor_run<3>(false), fine_floor_run<3>(true));
}

TEST(MeshReach, FineLineGivesTheSameBitsWhateverTheRemakes2D) {
  EXPECT_EQ(fine_floor_run<2>(false), fine_floor_run<2>(true));
}

// The list reach (NeighborList::list_reach): a still mesh lists its elements within half the
// skin, a moving one within the whole skin, exactly as brute force with the same distance
// function finds them. Then grains random-walking over a fine still floor (steps of 0.098
// skin in persistent directions, so a grain can cover half the skin in 6 steps), and the
// floor sliding and rising under them, the lists rebuilt only when needs_rebuild says so:
// at every step every touching (grain, element) pair is listed. Exact: set membership.
TEST(MeshReach, StillMeshListsWithinHalfTheSkinAndMissesNoContact) {
  using Entry = std::pair<std::uint32_t, std::uint32_t>;
  const double skin = 0.2 * kR;
  std::vector<sable::Wall<3>> walls(1);
  walls[0].name = "floor";
  walls[0].set_mesh(grid(40, 0.5 * kR));
  sable::ParticleStore<3> p;
  sable::Rng rng(11);
  std::vector<V3> step_of;
  for (int k = 0; k < 150; ++k) {
    const V3 x(rng.uniform(-8, 8), rng.uniform(-8, 8), rng.uniform(0.85, 1.15));
    p.add(x * kR, 0.9 * kR, 2500.0, 0, 1.0);
    step_of.push_back(V3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)).normalized());
  }
  sable::NeighborList<3> nl;
  nl.skin = skin;
  nl.domain_lo = V3::Constant(-0.012);
  nl.domain_hi = V3::Constant(0.012);
  const auto brute = [&](double reach, bool touching) {
    std::vector<Entry> out;
    const auto& mesh = *walls[0].mesh();
    for (std::uint32_t i = 0; i < p.size(); ++i)
      for (std::uint32_t e = 0; e < mesh.elements(); ++e) {
        const double gap = mesh.element_distance(p.x[i], e) - p.radius[i];
        if (touching ? gap < 0.0 : gap < reach) out.emplace_back(i, e);
      }
    return out;
  };
  const auto listed = [&] {
    std::vector<Entry> out;
    for (std::size_t k = 0; k < nl.wall_pairs.size(); ++k)
      out.emplace_back(nl.wall_pairs.i[k], nl.wall_pairs.element[k]);
    return out;
  };
  nl.build(p, walls);
  EXPECT_EQ(nl.wall_reach, std::vector<double>{0.5 * skin});
  EXPECT_EQ(listed(), brute(0.5 * skin, false));
  EXPECT_LT(listed().size(), brute(skin, false).size() * 3 / 4);  // the half reach spares many
  // Grain pairs force a rebuild at 2 dp = skin; a still mesh adds none before, a moved one
  // does once dp + dw reaches its half skin.
  const V3 x0 = p.x[0];
  p.x[0].x() += 0.45 * skin;
  EXPECT_FALSE(nl.needs_rebuild(p, walls));
  walls[0].point.x() += 0.06 * skin;
  walls[0].place();
  EXPECT_TRUE(nl.needs_rebuild(p, walls));
  walls[0].point.x() -= 0.06 * skin;
  walls[0].place();
  p.x[0] = x0;
  walls[0].velocity = V3(0.0, 0.0, 1e-3);  // moving: the whole skin
  nl.build(p, walls);
  EXPECT_EQ(nl.wall_reach, std::vector<double>{skin});
  EXPECT_EQ(listed(), brute(skin, false));

  walls[0].velocity = V3::Zero();
  nl.build(p, walls);
  std::size_t rebuilds = 0, touching = 0;
  for (int step = 0; step < 160; ++step) {
    if (nl.needs_rebuild(p, walls)) {
      nl.build(p, walls);
      ++rebuilds;
    }
    const auto have = listed();
    for (const Entry& t : brute(0.0, true)) {
      ++touching;
      ASSERT_TRUE(std::binary_search(have.begin(), have.end(), t))
          << "step " << step << ": grain " << t.first << " touches element " << t.second
          << " unlisted";
    }
    for (std::size_t k = 0; k < p.size(); ++k) {
      if (rng.uniform() < 0.1)
        step_of[k] = V3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)).normalized();
      p.x[k] += (step >= 100 ? 0.01 : 1.0) * 0.098 * skin * step_of[k];
    }
    if (step >= 100) {  // the floor slides and rises at 0.05 skin a step
      walls[0].velocity = V3(0.03, 0.0, 0.04) * skin;
      walls[0].advance(1.0);
    }
  }
  EXPECT_GT(touching, 5000u);
  EXPECT_GT(rebuilds, 15u);  // rebuilds happened ...
  EXPECT_LT(rebuilds, 80u);  // ... but not every step
}

}  // namespace
