// The contact model: the normal law (a row of the law table, contact/registry.hpp) composed
// with the tangential, rolling and cohesion sub-models, and the one force kernel they share.
//
// A law is stateless: given the contact geometry, the pair's material parameters and the
// contact's history (the tangential spring), it returns the force on grain i and updates the
// history. The same kernel serves grain-grain and grain-wall contacts: a wall contact simply
// has the grain's own radius and mass as the effective ones, and the wall's velocity in vrel.
// Adding a normal law is one file (a struct like HertzNormal, contact/hertz_law.hpp) and one
// row of NormalLaws (contact/registry.hpp); docs/ARCHITECTURE.md says what the struct holds.
#pragma once

#include <cmath>
#include <string_view>

#include "sable/contact/capillary.hpp"
#include "sable/contact/law_table.hpp"
#include "sable/contact/rolling.hpp"
#include "sable/core/material.hpp"
#include "sable/core/space.hpp"

namespace sable {

enum class TangentialModel : std::uint8_t { kHistory, kNone };

struct ContactModel {
  NormalModel normal;  // a row of the law table (contact/registry.hpp: NormalLaws)
  TangentialModel tangential = TangentialModel::kHistory;
  // When false the total normal force is clipped at zero: a dry contact never pulls. LIGGGHTS
  // lets the dashpot pull at the end of a contact; clipping makes rebounds slightly livelier
  // (nominal e = 0.5 gives about 0.55 with the linear law). See docs/contact-laws.md.
  bool attractive_damping = false;
  // As the contact turns, the tangential spring is brought into the new tangent plane. True:
  // turned with its length kept (the spring follows the contact). False: only projected, so it
  // loses the factor cos(theta) for a turn theta each step, as in LIGGGHTS 3.8's tangential
  // history, which the peer benchmark compares with. DEM only (CD has no spring).
  bool keep_spring_length = true;
  double kn = 0.0;  // linear law only (N/m)
  double kt = 0.0;  // linear law only (N/m)
  // Cohesion, added to the normal force of grain pairs (walls are dry). Capillary bridges
  // (contact/capillary.hpp) are DEM only, in 3D; their volumes live in the pair list.
  CohesionModel cohesion = CohesionModel::kNone;
  CapillaryParams capillary;
  // Rolling resistance (contact/rolling.hpp), with each pair's rolling friction mu_r from its
  // materials. rolling_damping is eta_r, the damping of the elastic regime as a fraction of
  // critical (DEM; contact dynamics has no spring).
  RollingModel rolling = RollingModel::kNone;
  double rolling_damping = 0.3;
};

// Stiffness and damping of one contact at its current overlap. Damping coefficients are
// positive: they multiply minus the relative velocity.
struct NormalCoeffs {
  double kn, gn, kt, gt;
};

template <int D>
struct ContactGeometry {
  using Vec = typename Space<D>::Vec;
  Vec n;         // unit normal, from j (or the wall) towards i
  double delta;  // overlap (> 0 in contact)
  Vec vrel;      // velocity of i's contact point minus j's (or the wall's)
  double r_eff;  // R* (a wall: R_i)
  double m_eff;  // m* (a wall or fixed grain: m_i)
};

// The force on grain i. `shear` is the contact's tangential history (a displacement); it is
// turned into the current tangent plane, advanced by vt*dt and Coulomb-capped. `cohesion`
// (<= 0, N) is added to the normal force; the Coulomb cap uses the repulsive part only: the
// attraction acts through the larger overlap it causes (Richefeu et al. 2009; Scholtes et al.
// 2009 make the same choice).
template <int D, class Normal>
[[gnu::always_inline]] inline typename Space<D>::Vec contact_force(
    const ContactGeometry<D>& g, const PairParams& p, const ContactModel& model, double dt,
    typename Space<D>::Vec& shear, double cohesion = 0.0) {
  using Vec = typename Space<D>::Vec;
  const NormalCoeffs c = Normal::coeffs(p, model, g.delta, g.r_eff, g.m_eff);
  const double vn = g.vrel.dot(g.n);
  double fn = c.kn * g.delta - c.gn * vn;
  if (!model.attractive_damping && fn < 0.0) fn = 0.0;
  Vec force = fn * g.n;
  if (cohesion != 0.0) force += cohesion * g.n;  // a branch keeps dry results bit-identical
  if (model.tangential == TangentialModel::kNone || p.friction == 0.0) {
    shear.setZero();
    return force;
  }
  const Vec vt = g.vrel - vn * g.n;
  // Keep the spring in the tangent plane as the contact rotates, with its length unchanged.
  const double s2 = shear.squaredNorm();
  if (s2 > 0.0) {
    shear -= shear.dot(g.n) * g.n;
    const double s2_new = shear.squaredNorm();
    if (model.keep_spring_length && s2_new > 0.0) shear *= std::sqrt(s2 / s2_new);
  }
  shear += vt * dt;
  const double f_max = p.friction * std::abs(fn);
  const double f_spring2 = c.kt * c.kt * shear.squaredNorm();
  if (f_spring2 > f_max * f_max) {
    // Sliding: the spring is held at the Coulomb limit; no tangential damping.
    shear *= f_max / std::sqrt(f_spring2);
    force -= c.kt * shear;
  } else {
    force -= c.kt * shear + c.gt * vt;
  }
  return force;
}

// The rolling couple on grain i of a touching contact whose force on i is f (contact/rolling.hpp,
// with the normal law's stiffness at this overlap); advances the rolling spring `theta`. A pair
// without rolling friction has no couple and keeps no spring. w_rel = w_i - w_j (a wall does
// not turn: the grain's own spin); inv_ic_i, inv_ic_j: the inverse inertias about the contact
// point (0 for a wall). Grain-grain and grain-wall contacts share it, as they share
// contact_force.
template <int D, class Normal>
[[gnu::always_inline]] inline typename Space<D>::Rot rolling_couple(
    const ContactGeometry<D>& g, const PairParams& p, const ContactModel& model, double dt,
    const typename Space<D>::Vec& f, const typename Space<D>::Rot& w_rel, double inv_ic_i,
    double inv_ic_j, typename Space<D>::Rot& theta) {
  if (p.rolling_friction == 0.0) {
    theta = Space<D>::zero_rot();
    return theta;
  }
  const RollingCoeffs c =
      rolling_coeffs(p.rolling_friction, model.rolling_damping, g.r_eff,
                     Normal::stiffness(p, model, g.delta, g.r_eff), f.dot(g.n), inv_ic_i, inv_ic_j);
  return rolling_moment<D>(g.n, w_rel, c, dt, theta);
}

}  // namespace sable
