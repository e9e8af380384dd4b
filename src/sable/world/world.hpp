// The World: everything a solver advances and an output or analysis reads.
//
// DEM now, and the contact-dynamics solver later, work on the same World: the same grains,
// walls, materials and contact lists (with their history). A solver owns no model state of its
// own beyond scratch space, which is what lets snapshots, outputs and analysis be shared.
#pragma once

#include <cstdint>
#include <vector>

#include "sable/collision/neighbor_list.hpp"
#include "sable/contact/registry.hpp"
#include "sable/core/exact_sum.hpp"
#include "sable/core/material.hpp"
#include "sable/core/particles.hpp"
#include "sable/core/rigid_rotation.hpp"
#include "sable/core/rng.hpp"
#include "sable/geometry/grain_shapes.hpp"
#include "sable/geometry/walls.hpp"
#include "sable/world/contact_geometry.hpp"

namespace sable {

// The liquid of a wet sample (capillary cohesion): in bridges (the pair list's `bridge`
// volumes), on the grains (films: liquid of ruptured bridges waiting for a new contact), or
// lost. total = sum of bridges + sum of films + lost at all times (to rounding).
struct LiquidState {
  std::vector<double> film;  // per grain slot (m^3); empty before the first wetting
  double total = 0.0;        // liquid put in by the last wetting (m^3)
  double lost = 0.0;         // RupturedLiquid::kLost: liquid of ruptured bridges (m^3)
  bool wet() const { return total > 0.0; }
  // Per-grain films are held once wet, and as zeros by a capillary law's solver before the
  // wetting: a decomposed run carries and writes them exactly when a serial run has them.
  bool has_films() const { return wet() || !film.empty(); }
};

// World::reorder_every's default: the solver decides from the number of grains
// (world/reorder.hpp, reorder_due()).
inline constexpr std::uint64_t kReorderAuto = ~std::uint64_t{0};

template <int D>
struct World {
  using Vec = typename Space<D>::Vec;

  ParticleStore<D> particles;
  std::vector<Wall<D>> walls;
  MaterialTable materials;
  ContactModel model;
  NeighborList<D> neighbors;  // candidate contacts with their history
  LiquidState liquid;
  GrainShapes shapes;  // the polyhedral grains' shapes (3D; empty while every grain is round)
  // Each list entry's normal, point and depth (world/contact_geometry.hpp): written by the
  // solvers for polyhedral grains, read by outputs and analyses; empty while every grain is
  // round. Not part of the state hash: nothing in a step reads it.
  ContactPoints<D> contact_geometry;

  Vec gravity = Vec::Zero();
  double thickness = 1.0;  // 2D out-of-plane depth (m)
  double dt = 0.0;
  double viscous_rate = 0.0;  // background damping nu (1/s), set per stage; DEM only
  // Integrate orientations. A disk's or sphere's orientation enters no force, so a run that
  // does not read it may leave it as it is (LIGGGHTS' atom_style granular keeps none); the
  // dense pour bed then steps about 8 % faster (bench/ab_dense.sh measures it).
  bool track_orientation = true;
  // Every how many neighbour-list builds the solver (DEM or contact dynamics) moves the
  // grains into cell order first (world/reorder.hpp): their slots then follow space, and a
  // pass over the contacts finds each grain's partners in cache. 0: never; kReorderAuto
  // (the default): every kAutoReorderEvery builds once the world holds kAutoReorderMinGrains
  // grains (reorder_due()).
  std::uint64_t reorder_every = kReorderAuto;
  double time = 0.0;
  std::uint64_t step = 0;
  Rng rng;

  // Run-time guards.
  double overlap_warning = 0.05;  // fraction of the radius
  double max_speed = 1.0e3;       // m/s
};

// Translational plus (unless translation_only) rotational kinetic energy (J; per thickness
// in 2D) of the grains this process steps (ghosts, copies of another process's grains, are
// not counted: world/domain.hpp sums over processes). Rattlers of a static packing keep
// spinning (nothing brakes a free rotation), so an equilibrium test may look at translation
// only. Summed exactly (core/exact_sum.hpp): the same bits in any order of the grains, so for
// any split of them among threads or processes (a stage's end can hang on this value).
template <int D>
ExactSum kinetic_energy_sum(const World<D>& w, bool translation_only = false) {
  const auto& p = w.particles;
  ExactSum e;
  {
    ExactRun run(e);
    for (std::size_t k = 0; k < p.size(); ++k) {
      if (p.flags[k] & (kFixed | kGhost)) continue;
      run.add(0.5 * p.mass[k] * p.v[k].squaredNorm());
      if (translation_only) continue;
      if constexpr (D == 3) {
        if (p.polyhedron(k)) {
          run.add(
              rotational_energy(p.q[k], w.shapes[p.shape_index[k]].moments(p.mass[k]), p.omega[k]));
          continue;
        }
      }
      run.add(0.5 * (p.inv_inertia[k] > 0.0 ? 1.0 / p.inv_inertia[k] : 0.0) *
              Space<D>::rot_norm2(p.omega[k]));
    }
  }
  return e;
}

template <int D>
double kinetic_energy(const World<D>& w, bool translation_only = false) {
  return kinetic_energy_sum(w, translation_only).value();
}

}  // namespace sable
