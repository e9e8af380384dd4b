// Near list (the inner level of the neighbour list): its content against brute force, its
// incidence, the inner skin chosen from the top speed, and the staleness criterion that
// guarantees no touching pair is ever left out between remakes.
//
// Sets are compared exactly: the brute force uses the near list's own test
// (|xi - xj|^2 < (ri + rj + inner)^2 over the entries of the neighbour list), and random
// positions never sit on the boundary to the last bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <vector>

#include "sable/collision/neighbor_list.hpp"
#include "sable/core/particles.hpp"
#include "sable/core/rng.hpp"
#include "sable/dem/near_list.hpp"

#include "geometry_helpers.hpp"

namespace {

template <int D>
using Vec = typename sable::Space<D>::Vec;
using Entries = std::vector<std::uint32_t>;

using sable::test::random_dir;
using sable::test::random_step;
using sable::test::random_vec;

// Polydisperse grains at rest inside [0, 1]^D.
template <int D>
sable::ParticleStore<D> random_grains(std::uint64_t seed, std::size_t n, double rmin, double rmax) {
  sable::Rng rng(seed);
  sable::ParticleStore<D> p;
  sable::test::add_random_grains(p, rng, n, rmin, rmax);
  return p;
}

template <int D>
sable::NeighborList<D> built_list(const sable::ParticleStore<D>& p, double skin) {
  sable::NeighborList<D> nl;
  nl.skin = skin;
  nl.domain_hi = Vec<D>::Ones();
  nl.build(p, {});
  return nl;
}

// The entries k of the list whose gap is below `inner`, ascending: the near list's own test.
template <int D>
Entries brute_near(const sable::ParticleStore<D>& p, const sable::PairList<D>& pl, double inner) {
  Entries out;
  for (std::size_t k = 0; k < pl.size(); ++k) {
    const double reach = p.radius[pl.i[k]] + p.radius[pl.j[k]] + inner;
    if ((p.x[pl.i[k]] - p.x[pl.j[k]]).squaredNorm() < reach * reach)
      out.push_back(static_cast<std::uint32_t>(k));
  }
  return out;
}

Entries complement(const Entries& in, std::size_t n) {
  Entries out;
  for (std::uint32_t k = 0; k < n; ++k)
    if (!std::binary_search(in.begin(), in.end(), k)) out.push_back(k);
  return out;
}

Entries all_entries(std::size_t n) {
  Entries out(n);
  std::iota(out.begin(), out.end(), 0u);
  return out;
}

// Remake and return the entries told to `drop`, ascending, each once. drop may be called
// from several threads, each call for its own entry: it counts into that entry's slot only.
template <int D>
Entries remake(sable::NearList<D>& near, const sable::ParticleStore<D>& p,
               const sable::NeighborList<D>& nl, double dt, bool keep_all) {
  std::vector<int> calls(nl.pairs.size(), 0);
  near.remake(p, nl, dt, keep_all, sable::Domain<D>{}, [&](std::size_t k) { ++calls[k]; });
  Entries dropped;
  for (std::size_t k = 0; k < calls.size(); ++k) {
    EXPECT_LE(calls[k], 1) << "entry " << k << " dropped twice";
    if (calls[k] > 0) dropped.push_back(static_cast<std::uint32_t>(k));
  }
  return dropped;
}

// Both incidences partition the near entries by grain: each entry once in each, under its
// first and its second member respectively, the second ones ascending within each grain.
template <int D>
void check_incidence(const sable::NearList<D>& near, const sable::PairList<D>& pl, std::size_t n) {
  ASSERT_EQ(near.first_begin.size(), n + 1);
  ASSERT_EQ(near.second_begin.size(), n + 1);
  ASSERT_EQ(near.second_pairs.size(), near.index.size());
  EXPECT_EQ(near.first_begin[0], 0u);
  EXPECT_EQ(near.second_begin[0], 0u);
  EXPECT_EQ(near.first_begin[n], near.index.size());
  EXPECT_EQ(near.second_begin[n], near.index.size());
  std::vector<int> in_first(pl.size(), 0), in_second(pl.size(), 0);
  for (std::uint32_t i = 0; i < n; ++i) {
    ASSERT_LE(near.first_begin[i], near.first_begin[i + 1]);
    ASSERT_LE(near.second_begin[i], near.second_begin[i + 1]);
    for (std::uint32_t m = near.first_begin[i]; m < near.first_begin[i + 1]; ++m) {
      EXPECT_EQ(pl.i[near.index[m]], i) << "position " << m;
      ++in_first[near.index[m]];
    }
    for (std::uint32_t m = near.second_begin[i]; m < near.second_begin[i + 1]; ++m) {
      const std::uint32_t k = near.second_pairs[m];
      ASSERT_LT(k, pl.size());
      EXPECT_EQ(pl.j[k], i) << "entry " << k;
      if (m > near.second_begin[i]) {
        EXPECT_LT(near.second_pairs[m - 1], k);
      }
      ++in_second[k];
    }
  }
  for (std::uint32_t k = 0; k < pl.size(); ++k) {
    const int expected = std::binary_search(near.index.begin(), near.index.end(), k) ? 1 : 0;
    EXPECT_EQ(in_first[k], expected) << "entry " << k;
    EXPECT_EQ(in_second[k], expected) << "entry " << k;
  }
}

template <int D>
void check_remake(std::size_t n, double rmin, double rmax, double skin) {
  auto p = random_grains<D>(11, n, rmin, rmax);
  const auto nl = built_list(p, skin);
  sable::NearList<D> near;
  const Entries dropped = remake(near, p, nl, 1e-3, false);
  // At rest the inner skin is its floor, a tenth of the skin.
  EXPECT_EQ(near.skin, sable::NearList<D>::kMinSkinFraction * skin);
  const Entries expected = brute_near(p, nl.pairs, near.skin);
  EXPECT_EQ(near.index, expected);
  EXPECT_EQ(dropped, complement(expected, nl.pairs.size()));
  std::size_t touching = 0, apart = 0;
  for (std::uint32_t k : expected) {
    const std::uint32_t i = nl.pairs.i[k], j = nl.pairs.j[k];
    ((p.x[i] - p.x[j]).norm() - p.radius[i] - p.radius[j] < 0.0 ? touching : apart)++;
  }
  // The test must see touching and apart near entries, and far entries left out.
  ASSERT_GT(touching, 100u);
  ASSERT_GT(apart, 10u);
  ASSERT_GT(nl.pairs.size(), expected.size() + 50);

  // Remade after a move (the neighbour list still valid): recomputed, not accumulated.
  sable::Rng rng(4);
  for (auto& x : p.x) x += random_step<D>(rng, 0.2 * skin);
  ASSERT_FALSE(nl.needs_rebuild(p, {}));
  const Entries dropped2 = remake(near, p, nl, 1e-3, false);
  const Entries expected2 = brute_near(p, nl.pairs, near.skin);
  EXPECT_NE(expected2, expected);
  EXPECT_EQ(near.index, expected2);
  EXPECT_EQ(dropped2, complement(expected2, nl.pairs.size()));
  EXPECT_EQ(near.remakes, 2u);
}

// Guards the content of a remake in 3D: at rest the inner skin is exactly
// kMinSkinFraction * skin, the kept entries are exactly the brute-force entries of the
// neighbour list closer than ri + rj + inner (ascending), and `drop` hears exactly the others,
// once each; a second remake after a move starts afresh. Exact: the same test and arithmetic.
TEST(NearList, RemakeKeepsExactlyTheNearEntries3D) {
  check_remake<3>(2000, 0.01, 0.04, 0.01);
}

// Guards the same in 2D (disks). Exact: same test.
TEST(NearList, RemakeKeepsExactlyTheNearEntries2D) {
  check_remake<2>(1000, 0.004, 0.015, 0.004);
}

// Guards the per-grain incidence the force pass sums through (first member: positions in
// `index`; second member: entries ascending): each near entry once in each, under the right
// grain, for a filtered remake, a keep-all remake, and after grains are added. Exact: integers.
TEST(NearList, IncidencePartitionsTheNearEntries) {
  auto p = random_grains<3>(12, 500, 0.01, 0.04);
  auto nl = built_list(p, 0.01);
  sable::NearList<3> near;
  remake(near, p, nl, 1e-3, false);
  check_incidence(near, nl.pairs, p.size());
  std::size_t empty = 0, several = 0;  // the test must see both kinds of grain
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto c1 = near.first_begin[i + 1] - near.first_begin[i];
    const auto c2 = near.second_begin[i + 1] - near.second_begin[i];
    if (c1 + c2 == 0) ++empty;
    if (c1 > 1 && c2 > 1) ++several;
  }
  EXPECT_GT(empty, 10u);
  EXPECT_GT(several, 0u);

  remake(near, p, nl, 1e-3, true);
  ASSERT_EQ(near.index.size(), nl.pairs.size());
  check_incidence(near, nl.pairs, p.size());

  sable::Rng rng(13);
  for (int k = 0; k < 50; ++k) p.add(random_vec<3>(rng, 0.0, 1.0), 0.03, 2500.0, 0, 1.0);
  nl.build(p, {});
  remake(near, p, nl, 1e-3, false);
  check_incidence(near, nl.pairs, p.size());
  EXPECT_EQ(near.index, brute_near(p, nl.pairs, near.skin));
}

// Guards the inner skin: 2 kStepsPerRemake max|v| dt between its bounds (the fastest grain,
// not another), the skin itself for a fast flow (then every entry of a list just built is kept:
// the same test as the list's), and infinity with keep_all (every entry kept, none dropped,
// even far apart ones). Exact: the same expression; velocity components are short binary
// fractions, so |v|^2 is exact in any summation order.
TEST(NearList, InnerSkinFromTheTopSpeed) {
  const double skin = 0.01, dt = 1e-4;
  auto p = random_grains<3>(14, 500, 0.01, 0.04);
  const auto nl = built_list(p, skin);
  sable::NearList<3> near;
  p.v[7] = Vec<3>(0.375, -0.5, 0.25);
  p.v[20] = Vec<3>(0.0, 0.5, 0.0);
  const double max_v2 = p.v[7].squaredNorm();
  const double expected = 2.0 * sable::NearList<3>::kStepsPerRemake * std::sqrt(max_v2) * dt;
  ASSERT_GT(expected, 2.0 * sable::NearList<3>::kMinSkinFraction * skin);
  ASSERT_LT(expected, 0.5 * skin);
  EXPECT_FALSE(remake(near, p, nl, dt, false).empty());
  EXPECT_EQ(near.skin, expected);
  EXPECT_EQ(near.index, brute_near(p, nl.pairs, expected));
  check_incidence(near, nl.pairs, p.size());

  p.v[20] = Vec<3>(-1e3, 0.0, 0.0);
  EXPECT_EQ(remake(near, p, nl, dt, false), Entries{});
  EXPECT_EQ(near.skin, skin);
  EXPECT_EQ(near.index, all_entries(nl.pairs.size()));

  for (auto& v : p.v) v = Vec<3>::Zero();
  for (auto& x : p.x) x *= 2.0;  // most entries far apart now
  ASSERT_LT(2 * brute_near(p, nl.pairs, skin).size(), nl.pairs.size());
  EXPECT_EQ(remake(near, p, nl, dt, true), Entries{});
  EXPECT_EQ(near.skin, std::numeric_limits<double>::infinity());
  EXPECT_EQ(near.index, all_entries(nl.pairs.size()));
  check_incidence(near, nl.pairs, p.size());
}

// Guards the staleness criterion of near_list.cpp (stale when 2 max|x - x_at_remake| >= inner
// skin, or the neighbour list was rebuilt or changed size, or the grains or keep_all changed):
// two grains just beyond the inner skin approach each other by 0.49 inner skin each (not
// stale, and indeed still apart) or 0.51 (stale, and indeed touching, while the neighbour
// list itself is still valid); a single grain moving 0.49 / 0.51 inner skin. Margins of 1-2 %
// of the inner skin are far above rounding.
TEST(NearList, StaleCriterion) {
  const double skin = 0.02, r = 0.1;
  const double inner = sable::NearList<3>::kMinSkinFraction * skin;  // at rest
  sable::ParticleStore<3> p;
  p.add(Vec<3>(0.0, 0.0, 0.0), r, 2500.0, 0, 1.0);
  p.add(Vec<3>(2 * r + 1.01 * inner, 0.0, 0.0), r, 2500.0, 0, 1.0);
  auto nl = built_list(p, skin);
  ASSERT_EQ(nl.pairs.size(), 1u);
  sable::NearList<3> near;
  EXPECT_TRUE(near.stale(p, nl, false));  // never made
  EXPECT_EQ(remake(near, p, nl, 1e-3, false), Entries{0});
  EXPECT_EQ(near.skin, inner);
  EXPECT_TRUE(near.index.empty());
  EXPECT_FALSE(near.stale(p, nl, false));
  const auto x0 = p.x;

  // The DEM step measures the displacement in its drift loop (dem/grain_loops_impl.hpp) and asks
  // stale_after(): that path must decide exactly as stale() does.
  const auto moved = [&] {
    const bool s = near.stale(p, nl, false);
    // As the drift loop reports it: measured only when the reference holds every grain.
    const double d2 = near.reference().size() == p.size()
                          ? sable::max_displacement2<3>(p.x, near.reference())
                          : 0.0;
    EXPECT_EQ(near.stale_after(d2, p, nl, false), s);
    return s;
  };
  sable::test::expect_half_reach_criterion<3>(p, x0, r, inner, moved);
  p.x[0].x() += 0.51 * inner;  // touching
  p.x[1].x() -= 0.51 * inner;
  EXPECT_FALSE(nl.needs_rebuild(p, {}));  // only the near list knows
  p.x = x0;

  // Remade touching: listed and quiet again; a rebuild, even in place, makes it stale.
  p.x[0].x() += 0.51 * inner;
  p.x[1].x() -= 0.51 * inner;
  EXPECT_EQ(remake(near, p, nl, 1e-3, false), Entries{});
  EXPECT_EQ(near.index, Entries{0});
  EXPECT_FALSE(near.stale(p, nl, false));
  nl.build(p, {});
  EXPECT_TRUE(near.stale(p, nl, false));
  remake(near, p, nl, 1e-3, false);
  EXPECT_FALSE(near.stale(p, nl, false));
  auto edited = nl;  // same build count, other size
  edited.pairs.i.pop_back();
  edited.pairs.j.pop_back();
  EXPECT_TRUE(near.stale(p, edited, false));
  EXPECT_TRUE(near.stale(p, nl, true));  // keep_all changed
  p.add(Vec<3>(0.5, 0.5, 0.5), r, 2500.0, 0, 1.0);
  EXPECT_TRUE(near.stale(p, nl, false));  // a new grain
  nl.build(p, {});
  remake(near, p, nl, 1e-3, false);
  EXPECT_FALSE(near.stale(p, nl, false));
  sable::ParticleStore<3> fewer;  // one grain less, the others where they were
  for (std::size_t k = 0; k < 2; ++k) fewer.add(p.x[k], r, 2500.0, 0, 1.0);
  EXPECT_TRUE(near.stale(fewer, nl, false));

  // Keep-all: every candidate is in, so only the neighbour list's rebuild makes it stale.
  remake(near, p, nl, 1e-3, true);
  EXPECT_FALSE(near.stale(p, nl, true));
  EXPECT_TRUE(near.stale(fewer, nl, true));
  EXPECT_TRUE(near.stale(p, nl, false));  // keep_all changed
  p.x[1].x() -= 0.4 * skin;               // 4 inner skins, still within the list's skin
  p.x[0].y() += 0.4 * skin;
  EXPECT_FALSE(nl.needs_rebuild(p, {}));
  EXPECT_FALSE(near.stale(p, nl, true));
  nl.build(p, {});
  EXPECT_TRUE(near.stale(p, nl, true));
}

// Guards the completeness the inner skin promises: grains random-walking, all at the same
// speed, with persistent directions (turning at random 1 step in 30, so pairs close in
// head-on at up to twice a grain's displacement: a criterion remaking at max|dx| >= inner
// skin fails here), fast, then slow, then faster than ever (a speed-up after a remake at the
// floor); the inner skin (40 |v| dt) is 0.2 skin, then 0.1 (its floor), then 0.4.
// The neighbour list is rebuilt when it says so, the near list remade when stale with the
// velocities of the coming step. At every step every truly touching pair (brute force) must
// be a near entry. Exact: a set membership.
TEST(NearList, NoTouchingPairMissedBetweenRemakes) {
  const double skin = 0.01, dt = 1.0;
  sable::Rng rng(9);
  sable::ParticleStore<3> p;
  std::vector<Vec<3>> dir;
  for (int k = 0; k < 300; ++k) {
    p.add(random_vec<3>(rng, 0.0, 1.0), rng.uniform(0.04, 0.06), 2500.0, 0, 1.0);
    dir.push_back(random_dir<3>(rng));
  }
  sable::NeighborList<3> nl;
  nl.skin = skin;
  nl.domain_hi = Vec<3>::Ones();
  sable::NearList<3> near;

  std::vector<std::uint64_t> listed;  // near entries as (i, j) keys, sorted
  std::size_t rebuilds = 0, remakes = 0, own_remakes = 0, touching_checked = 0;
  std::size_t at_floor = 0, adapted = 0;  // remakes with the inner skin at / above its floor
  const int steps = 400;
  for (int step = 0; step < steps; ++step) {
    const double speed = step < 200 ? 0.005 * skin : (step < 300 ? 0.002 * skin : 0.01 * skin);
    for (std::size_t k = 0; k < p.size(); ++k) {
      if (rng.uniform() < 0.03) dir[k] = random_dir<3>(rng);
      p.v[k] = dir[k] * (speed / dt);
    }
    bool rebuilt = false;
    if (nl.needs_rebuild(p, {})) {
      nl.build(p, {});
      ++rebuilds;
      rebuilt = true;
    }
    if (near.stale(p, nl, false)) {
      remake(near, p, nl, dt, false);
      ++remakes;
      if (!rebuilt) ++own_remakes;
      if (near.skin == sable::NearList<3>::kMinSkinFraction * skin) ++at_floor;
      if (near.skin > sable::NearList<3>::kMinSkinFraction * skin && near.skin < skin) ++adapted;
      check_incidence(near, nl.pairs, p.size());
      listed.clear();
      for (std::uint32_t k : near.index)
        listed.push_back(std::uint64_t{nl.pairs.i[k]} << 32 | nl.pairs.j[k]);
    }
    for (std::uint32_t i = 0; i < p.size(); ++i)
      for (std::uint32_t j = i + 1; j < p.size(); ++j) {
        const double rs = p.radius[i] + p.radius[j];
        if ((p.x[i] - p.x[j]).squaredNorm() >= rs * rs) continue;
        ++touching_checked;
        EXPECT_TRUE(std::binary_search(listed.begin(), listed.end(), std::uint64_t{i} << 32 | j))
            << "step " << step << ": touching pair " << i << "-" << j << " not near";
      }
    if (::testing::Test::HasFailure()) break;
    for (std::size_t k = 0; k < p.size(); ++k) p.x[k] += p.v[k] * dt;
  }
  EXPECT_EQ(near.remakes, remakes);
  EXPECT_GT(touching_checked, 1000u);
  EXPECT_GT(own_remakes, 10u);  // remakes by the near list's own criterion happened ...
  EXPECT_LT(remakes, 100u);     // ... but not every step
  EXPECT_GT(rebuilds, 2u);
  EXPECT_GT(at_floor, 0u);
  EXPECT_GT(adapted, 5u);
}

}  // namespace
