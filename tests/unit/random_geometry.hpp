// Random positions, directions and steps for the contact-detection tests (neighbour list,
// near list), drawn from the project's seeded generator so every test run sees the same data.
#pragma once

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

}  // namespace sable::test
