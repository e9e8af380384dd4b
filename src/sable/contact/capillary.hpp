// Capillary cohesion of a liquid bridge between two spheres (Richefeu, El Youssoufi, Peyroux &
// Radjai 2009, eq. 1-8), the cohesion sub-model of the contact law.
//
// With gap delta (< 0: overlap), bridge volume V_b, surface tension gamma and contact angle
// theta, the capillary part of the normal force (negative: attractive) is
//   f = -kappa R                      delta < 0
//   f = -kappa R exp(-delta / lambda)  0 <= delta <= delta_max
//   f = 0                             delta > delta_max
// with kappa = 2 pi gamma cos(theta) (eq. 2), R = sqrt(R_i R_j) (eq. 1, the geometric mean the
// Laplace-Young data favour), the rupture distance delta_max = (1 + theta / 2) V_b^(1/3) (eq. 3)
// and the decay length (eq. 8)
//   lambda = c / sqrt(2) * sqrt( (1/R_i + 1/R_j) / max(R_i/R_j, R_j/R_i) * V_b ),  c = 0.9.
// The law is symmetric in i and j. A bridge forms when two grains touch and breaks beyond
// delta_max (hysteresis: none forms at a distance); that bookkeeping belongs to the solver.
// Pure functions: no state, no allocation.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace sable {

// The cohesion sub-model of the contact law (a row of kContactSubModels each).
enum class CohesionModel : std::uint8_t { kNone, kCapillary };

// Where the liquid of a ruptured bridge goes. kGrains: half to each grain's film, from which
// the grains' next new bridges draw (liquid conserved); kLost: it leaves the sample and is
// counted in LiquidState::lost (the balance still closes).
enum class RupturedLiquid : std::uint8_t { kGrains, kLost };

struct CapillaryParams {
  double surface_tension = 0.0728;  // N/m (water at 20 C)
  double contact_angle = 0.0;       // rad (perfectly wetting, as Richefeu et al.)
  double c = 0.9;                   // fitted constant of eq. 6
  RupturedLiquid ruptured = RupturedLiquid::kGrains;
};

struct Capillary {
  static constexpr double kPi = 3.14159265358979323846;

  static double kappa(const CapillaryParams& p) {
    return 2.0 * kPi * p.surface_tension * std::cos(p.contact_angle);
  }
  static double rupture_distance(const CapillaryParams& p, double volume) {
    return (1.0 + 0.5 * p.contact_angle) * std::cbrt(volume);
  }
  // The reduced diameter 4 R_i R_j / (R_i + R_j) (the harmonic mean of the diameters): a
  // pair's share of the liquid is proportional to it (Richefeu et al. 2009, section 2).
  static double reduced_diameter(double ri, double rj) { return 4.0 * ri * rj / (ri + rj); }
  static double decay_length(const CapillaryParams& p, double ri, double rj, double volume) {
    const double ratio = std::max(ri / rj, rj / ri);
    return p.c / std::sqrt(2.0) * std::sqrt((1.0 / ri + 1.0 / rj) / ratio * volume);
  }
  // True while a bridge of `volume` holds at gap `delta` (delta <= delta_max), without the
  // cube root: the test the DEM kernel makes for every bridge at every step.
  static bool holds(const CapillaryParams& p, double volume, double delta) {
    const double g = delta / (1.0 + 0.5 * p.contact_angle);
    return g * g * g <= volume;
  }
  // The capillary normal force (N, <= 0) at gap `delta` for a bridge of `volume` (> 0).
  static double force(const CapillaryParams& p, double ri, double rj, double volume, double delta) {
    const double f0 = -kappa(p) * std::sqrt(ri * rj);
    if (delta < 0.0) return f0;
    if (!holds(p, volume, delta)) return 0.0;
    return f0 * std::exp(-delta / decay_length(p, ri, rj, volume));
  }
};

}  // namespace sable
