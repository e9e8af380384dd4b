// Neighbour list: candidate sets against brute force, sorting, history carry-over, and the
// rebuild criterion that guarantees no touching pair is ever missing between rebuilds.
//
// The lists are compared as exact sets: the list and the brute force use the same test
// (|xi - xj|^2 < (ri + rj + skin)^2, distance - r < skin), and random positions never sit on
// the boundary to the last bit.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "sable/collision/neighbor_list.hpp"
#include "sable/core/particles.hpp"
#include "sable/core/rng.hpp"
#include "sable/geometry/walls.hpp"

#include "geometry_helpers.hpp"

namespace {

using Pair = std::pair<std::uint32_t, std::uint32_t>;
template <int D>
using Vec = typename sable::Space<D>::Vec;

using sable::test::random_dir;
using sable::test::random_step;
using sable::test::random_vec;

template <int D>
std::vector<Pair> brute_pairs(const sable::ParticleStore<D>& p, double skin) {
  std::vector<Pair> out;
  for (std::uint32_t i = 0; i < p.size(); ++i)
    for (std::uint32_t j = i + 1; j < p.size(); ++j) {
      const double reach = p.radius[i] + p.radius[j] + skin;
      if ((p.x[i] - p.x[j]).squaredNorm() < reach * reach) out.emplace_back(i, j);
    }
  return out;
}

template <int D>
std::vector<Pair> brute_wall_pairs(const sable::ParticleStore<D>& p,
                                   const std::vector<sable::Wall<D>>& walls, double skin) {
  std::vector<Pair> out;
  Vec<D> n;
  for (std::uint32_t i = 0; i < p.size(); ++i)
    for (std::uint32_t w = 0; w < walls.size(); ++w)
      if (walls[w].distance(p.x[i], n) - p.radius[i] < skin) out.emplace_back(i, w);
  return out;
}

template <int D>
std::vector<Pair> list_pairs(const sable::PairList<D>& l) {
  std::vector<Pair> out;
  for (std::size_t k = 0; k < l.size(); ++k) out.emplace_back(l.i[k], l.j[k]);
  return out;
}

template <int D>
std::vector<Pair> list_wall_pairs(const sable::WallPairList<D>& l) {
  std::vector<Pair> out;
  for (std::size_t k = 0; k < l.size(); ++k) out.emplace_back(l.i[k], l.wall[k]);
  return out;
}

template <int D>
sable::Wall<D> plane(const Vec<D>& point, const Vec<D>& normal) {
  sable::Wall<D> w;
  w.point = point;
  w.set_plane(normal.normalized());
  return w;
}

// The planes of the box [0, 1]^D, normals pointing inside.
template <int D>
std::vector<sable::Wall<D>> unit_box_walls() {
  std::vector<sable::Wall<D>> walls;
  for (int d = 0; d < D; ++d) {
    const Vec<D> e = Vec<D>::Unit(d);
    walls.push_back(plane<D>(Vec<D>::Zero(), e));
    walls.push_back(plane<D>(e, -e));
  }
  return walls;
}

// Polydisperse grains: n inside [0, 1]^D plus two clusters outside it (beyond lo and hi).
template <int D>
sable::ParticleStore<D> random_grains(std::uint64_t seed, std::size_t n, double rmin, double rmax) {
  sable::Rng rng(seed);
  sable::ParticleStore<D> p;
  sable::test::add_random_grains(p, rng, n, rmin, rmax);
  for (std::size_t k = 0; k < 40; ++k) {
    const double c = k < 20 ? -0.35 : 1.6;  // cluster centre, outside the domain box
    p.add(Vec<D>::Constant(c) + random_vec<D>(rng, -0.08, 0.08), rng.uniform(rmin, rmax), 2500.0, 0,
          1.0);
  }
  return p;
}

template <int D>
void check_pair_set(double rmin, double rmax, double skin) {
  auto p = random_grains<D>(11, 500, rmin, rmax);
  const auto expected = brute_pairs(p, skin);
  ASSERT_GT(expected.size(), 100u);  // the test must see many pairs to mean anything
  std::size_t outside = 0;
  for (const auto& [i, j] : expected)
    if (i >= 500) ++outside;
  ASSERT_GT(outside, 10u);  // and pairs among the grains outside the domain box

  // The domain box as the scenario gives it, a much smaller one (most grains outside), and
  // boxes one cell thick along an axis (the search reads each row of cells along axis 0 as
  // one run: a row of one cell, and a single row of rows, must still be whole).
  std::vector<Vec<D>> highs = {Vec<D>::Constant(1.0), Vec<D>::Constant(0.3)};
  for (int d = 0; d < D; ++d) {
    Vec<D> thin = Vec<D>::Constant(1.0);
    thin[d] = 1e-3;
    highs.push_back(thin);
  }
  for (const Vec<D>& hi : highs) {
    SCOPED_TRACE(hi.transpose());
    sable::NeighborList<D> nl;
    nl.skin = skin;
    nl.domain_lo = Vec<D>::Zero();
    nl.domain_hi = hi;
    nl.build(p, {});
    EXPECT_EQ(list_pairs(nl.pairs), expected);  // brute force is generated in (i, j) order
    EXPECT_TRUE(std::is_sorted(nl.pairs.i.begin(), nl.pairs.i.end()));
    for (std::size_t k = 0; k < nl.pairs.size(); ++k) EXPECT_LT(nl.pairs.i[k], nl.pairs.j[k]);
    EXPECT_EQ(nl.wall_pairs.size(), 0u);
  }
}

// Guards the candidate set in 3D: exactly the brute-force pairs (i < j) closer than
// ri + rj + skin, sorted by (i, j), including grains outside the domain box. Exact: same test.
TEST(NeighborList, PairSetMatchesBruteForce3D) {
  check_pair_set<3>(0.01, 0.04, 0.01);
}

// Guards the same in 2D (disks). Exact: same test as the list's.
TEST(NeighborList, PairSetMatchesBruteForce2D) {
  check_pair_set<2>(0.004, 0.015, 0.004);
}

// Guards the parallel search (blocks of grains per thread, joined in order; it runs from
// 4096 grains): on one, two and three threads, exactly the brute-force pairs, sorted. Exact:
// same test as the list's.
template <int D>
void check_parallel_pair_set(double r) {
  sable::Rng rng(23);
  sable::ParticleStore<D> p;
  sable::test::add_random_grains(p, rng, 6000, 0.5 * r, r);
  const auto expected = brute_pairs(p, r);
  ASSERT_GT(expected.size(), 6000u);  // a dense enough set: every grain has partners
  const int threads = omp_get_max_threads();
  for (int t : {1, 2, 3}) {
    SCOPED_TRACE(t);
    omp_set_num_threads(t);
    sable::NeighborList<D> nl;
    nl.skin = r;
    nl.domain_lo = Vec<D>::Zero();
    nl.domain_hi = Vec<D>::Constant(1.0);
    nl.build(p, {});
    EXPECT_EQ(list_pairs(nl.pairs), expected);
  }
  omp_set_num_threads(threads);
}

TEST(NeighborList, ParallelPairSetMatchesBruteForce3D) {
  check_parallel_pair_set<3>(0.025);
}

TEST(NeighborList, ParallelPairSetMatchesBruteForce2D) {
  check_parallel_pair_set<2>(0.006);
}

// Guards the lists' memory across rebuilds (core/grow.hpp): a list that grows by a few %
// per rebuild (a settling bed) is refilled in the memory it had, not given new memory (whose
// pages the kernel hands in one fault at a time) at every rebuild. The pair list and its
// spare are swapped at each build, so the arrays two builds apart are compared. Exact:
// which memory an array holds.
TEST(NeighborList, GrowingListKeepsItsMemory) {
  sable::Rng rng(5);
  sable::ParticleStore<3> p;
  sable::test::add_random_grains(p, rng, 2000, 0.01, 0.02);
  sable::NeighborList<3> nl;
  nl.skin = 0.01;
  nl.domain_lo = Vec<3>::Zero();
  nl.domain_hi = Vec<3>::Constant(1.0);
  nl.build(p, {});
  nl.build(p, {});
  const std::size_t n0 = nl.pairs.size();
  const Vec<3>* shear = nl.pairs.shear.data();
  const std::uint32_t* first = nl.pairs.i.data();
  for (auto& x : p.x) x *= 0.985;  // grains closer: more pairs
  nl.build(p, {});
  nl.build(p, {});
  ASSERT_GT(nl.pairs.size(), n0);           // the list grew...
  ASSERT_LT(nl.pairs.size(), n0 + n0 / 4);  // ...by less than the headroom
  EXPECT_EQ(nl.pairs.shear.data(), shear);
  EXPECT_EQ(nl.pairs.i.data(), first);
}

// Guards the wall candidates: exactly the brute-force (grain, wall) pairs with
// distance - r < skin, in (grain, wall) order, for planes (tilted too) and a cylinder. Exact:
// the same distance function and test.
TEST(NeighborList, WallPairsMatchBruteForce) {
  const double skin = 0.01;
  auto p3 = random_grains<3>(5, 500, 0.01, 0.04);
  auto walls3 = unit_box_walls<3>();
  walls3.push_back(plane<3>(Vec<3>(0.5, 0.5, 0.5), Vec<3>(1.0, -2.0, 0.5)));
  sable::Wall<3> cyl;
  cyl.point = Vec<3>(0.5, 0.45, 0.0);
  cyl.set_cylinder(0.45);
  walls3.push_back(cyl);
  sable::NeighborList<3> nl3;
  nl3.skin = skin;
  nl3.domain_hi = Vec<3>::Ones();
  nl3.build(p3, walls3);
  const auto expected3 = brute_wall_pairs(p3, walls3, skin);
  ASSERT_GT(expected3.size(), 100u);
  EXPECT_EQ(list_wall_pairs(nl3.wall_pairs), expected3);

  auto p2 = random_grains<2>(6, 500, 0.004, 0.015);
  auto walls2 = unit_box_walls<2>();
  walls2.push_back(plane<2>(Vec<2>(0.5, 0.5), Vec<2>(-1.0, 3.0)));
  sable::NeighborList<2> nl2;
  nl2.skin = skin;
  nl2.domain_hi = Vec<2>::Ones();
  nl2.build(p2, walls2);
  const auto expected2 = brute_wall_pairs(p2, walls2, skin);
  ASSERT_GT(expected2.size(), 50u);
  EXPECT_EQ(list_wall_pairs(nl2.wall_pairs), expected2);
}

// Guards history carry-over on rebuild: pairs present before and after keep their shear and
// force bit for bit (exact: a copy), pairs new to the list start at zero, for grain pairs and
// wall pairs alike.
TEST(NeighborList, HistoryCarriedOverOnRebuild) {
  const double skin = 0.01;
  auto p = random_grains<3>(21, 500, 0.01, 0.04);
  auto walls = unit_box_walls<3>();
  sable::NeighborList<3> nl;
  nl.skin = skin;
  nl.domain_hi = Vec<3>::Ones();
  nl.build(p, walls);

  // Distinct values on every other entry, keyed by the pair.
  auto shear_of = [](std::uint32_t a, std::uint32_t b) { return Vec<3>(a + 0.5, b + 0.25, -1.0); };
  auto force_of = [](std::uint32_t a, std::uint32_t b) { return Vec<3>(-2.0, a * 3.0, b * 7.0); };
  std::map<Pair, bool> old_pairs, old_walls;  // value: was given a history
  for (std::size_t k = 0; k < nl.pairs.size(); ++k) {
    const bool set = k % 2 == 0;
    if (set) {
      nl.pairs.shear[k] = shear_of(nl.pairs.i[k], nl.pairs.j[k]);
      nl.pairs.force[k] = force_of(nl.pairs.i[k], nl.pairs.j[k]);
    }
    old_pairs[{nl.pairs.i[k], nl.pairs.j[k]}] = set;
  }
  for (std::size_t k = 0; k < nl.wall_pairs.size(); ++k) {
    const bool set = k % 2 == 1;
    if (set) {
      nl.wall_pairs.shear[k] = shear_of(nl.wall_pairs.i[k], nl.wall_pairs.wall[k]);
      nl.wall_pairs.force[k] = force_of(nl.wall_pairs.i[k], nl.wall_pairs.wall[k]);
    }
    old_walls[{nl.wall_pairs.i[k], nl.wall_pairs.wall[k]}] = set;
  }

  sable::Rng rng(3);
  for (auto& x : p.x) x += random_step<3>(rng, 0.8 * skin);
  nl.build(p, walls);

  std::size_t kept = 0, fresh = 0;
  for (std::size_t k = 0; k < nl.pairs.size(); ++k) {
    const Pair key{nl.pairs.i[k], nl.pairs.j[k]};
    const auto it = old_pairs.find(key);
    if (it != old_pairs.end() && it->second) {
      ++kept;
      EXPECT_EQ(nl.pairs.shear[k], shear_of(key.first, key.second));
      EXPECT_EQ(nl.pairs.force[k], force_of(key.first, key.second));
    } else {
      if (it == old_pairs.end()) ++fresh;
      EXPECT_EQ(nl.pairs.shear[k], Vec<3>::Zero()) << key.first << "-" << key.second;
      EXPECT_EQ(nl.pairs.force[k], Vec<3>::Zero()) << key.first << "-" << key.second;
    }
  }
  EXPECT_GT(kept, 50u);
  EXPECT_GT(fresh, 0u);
  EXPECT_LT(nl.pairs.size(), old_pairs.size() + fresh);  // some pairs were dropped too

  std::size_t wkept = 0, wfresh = 0;
  for (std::size_t k = 0; k < nl.wall_pairs.size(); ++k) {
    const Pair key{nl.wall_pairs.i[k], nl.wall_pairs.wall[k]};
    const auto it = old_walls.find(key);
    if (it != old_walls.end() && it->second) {
      ++wkept;
      EXPECT_EQ(nl.wall_pairs.shear[k], shear_of(key.first, key.second));
      EXPECT_EQ(nl.wall_pairs.force[k], force_of(key.first, key.second));
    } else {
      if (it == old_walls.end()) ++wfresh;
      EXPECT_EQ(nl.wall_pairs.shear[k], Vec<3>::Zero());
      EXPECT_EQ(nl.wall_pairs.force[k], Vec<3>::Zero());
    }
  }
  EXPECT_GT(wkept, 5u);
  EXPECT_GT(wfresh, 0u);
}

// Guards the rebuild criterion of neighbor_list.cpp (rebuild when 2 max|dx| >= skin or
// max|dx| + max|dwall| >= skin): two grains just beyond the skin approach each other by
// 0.49 skin each (no rebuild, and indeed still apart) or 0.51 skin each (rebuild, and indeed
// touching); a wall moving 0.99 / 1.01 skin, and a grain plus a wall. Margins of 1-2 % of the
// skin are far above rounding.
TEST(NeighborList, NeedsRebuildCriterion) {
  const double skin = 0.02, r = 0.1;
  sable::ParticleStore<3> p;
  p.add(Vec<3>(0.0, 0.0, 0.0), r, 2500.0, 0, 1.0);
  p.add(Vec<3>(2 * r + 1.01 * skin, 0.0, 0.0), r, 2500.0, 0, 1.0);
  std::vector<sable::Wall<3>> walls{plane<3>(Vec<3>(0.0, -1.0, 0.0), Vec<3>(0.0, 1.0, 0.0))};
  sable::NeighborList<3> nl;
  nl.skin = skin;
  nl.domain_lo = Vec<3>::Constant(-1.0);
  nl.domain_hi = Vec<3>::Constant(1.0);
  EXPECT_TRUE(nl.needs_rebuild(p, walls));           // never built
  EXPECT_TRUE(nl.needs_rebuild_after(-1.0, walls));  // the DEM drift's "no reference"
  nl.build(p, walls);
  // The DEM step measures the displacement in its drift loop (dem/grain_loops_impl.hpp) and asks
  // needs_rebuild_after(): that path must decide exactly as needs_rebuild() does.
  const auto rebuild = [&] {
    const bool due = nl.needs_rebuild(p, walls);
    // As the drift loop reports it: -1 when x_ref does not hold every grain.
    const double moved =
        nl.x_ref.size() == p.size() ? sable::max_displacement2<3>(p.x, nl.x_ref) : -1.0;
    EXPECT_EQ(nl.needs_rebuild_after(moved, walls), due);
    return due;
  };
  EXPECT_FALSE(rebuild());
  EXPECT_EQ(nl.pairs.size(), 0u);
  EXPECT_EQ(nl.wall_pairs.size(), 0u);
  const auto x0 = p.x;

  sable::test::expect_half_reach_criterion<3>(p, x0, r, skin, [&] { return rebuild(); });

  // A moved wall alone, then together with a grain.
  p.x = x0;
  const Vec<3> w0 = walls[0].point;
  walls[0].point.y() = w0.y() + 0.99 * skin;
  EXPECT_FALSE(rebuild());
  walls[0].point.y() = w0.y() + 1.01 * skin;
  EXPECT_TRUE(rebuild());
  walls[0].point.x() = w0.x() - 1.01 * skin;  // sideways counts too: the criterion is |dwall|
  walls[0].point.y() = w0.y();
  EXPECT_TRUE(rebuild());
  walls[0].point = w0;
  p.x[0].z() = x0[0].z() + 0.3 * skin;
  walls[0].point.y() = w0.y() + 0.69 * skin;
  EXPECT_FALSE(rebuild());
  walls[0].point.y() = w0.y() + 0.71 * skin;
  EXPECT_TRUE(rebuild());

  // After a rebuild at the touching configuration the pair is listed and all is quiet again.
  walls[0].point = w0;
  p.x = x0;
  p.x[0].x() += 0.51 * skin;  // touching
  p.x[1].x() -= 0.51 * skin;
  nl.build(p, walls);
  EXPECT_FALSE(rebuild());
  ASSERT_EQ(nl.pairs.size(), 1u);
  EXPECT_EQ(nl.pairs.i[0], 0u);
  EXPECT_EQ(nl.pairs.j[0], 1u);
  // A new grain or a new wall invalidates the list.
  walls.push_back(plane<3>(Vec<3>(0.0, 0.0, -1.0), Vec<3>(0.0, 0.0, 1.0)));
  EXPECT_TRUE(rebuild());
  walls.pop_back();
  p.add(Vec<3>(0.5, 0.5, 0.5), r, 2500.0, 0, 1.0);
  EXPECT_TRUE(rebuild());
}

// Guards the completeness the skin promises: grains random-walking with persistent directions
// (steps of 0.098 skin, turning at random 1 step in 10, so pairs close in head-on at up to
// 2 skin per 10 steps: a criterion rebuilding at max|dx| >= skin fails here), then nearly still
// while the top wall closes in at 0.099 skin per step; rebuilt only when needs_rebuild says so.
// At every step every truly touching grain pair and grain-wall pair (brute force) must be in
// the list. Exact: a set membership.
TEST(NeighborList, NoTouchingPairMissedBetweenRebuilds) {
  const double skin = 0.01;
  sable::Rng rng(8);
  sable::ParticleStore<3> p;
  std::vector<Vec<3>> step_of;
  for (int k = 0; k < 300; ++k) {
    p.add(random_vec<3>(rng, 0.0, 1.0), rng.uniform(0.04, 0.06), 2500.0, 0, 1.0);
    step_of.push_back(random_dir<3>(rng) * (0.098 * skin));
  }
  auto walls = unit_box_walls<3>();
  sable::NeighborList<3> nl;
  nl.skin = skin;
  nl.domain_hi = Vec<3>::Ones();

  std::vector<std::uint64_t> listed;
  std::vector<Pair> listed_walls;
  std::size_t rebuilds = 0, touching_checked = 0, wall_touching_checked = 0;
  const int steps = 200, still_from = 130;
  for (int step = 0; step < steps; ++step) {
    if (nl.needs_rebuild(p, walls)) {
      nl.build(p, walls);
      ++rebuilds;
      listed.clear();
      for (std::size_t k = 0; k < nl.pairs.size(); ++k)
        listed.push_back(std::uint64_t{nl.pairs.i[k]} << 32 | nl.pairs.j[k]);
      listed_walls = list_wall_pairs(nl.wall_pairs);
    }
    for (std::uint32_t i = 0; i < p.size(); ++i) {
      for (std::uint32_t j = i + 1; j < p.size(); ++j) {
        const double rs = p.radius[i] + p.radius[j];
        if ((p.x[i] - p.x[j]).squaredNorm() >= rs * rs) continue;
        ++touching_checked;
        EXPECT_TRUE(std::binary_search(listed.begin(), listed.end(), std::uint64_t{i} << 32 | j))
            << "step " << step << ": touching pair " << i << "-" << j << " not listed";
      }
      Vec<3> n;
      for (std::uint32_t w = 0; w < walls.size(); ++w) {
        if (walls[w].distance(p.x[i], n) >= p.radius[i]) continue;
        ++wall_touching_checked;
        EXPECT_TRUE(std::binary_search(listed_walls.begin(), listed_walls.end(), Pair{i, w}))
            << "step " << step << ": grain " << i << " touching wall " << w << " not listed";
      }
    }
    if (::testing::Test::HasFailure()) break;
    const bool still = step >= still_from;
    for (std::size_t k = 0; k < p.size(); ++k) {
      if (rng.uniform() < 0.1) step_of[k] = random_dir<3>(rng) * (0.098 * skin);
      p.x[k] += still ? 0.01 * step_of[k] : step_of[k];
    }
    walls[5].point.z() -= (still ? 0.099 : 0.02) * skin;  // the top (z = 1) plane moves down
  }
  EXPECT_GT(touching_checked, 1000u);
  EXPECT_GT(wall_touching_checked, 1000u);
  EXPECT_GT(rebuilds, 10u);   // rebuilds happened ...
  EXPECT_LT(rebuilds, 100u);  // ... but not every step
}

}  // namespace
