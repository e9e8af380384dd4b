// Rolling resistance: the elastic-plastic spring-dashpot (EPSD) model of Iwashita & Oda (1998)
// as specified by Ai, Chen, Rotter & Ooi (2011, Powder Technol. 206:269, "model type C").
//
// A contact resists the relative rolling of its two grains, (w_i - w_j) with its twisting
// component (along n) removed in 3D, by a couple M on grain i and -M on grain j:
//   theta += w_roll dt                  (the rolling spring, kept in the tangent plane)
//   M = -k_r theta - c_r w_roll         while k_r |theta| < M_max (elastic, damped; the sum
//                                       is scaled down to M_max if it exceeds it)
//   M = -M_max theta / |theta|          otherwise (full mobilisation: theta held at the limit)
// with M_max = mu_r R* F_n (F_n the repulsive normal force), k_r = 2.25 k_n mu_r^2 R*^2 (Ai et
// al.'s rolling stiffness, after Iwashita & Oda; k_n = F_n / delta, the secant stiffness for
// Hertz), c_r = eta_r 2 sqrt(I_r k_r) with I_r = 1 / (1/(I_i + m_i R_i^2) + 1/(I_j + m_j R_j^2))
// (each grain's inertia about the contact point). At full mobilisation a grain rolling on
// a floor feels exactly the couple mu_r R F_n against its rolling, the law's defining property
// (tests/validation/test_rolling_resistance.cpp checks the stopping distance and the
// tilt at which a grain starts to roll, tan(alpha) = mu_r).
//
// Contact dynamics uses the law's rigid limit (cd/cd_solver.cpp: |M| <= mu_r R* F_n, M against
// the rolling when the grains roll, anything below the cap when they do not).
//
// Stateless like the other sub-models: the spring `theta` is the contact's history, stored in
// the pair list beside the tangential spring (PairList::roll).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "sable/core/space.hpp"

namespace sable {

enum class RollingModel : std::uint8_t { kNone, kEpsd };

struct RollingCoeffs {
  double k_r;    // N m / rad
  double m_max;  // N m
  double c_r;    // N m s / rad
};

// k_n is the normal stiffness F_n / delta at the current overlap, inv_ic_i, inv_ic_j the
// inverse inertias about the contact point (0 for a wall or a fixed grain).
inline RollingCoeffs rolling_coeffs(double mu_r, double eta_r, double r_eff, double k_n, double f_n,
                                    double inv_ic_i, double inv_ic_j) {
  const double k_r = 2.25 * k_n * mu_r * mu_r * r_eff * r_eff;
  const double inv_sum = inv_ic_i + inv_ic_j;
  const double c_r = inv_sum > 0.0 ? eta_r * 2.0 * std::sqrt(k_r / inv_sum) : 0.0;
  return {k_r, mu_r * r_eff * std::max(f_n, 0.0), c_r};
}

// The inverse inertia of a grain about its contact point, 1 / (I + m R^2), from its inverse
// inertia and mass; 0 for a fixed grain (inv_inertia = 0).
inline double inverse_inertia_at_contact(double inv_inertia, double mass, double radius) {
  return inv_inertia / (1.0 + inv_inertia * mass * radius * radius);
}

// The couple on grain i; updates the spring. n: unit normal (j towards i); w_rel = w_i - w_j.
template <int D>
[[gnu::always_inline]] inline typename Space<D>::Rot rolling_moment(
    const typename Space<D>::Vec& n, const typename Space<D>::Rot& w_rel, const RollingCoeffs& c,
    double dt, typename Space<D>::Rot& theta) {
  using Rot = typename Space<D>::Rot;
  Rot w_roll = w_rel;
  if constexpr (D == 3) {
    // Twisting (spin about n) is not rolling. Keep the spring in the tangent plane as the
    // contact turns, with its length (as the tangential spring with keep_spring_length).
    w_roll -= w_rel.dot(n) * n;
    const double t2 = theta.squaredNorm();
    if (t2 > 0.0) {
      theta -= theta.dot(n) * n;
      const double t2_new = theta.squaredNorm();
      if (t2_new > 0.0) theta *= std::sqrt(t2 / t2_new);
    }
  }
  theta += w_roll * dt;
  const double m_max2 = c.m_max * c.m_max;
  const double spring2 = c.k_r * c.k_r * Space<D>::rot_norm2(theta);
  if (spring2 > m_max2) {
    theta *= c.m_max / std::sqrt(spring2);
    return -c.k_r * theta;
  }
  // The damped couple is capped too (as LAMMPS' rolling "sds" caps spring plus dashpot): a
  // contact that closes between grains already rolling would otherwise feel, for the few
  // steps its spring takes to load, a viscous couple many times mu_r R* F_n.
  const Rot m = -c.k_r * theta - c.c_r * w_roll;
  const double m2 = Space<D>::rot_norm2(m);
  return m2 > m_max2 ? Rot(m * (c.m_max / std::sqrt(m2))) : m;
}

}  // namespace sable
