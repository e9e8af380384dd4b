// DemSolver's GrainPass: what the grain loops read and write, and a grain's sum, kick and
// check (dem/grain_loops_impl.hpp). Private to the DEM solver's translation units: the pair pass
// (dem_solver_impl.hpp) closes its grains with it as it goes.
#pragma once

#include <cstddef>
#include <cstdint>

#include "sable/dem/dem_solver.hpp"
#include "sable/world/guards.hpp"

namespace sable {

// What the grain loops read and write, as raw pointers and plain copies taken once per loop
// (reached through world_, every vector store would make the compiler fetch each array's
// address again: see PairPass in dem_solver_impl.hpp). Each thread works on its own copy
// (firstprivate).
template <int D, class Laws>
struct DemSolver<D, Laws>::GrainPass {
  using S = Space<D>;
  using Vec = typename S::Vec;
  using Rot = typename S::Rot;
  Vec *x, *v;
  typename S::Orientation* q;
  Rot* omega;  // the grains' spins
  Vec* f;
  Rot* t;
  const double *inv_mass, *inv_inertia, *radius;
  Vec gravity;
  double keep;  // background damping over a half kick: 1 / (1 + nu h)
  double max_speed;
  // The gather: grain i's contacts, in the order of NearList's incidence and wall_begin.
  const std::uint32_t *near, *first_begin, *second_begin, *second_pairs, *wall_begin;
  EntryWalk wall_walk;  // the wall entries the step visits (see skip_far_entries)
  const Vec *pair_force, *wall_force;
  const Rot *pair_moment, *wall_moment, *pair_roll, *wall_roll;
  const double *pair_delta, *wall_delta;
  const std::uint8_t* flags;  // the pair pass's (kGathered: the sum is left to the gather)
  const std::uint8_t* kind;   // the grains' own flags (kGhost: stepped by another process)
  bool rolling;

  bool ghost(std::size_t k) const { return (kind[k] & kGhost) != 0; }

  // v += h a, omega += h alpha: a half kick; gravity enters as an acceleration. The
  // background damping -m nu v, -I nu omega is taken implicitly (v_new feels it): stable for
  // any nu h.
  // False for a grain that does not move (infinite mass).
  [[gnu::always_inline]] bool kick(std::size_t k, double h) const {
    if (inv_mass[k] == 0.0) return false;
    v[k] += h * (f[k] * inv_mass[k] + gravity);
    omega[k] += h * inv_inertia[k] * t[k];
    if (keep != 1.0) {
      v[k] *= keep;
      omega[k] *= keep;
    }
    return true;
  }

  // Grain i's sum: from its contacts' slots when `full` (the wet pass's grains, and those
  // the dry pass left to the gather: see dry_pair_forces), else its walls' terms added to the
  // pair pass's sum. The torque of force F at lever arm -(R - delta/2) n is
  // -(R - delta/2) (n x F) for the first grain; the second grain gets -F at +(R - delta/2) n:
  // the same sign, its own R. A grain's terms are summed in list order: the entries where it
  // is the second member (their first member has a smaller index, so they come first in the
  // list), then those where it is the first, then its walls; the dry pass meets them in that
  // order too, so either way the bits are the same. Rolling resistance: each contact's couple
  // follows its force's torque (+ on the first grain, - on the second).
  [[gnu::always_inline]] void sum(std::size_t i, bool full) const {
    if (!full && wall_begin[i] == wall_begin[i + 1]) return;  // the pass's sum is final
    Vec fi = full ? S::zero() : f[i];
    Rot ti = full ? S::zero_rot() : t[i];
    const double r = radius[i];
    for (std::uint32_t s = second_begin[i]; full && s < second_begin[i + 1]; ++s) {
      const std::uint32_t k = second_pairs[s];
      fi -= pair_force[k];
      ti -= (r - 0.5 * pair_delta[k]) * pair_moment[k];
      if (rolling) ti -= pair_roll[k];
    }
    for (std::uint32_t m = first_begin[i]; full && m < first_begin[i + 1]; ++m) {
      const std::uint32_t k = near[m];
      fi += pair_force[k];
      ti -= (r - 0.5 * pair_delta[k]) * pair_moment[k];
      if (rolling) ti += pair_roll[k];
    }
    // Entries apart hold zeros and are left out (a mesh's far entries are not visited): the
    // sum is the same whichever entries the last remake found far.
    const std::uint32_t w1 = wall_begin[i + 1];
    for (std::uint32_t k = wall_walk.first(wall_begin[i]); k < w1; k = wall_walk.next(k)) {
      if (wall_delta[k] == 0.0) continue;
      fi += wall_force[k];
      ti -= (r - 0.5 * wall_delta[k]) * wall_moment[k];
      if (rolling) ti += wall_roll[k];
    }
    f[i] = fi;
    t[i] = ti;
  }

  // What check_grain_states() tests (world/guards.hpp).
  [[gnu::always_inline]] bool sound(std::size_t k) const {
    return motion_ok<D>(v[k], omega[k], max_speed) && position_ok<D>(x[k]);
  }

  // Grain k's closing once its sum is final: its half kick by h (none when 0: forces only)
  // and its check. 1 when its state is unsound (check_grain_states() then names it).
  // A ghost is neither kicked nor checked: its owner does both.
  [[gnu::always_inline]] int close(std::size_t k, double h) const {
    if (ghost(k)) return 0;
    if (h > 0.0) kick(k, h);
    return sound(k) ? 0 : 1;
  }
};

}  // namespace sable
