// The DEM force pass's per-thread views of the data (dem/dem_solver.cpp): raw pointers and
// plain copies, taken once per pass, with the kernels that run per contact (PairPass,
// WallPass) and per grain (GrainPass). Internal to the DEM solver.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "sable/contact/contact_model.hpp"
#include "sable/contact/rolling.hpp"
#include "sable/core/material.hpp"
#include "sable/core/space.hpp"
#include "sable/geometry/walls.hpp"
#include "sable/world/guards.hpp"

namespace sable::dem {

// Entry k is apart. A contact that has just ended forgets its history; entries already apart
// hold zeros and are not written again (most candidates are apart: this saves bandwidth).
// Grain pairs and wall pairs alike, through their arrays' addresses (see PairPass).
template <class Vec, class Rot>
void forget_if_ended(Vec* shear, Vec* force, Rot* moment, double* delta, std::size_t k,
                     const Rot& zero) {
  if (delta[k] == 0.0) return;
  shear[k].setZero();
  force[k].setZero();
  moment[k] = zero;
  delta[k] = 0.0;
}

// How the grain-pair passes sum forces per grain (see dry_forces and GrainPass::finish): store in
// the contact's slots only, for the gather (kGather); add to both grains (kScatter); add to
// the grains not flagged `gathered`, store for the others (kScatterChecked).
enum class Sum : std::uint8_t { kGather, kScatter, kScatterChecked };

// What the grain-pair passes read and write, as raw pointers and plain copies taken once per
// pass. Reached through `this` and std::vector instead, every store of a force (Eigen's SSE
// stores may alias anything) makes the compiler fetch each array's address again: 4 % more
// instructions in the pass (cachegrind, docs/BENCHMARKS.md). Each thread works on its own
// copy (firstprivate).
template <int D>
struct PairPass {
  using S = Space<D>;
  using Vec = typename S::Vec;
  using Rot = typename S::Rot;
  const Vec *x, *v;
  const Rot* w;
  const double *radius, *inv_mass;
  const MaterialIndex* material;
  const std::uint32_t *i, *j;
  Vec *shear, *force;
  Rot* moment;
  double* delta;
  // The dry pass adds forces and torques to grains as it goes (see DemSolver::dry_forces), except
  // to the grains flagged `gathered`, which GrainPass::finish sums from the contacts' slots.
  Vec* grain_force;
  Rot* grain_torque;
  std::uint8_t* gathered;
  const std::uint32_t *second_begin, *second_pairs;
  PairTableView materials;
  ContactModel model;
  double dt;
  // Rolling resistance only (dry_forces<Normal, true>): the springs, each contact's couple on
  // its first grain (for the gather), and each grain's 1 / (I + m R^2).
  Rot *roll, *couple;
  const double* inv_ic;

  template <bool Roll = false>
  void forget(std::size_t k) const {
    if (delta[k] == 0.0) return;  // apart already: everything is zero
    if constexpr (Roll) {
      roll[k] = S::zero_rot();
      couple[k] = S::zero_rot();
    }
    forget_if_ended(shear, force, moment, delta, k, S::zero_rot());
  }

  // The rolling couple of touching pair k on grain a (contact/rolling.hpp), from the force
  // pass's geometry and force; stored for the gather.
  template <class Normal>
  [[gnu::always_inline]] Rot rolling_couple(std::size_t k, std::uint32_t a, std::uint32_t b,
                                            const ContactGeometry<D>& g, const PairParams& pp,
                                            const Vec& f) const {
    Rot m = S::zero_rot();
    if (pp.rolling_friction == 0.0) {
      roll[k] = m;
    } else {
      const RollingCoeffs c = rolling_coeffs(pp.rolling_friction, model.rolling_damping, g.r_eff,
                                             Normal::stiffness(pp, model, g.delta, g.r_eff),
                                             f.dot(g.n), inv_ic[a], inv_ic[b]);
      m = rolling_moment<D>(g.n, Rot(w[a] - w[b]), c, dt, roll[k]);
    }
    couple[k] = m;
    return m;
  }

  // Grains [g0, g1) are this thread's: zero their sums, and flag those that are the second
  // member of an entry whose first member is another thread's (below g0): another thread
  // would add to them, in a race and out of order, so they are gathered instead.
  void own(std::uint32_t g0, std::uint32_t g1) const {
    for (std::uint32_t g = g0; g < g1; ++g) {
      grain_force[g] = S::zero();
      grain_torque[g] = S::zero_rot();
      gathered[g] = second_begin[g] < second_begin[g + 1] && i[second_pairs[second_begin[g]]] < g0;
    }
  }

  // The force of touching pair k (centre offset d = x_i - x_j, |d|^2 = dist2 < rsum^2), with
  // `cohesion` (<= 0) added to its normal force, stored in the pair's slots (n x F only where
  // GrainPass::finish will read it: `How`), and summed per grain as `How` says; raises max_ratio
  // to the overlap over the smaller radius. Shared by the dry and the wet passes.
  template <class Normal, Sum How = Sum::kGather, bool Roll = false>
  [[gnu::always_inline]] void touch(std::size_t k, const Vec& d, double dist2, double rsum,
                                    double cohesion, double& max_ratio) const {
    const std::uint32_t a = i[k], b = j[k];
    const double dist = std::sqrt(dist2);
    ContactGeometry<D> g;
    g.n = d * (1.0 / dist);  // one division, not three
    g.delta = rsum - dist;
    // Lever arms from each centre to the middle of the overlap: -(R_i - delta/2) n for i,
    // +(R_j - delta/2) n for j, so the contact points' velocity difference is
    // v_i - v_j - ((R_i - delta/2) w_i + (R_j - delta/2) w_j) x n: one cross product.
    const double lever_i = radius[a] - 0.5 * g.delta, lever_j = radius[b] - 0.5 * g.delta;
    g.vrel = v[a] - v[b] - S::spin_velocity(lever_i * w[a] + lever_j * w[b], g.n);
    g.r_eff = radius[a] * radius[b] / rsum;
    g.m_eff = 1.0 / (inv_mass[a] + inv_mass[b]);
    const PairParams& pp = materials(material[a], material[b]);
    const Vec f = contact_force<D, Normal>(g, pp, model, dt, shear[k], cohesion);
    force[k] = f;
    delta[k] = g.delta;
    const Rot m = S::moment(g.n, f);
    Rot c = S::zero_rot();  // the rolling couple on a (b gets -c)
    if constexpr (Roll) c = rolling_couple<Normal>(k, a, b, g, pp, f);
    if constexpr (How == Sum::kScatter) {
      // Term for term as GrainPass::finish would add them (see there for the torques).
      grain_force[a] += f;
      grain_torque[a] -= lever_i * m;
      if constexpr (Roll) grain_torque[a] += c;
      grain_force[b] -= f;
      grain_torque[b] -= lever_j * m;
      if constexpr (Roll) grain_torque[b] -= c;
    } else if constexpr (How == Sum::kScatterChecked) {
      if (!gathered[a]) {
        grain_force[a] += f;
        grain_torque[a] -= lever_i * m;
        if constexpr (Roll) grain_torque[a] += c;
      }
      if (!gathered[b]) {
        grain_force[b] -= f;
        grain_torque[b] -= lever_j * m;
        if constexpr (Roll) grain_torque[b] -= c;
      }
      if (gathered[a] | gathered[b]) moment[k] = m;
    } else {
      moment[k] = m;
    }
    const double r_min = std::min(radius[a], radius[b]);
    if (g.delta > max_ratio * r_min) max_ratio = g.delta / r_min;
  }

  // The dry pass over near-list entries [m0, m1) (see DemSolver::dry_forces). Flattened: left
  // to its heuristics, GCC kept some of Eigen's vector operations out of line here once the
  // translation unit held more kernels, and the pass took 14 % more instructions (cachegrind,
  // docs/BENCHMARKS.md).
  template <class Normal, Sum How, bool Roll>
  [[gnu::flatten]] void entries(const std::uint32_t* near, std::uint32_t m0, std::uint32_t m1,
                                double& max_ratio, std::size_t& touching) const {
    for (std::uint32_t m = m0; m < m1; ++m) {
      const std::size_t k = near[m];
      const Vec d = x[i[k]] - x[j[k]];
      const double rsum = radius[i[k]] + radius[j[k]];
      const double dist2 = d.squaredNorm();
      if (dist2 >= rsum * rsum) {
        forget<Roll>(k);
        continue;
      }
      touch<Normal, How, Roll>(k, d, dist2, rsum, 0.0, max_ratio);
      ++touching;
    }
  }
};

// What the wall-contact loop reads and writes, as PairPass (and for the same reason). A wall
// contact has the grain's own radius and mass as the effective ones, and the wall's velocity
// in vrel; the wall does not turn, so the relative spin is the grain's.
template <int D>
struct WallPass {
  using S = Space<D>;
  using Vec = typename S::Vec;
  using Rot = typename S::Rot;
  const Vec *x, *v;
  const Rot* w;
  const double *radius, *mass;
  const MaterialIndex* material;
  const std::uint32_t *i, *wall;
  const Wall<D>* walls;
  Vec *shear, *force;
  Rot* moment;
  double* delta;
  PairTableView materials;
  ContactModel model;
  double dt;
  // Rolling resistance only (Roll): the springs, each contact's couple (for the gather), and
  // each grain's 1 / (I + m R^2).
  Rot *roll, *couple;
  const double* inv_ic;

  // Wall contact k: its force, n x F and overlap in its slots, or its history forgotten if
  // it has ended; raises max_ratio to the overlap over the radius.
  template <class Normal, bool Roll>
  [[gnu::always_inline]] void entry(std::size_t k, double& max_ratio, std::size_t& touching) const {
    const std::uint32_t a = i[k];
    const Wall<D>& wl = walls[wall[k]];
    ContactGeometry<D> g;
    const double dist = wl.distance(x[a], g.n);
    g.delta = radius[a] - dist;
    if (g.delta <= 0.0) {
      if constexpr (Roll) {
        if (delta[k] != 0.0) {
          roll[k] = S::zero_rot();
          couple[k] = S::zero_rot();
        }
      }
      forget_if_ended(shear, force, moment, delta, k, S::zero_rot());
      return;
    }
    // The lever arm is -(R_i - delta/2) n (see PairPass::touch).
    g.vrel = v[a] - wl.velocity - S::spin_velocity((radius[a] - 0.5 * g.delta) * w[a], g.n);
    g.r_eff = radius[a];
    g.m_eff = mass[a];
    const PairParams& pp = materials(material[a], wl.material);
    const Vec f = contact_force<D, Normal>(g, pp, model, dt, shear[k]);
    force[k] = f;
    moment[k] = S::moment(g.n, f);
    delta[k] = g.delta;
    if constexpr (Roll) {
      Rot c = S::zero_rot();
      if (pp.rolling_friction != 0.0) {
        const RollingCoeffs rc = rolling_coeffs(pp.rolling_friction, model.rolling_damping, g.r_eff,
                                                Normal::stiffness(pp, model, g.delta, g.r_eff),
                                                f.dot(g.n), inv_ic[a], 0.0);
        c = rolling_moment<D>(g.n, w[a], rc, dt, roll[k]);
      } else {
        roll[k] = c;
      }
      couple[k] = c;
    }
    max_ratio = std::max(max_ratio, g.delta / radius[a]);
    ++touching;
  }
};

// The half kick of one grain by h: v += h (F/m + g), w += h I^-1 T, then the background
// damping -m nu v, -I nu w taken implicitly (keep = 1 / (1 + nu h): stable for any nu h).
template <int D>
[[gnu::always_inline]] inline void half_kick(typename Space<D>::Vec& v, typename Space<D>::Rot& w,
                                             const typename Space<D>::Vec& f,
                                             const typename Space<D>::Rot& t, double inv_mass,
                                             double inv_inertia, const typename Space<D>::Vec& g,
                                             double h, double keep) {
  v += h * (f * inv_mass + g);
  w += h * inv_inertia * t;
  if (keep != 1.0) {
    v *= keep;
    w *= keep;
  }
}

// What a step's opening half measures for the rest of the step: the grains' largest squared
// displacements since the neighbour list's build and since the near list's remake (for their
// staleness tests: measured here, each would be one more pass over the grains), and whether
// some position is not finite (the guard's other half is in the closing kick). Maxima and an
// or: the same whatever the thread count.
struct DriftMax {
  double since_build = 0.0, since_near = 0.0;
  int bad = 0;
  void merge(const DriftMax& o) {
    since_build = std::max(since_build, o.since_build);
    since_near = std::max(since_near, o.since_near);
    bad |= o.bad;
  }
};

// A step's opening half for one grain: the half kick by h, then the drift by h_drift (fixed
// grains stay), and what DriftMax records. The references are those the next staleness tests
// compare with (null: the list has none for every grain, and is stale anyway).
template <int D>
struct DriftPass {
  using S = Space<D>;
  using Vec = typename S::Vec;
  using Rot = typename S::Rot;
  Vec *x, *v;
  typename S::Orientation* q;
  Rot* w;
  const Vec* f;
  const Rot* t;
  const double *inv_mass, *inv_inertia;
  const Vec *x_build, *x_near;
  Vec gravity;
  double h, h_drift, keep;
  bool turning;

  [[gnu::always_inline]] void grain(std::size_t k, DriftMax& m) const {
    if (inv_mass[k] != 0.0) {
      half_kick<D>(v[k], w[k], f[k], t[k], inv_mass[k], inv_inertia[k], gravity, h, keep);
      x[k] += h_drift * v[k];
      if (turning) q[k] = S::rotate(q[k], w[k], h_drift);
    }
    m.bad |= position_ok<D>(x[k]) ? 0 : 1;
    if (x_build) m.since_build = std::max(m.since_build, (x[k] - x_build[k]).squaredNorm());
    if (x_near) m.since_near = std::max(m.since_near, (x[k] - x_near[k]).squaredNorm());
  }

  // The loop's result for the staleness tests: infinite for a list without references.
  DriftMax settle(DriftMax m) const {
    constexpr double kUnknown = std::numeric_limits<double>::infinity();
    if (!x_build) m.since_build = kUnknown;
    if (!x_near) m.since_near = kUnknown;
    return m;
  }
};

// What the grains' last loop reads and writes (see finish), as raw pointers taken once per
// step like PairPass.
template <int D>
struct GrainPass {
  using S = Space<D>;
  using Vec = typename S::Vec;
  using Rot = typename S::Rot;
  Vec *force, *v;
  Rot *torque, *w;
  const double *radius, *inv_mass, *inv_inertia;
  const std::uint32_t *near, *first_begin, *second_begin, *second_pairs, *wall_begin;
  const Vec *pair_force, *wall_force;
  const Rot *pair_moment, *wall_moment, *pair_roll, *wall_roll;
  const double *pair_delta, *wall_delta;
  const std::uint8_t* gathered;
  bool all, rolling;
  // The closing half kick (h = 0: none).
  double h, keep, max_speed;
  Vec gravity;

  // Grain i's force and torque: summed from its contacts' slots for every grain (`all`: the
  // wet pass) or for those the dry pass left (`gathered`); the others get their walls' terms
  // added to the pass's sums. Then, with h > 0, the closing half kick and the guard on the
  // grain's velocities (guards.hpp; its position is checked in the drift): false if it fails.
  [[gnu::always_inline]] bool finish(std::size_t i) const {
    const bool full = all || gathered[i];
    Vec f;
    Rot t;
    if (full || wall_begin[i] != wall_begin[i + 1]) {
      sum(i, full, f, t);
      force[i] = f;
      torque[i] = t;
    } else {
      if (h == 0.0) return true;  // the pass's sum is final
      f = force[i];
      t = torque[i];
    }
    if (h == 0.0) return true;
    if (inv_mass[i] != 0.0)
      half_kick<D>(v[i], w[i], f, t, inv_mass[i], inv_inertia[i], gravity, h, keep);
    return motion_ok<D>(v[i], w[i], max_speed);
  }

  // The sum of grain i's terms (the pass's sum unless `full`, then its walls'). The torque of
  // force F at lever arm -(R - delta/2) n is -(R - delta/2) (n x F) for the first grain; the
  // second grain gets -F at +(R - delta/2) n: the same sign, its own R. A grain's terms are
  // summed in list order: the entries where it is the second member (their first member has
  // a smaller index, so they come first in the list), then those where it is the first, then
  // its walls; the dry pass meets them in that order too, so either way the bits are the
  // same. Rolling resistance: each contact's couple follows its force's torque (+ on the
  // first grain, - on the second).
  [[gnu::always_inline]] void sum(std::size_t i, bool full, Vec& f, Rot& t) const {
    f = full ? S::zero() : force[i];
    t = full ? S::zero_rot() : torque[i];
    const double r = radius[i];
    for (std::uint32_t s = second_begin[i]; full && s < second_begin[i + 1]; ++s) {
      const std::uint32_t k = second_pairs[s];
      f -= pair_force[k];
      t -= (r - 0.5 * pair_delta[k]) * pair_moment[k];
      if (rolling) t -= pair_roll[k];
    }
    for (std::uint32_t m = first_begin[i]; full && m < first_begin[i + 1]; ++m) {
      const std::uint32_t k = near[m];
      f += pair_force[k];
      t -= (r - 0.5 * pair_delta[k]) * pair_moment[k];
      if (rolling) t += pair_roll[k];
    }
    for (std::uint32_t k = wall_begin[i]; k < wall_begin[i + 1]; ++k) {
      f += wall_force[k];
      t -= (r - 0.5 * wall_delta[k]) * wall_moment[k];
      if (rolling) t += wall_roll[k];
    }
  }
};

}  // namespace sable::dem
