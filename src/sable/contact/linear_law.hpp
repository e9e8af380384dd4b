// The linear spring-dashpot law: constant stiffnesses contact.kn and contact.kt, each with a
// damping from the restitution that gives the material's restitution exactly for a normal
// collision (Cundall & Strack's spring with the classic critical-fraction dashpot). A row of
// NormalLaws (contact/registry.hpp).
#pragma once

#include <algorithm>
#include <cmath>
#include <string_view>

#include "sable/contact/contact_model.hpp"
#include "sable/core/material.hpp"

namespace sable {

struct LinearNormal {
  static constexpr std::string_view kName = "linear";
  static constexpr std::string_view kSummary =
      "linear spring-dashpot, kn and kt given, damping from restitution (exact for e)";
  // The scenario gives contact.kn (and contact.kt unless tangential = "none").
  static constexpr bool kSpringConstants = true;
  static constexpr std::string_view kCriticalTimeName = "sqrt(m / 2k)";

  static NormalCoeffs coeffs(const PairParams& p, const ContactModel& m, double, double,
                             double m_eff) {
    return {m.kn, -2.0 * p.beta * std::sqrt(m.kn * m_eff), m.kt,
            -2.0 * p.beta * std::sqrt(m.kt * m_eff)};
  }
  static double stiffness(const PairParams&, const ContactModel& m, double, double) { return m.kn; }
  static double tangent_stiffness(const PairParams& p, const ContactModel& m, double delta,
                                  double r_eff) {
    return stiffness(p, m, delta, r_eff);
  }
  // 1/omega of the stiffer of the two springs acting on a pair of this grain (m* = m / 2).
  static double critical_time(const Material&, double, double mass, const ContactModel& model) {
    return std::sqrt(0.5 * mass / std::max(model.kn, model.kt));
  }
};

}  // namespace sable
