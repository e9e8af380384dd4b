// Shared by the contact-detection tests (neighbour list, near list): random positions,
// directions and steps drawn from the project's seeded generator (every run sees the same
// data), and the displacement check of a list's "may a pair now touch?" criterion.
#pragma once

#include <gtest/gtest.h>

#include <vector>

#include "sable/core/particles.hpp"
#include "sable/core/rng.hpp"
#include "sable/core/space.hpp"

namespace sable::test {

template <int D>
using Vec = typename Space<D>::Vec;

template <int D>
Vec<D> random_vec(Rng& rng, double lo, double hi) {
  Vec<D> v;
  for (int d = 0; d < D; ++d) v[d] = rng.uniform(lo, hi);
  return v;
}

// A unit vector in a uniformly random direction.
template <int D>
Vec<D> random_dir(Rng& rng) {
  Vec<D> v;
  do v = random_vec<D>(rng, -1.0, 1.0);
  while (v.squaredNorm() > 1.0 || v.squaredNorm() < 1e-6);
  return v.normalized();
}

// A random vector of length below `len`, in a uniformly random direction.
template <int D>
Vec<D> random_step(Rng& rng, double len) {
  return random_dir<D>(rng) * (len * rng.uniform());
}

// n polydisperse grains at rest at uniform positions inside [0, 1]^D, radii uniform in
// [rmin, rmax], added to p.
template <int D>
void add_random_grains(ParticleStore<D>& p, Rng& rng, std::size_t n, double rmin, double rmax) {
  for (std::size_t k = 0; k < n; ++k) {
    // The radius is drawn first, then the position, in statements of their own: as arguments
    // of one call their order was the compiler's (GCC drew the radius first, clang the
    // position, and the packing differed).
    const double r = rng.uniform(rmin, rmax);
    p.add(random_vec<D>(rng, 0.0, 1.0), r, 2500.0, 0, 1.0);
  }
}

// Grains 0 and 1 of `p`, of radius r, start at x0 a gap of just over `reach` apart along x
// (the list's skin, or the near list's inner skin). Closing in by 0.49 reach each must leave
// them apart and `moved()` false; by 0.51 reach each, touching and `moved()` true. Grain 1
// alone moving 0.49 / 0.51 reach sideways: false / true. Ends with p.x = x0. Margins of 1-2 %
// of the reach are far above rounding.
template <int D, class Moved>
void expect_half_reach_criterion(ParticleStore<D>& p, const std::vector<Vec<D>>& x0, double r,
                                 double reach, Moved moved) {
  auto approach = [&](double each) {
    p.x = x0;
    p.x[0].x() += each * reach;
    p.x[1].x() -= each * reach;
    return (p.x[1] - p.x[0]).norm() - 2 * r;  // gap
  };
  EXPECT_GT(approach(0.49), 0.0);
  EXPECT_FALSE(moved());
  EXPECT_LT(approach(0.51), 0.0);
  EXPECT_TRUE(moved());
  p.x = x0;
  p.x[1].y() += 0.49 * reach;
  EXPECT_FALSE(moved());
  p.x[1].y() += 0.02 * reach;
  EXPECT_TRUE(moved());
  p.x = x0;
}

}  // namespace sable::test
