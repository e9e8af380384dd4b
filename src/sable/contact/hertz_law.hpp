// The Hertz-Mindlin normal law: Hertz's elastic force with a damping from the restitution
// (Tsuji et al. 1992's form, LIGGGHTS 3.8's coefficients), and Mindlin's tangential
// stiffness. A row of NormalLaws (contact/registry.hpp).
#pragma once

#include <cmath>
#include <numbers>
#include <string_view>

#include "sable/contact/contact_model.hpp"
#include "sable/core/material.hpp"

namespace sable {

struct HertzNormal {
  static constexpr std::string_view kName = "hertz";
  static constexpr std::string_view kSummary =
      "Hertz elastic force with Tsuji-type damping from restitution; LIGGGHTS 3.8 coefficients";
  // The law's stiffness comes from the materials: contact.kn and contact.kt do not apply.
  static constexpr bool kSpringConstants = false;
  static constexpr std::string_view kCriticalTimeName = "the Rayleigh time";

  static NormalCoeffs coeffs(const PairParams& p, const ContactModel&, double delta, double r_eff,
                             double m_eff) {
    const double sqrt_rd = std::sqrt(r_eff * delta);
    constexpr double c = 1.8257418583505538;  // 2 sqrt(5/6)
    // gamma_n = -c beta sqrt(S_n m*) with S_n = 2 Y* sqrt(R* delta); gamma_t is the same with
    // S_t = 8 G* sqrt(R* delta), i.e. gamma_n sqrt(S_t / S_n): one square root for both.
    const double gn = -c * p.beta * std::sqrt(2.0 * p.y_star * sqrt_rd * m_eff);
    return {4.0 / 3.0 * p.y_star * sqrt_rd, gn, 8.0 * p.g_star * sqrt_rd, gn * p.st_over_sn_sqrt};
  }
  // coeffs().kn alone, the secant stiffness F / delta (the rolling sub-model's k_n): the same
  // bits.
  static double stiffness(const PairParams& p, const ContactModel&, double delta, double r_eff) {
    return 4.0 / 3.0 * p.y_star * std::sqrt(r_eff * delta);
  }
  // dF/d(delta), the stiffness a servo wall feels: F = 4/3 Y* sqrt(R) delta^1.5 gives
  // 2 Y* sqrt(R delta), 1.5 times the secant stiffness.
  static double tangent_stiffness(const PairParams& p, const ContactModel& m, double delta,
                                  double r_eff) {
    return 1.5 * stiffness(p, m, delta, r_eff);
  }
  // The Rayleigh time of a grain: the time a shear wave takes to cross it (LIGGGHTS' criterion;
  // Thornton & Randall's fit of the Rayleigh wave speed, 0.1631 nu + 0.8766).
  static double critical_time(const Material& m, double radius, double /*mass*/,
                              const ContactModel&) {
    const double g = m.young / (2.0 * (1.0 + m.poisson));
    return std::numbers::pi * radius * std::sqrt(m.density / g) / (0.1631 * m.poisson + 0.8766);
  }
};

}  // namespace sable
