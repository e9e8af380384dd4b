// The World: everything a solver advances and an output or analysis reads.
//
// DEM now, and the contact-dynamics solver later, work on the same World: the same grains,
// walls, materials and contact lists (with their history). A solver owns no model state of its
// own beyond scratch space, which is what lets snapshots, outputs and analysis be shared.
#pragma once

#include <cstdint>
#include <vector>

#include "sable/collision/neighbor_list.hpp"
#include "sable/contact/contact_model.hpp"
#include "sable/core/material.hpp"
#include "sable/core/particles.hpp"
#include "sable/core/rng.hpp"
#include "sable/geometry/walls.hpp"

namespace sable {

template <int D>
struct World {
  using Vec = typename Space<D>::Vec;

  ParticleStore<D> particles;
  std::vector<Wall<D>> walls;
  MaterialTable materials;
  ContactModel model;
  NeighborList<D> neighbors;  // candidate contacts with their history

  Vec gravity = Vec::Zero();
  double thickness = 1.0;  // 2D out-of-plane depth (m)
  double dt = 0.0;
  double time = 0.0;
  std::uint64_t step = 0;
  Rng rng;

  // Run-time guards.
  double overlap_warning = 0.05;  // fraction of the radius
  double max_speed = 1.0e3;       // m/s
};

// Translational plus rotational kinetic energy (J; per thickness in 2D).
template <int D>
double kinetic_energy(const World<D>& w) {
  const auto& p = w.particles;
  double e = 0.0;
  for (std::size_t k = 0; k < p.size(); ++k) {
    if (p.fixed(k)) continue;
    e += 0.5 * p.mass[k] * p.v[k].squaredNorm();
    e +=
        0.5 * (p.inv_inertia[k] > 0.0 ? 1.0 / p.inv_inertia[k] : 0.0) * Space<D>::rot_norm2(p.w[k]);
  }
  return e;
}

}  // namespace sable
