// Set-up shared by the rolling-resistance validation tests (DEM: test_rolling_resistance.cpp,
// contact dynamics: test_rolling_cd.cpp): one grain on a plane tilted by alpha.
#pragma once

#include <algorithm>
#include <cmath>

#include "impact_helpers.hpp"

namespace sable::validation {

constexpr double kRollingMuR = 0.1;  // the rolling friction of the tests' grain and plane

// One case: the tilt (tan alpha), the grain's rolling friction, a launch speed, a duration.
struct RollingSetup {
  double tan_alpha = 0.0;
  double mu_r_grain = kRollingMuR;  // the plane always has kRollingMuR; the pair the smaller
  double v0 = 0.0;                  // launch speed along +x, with the rolling spin v0 / R
  double duration = 0.5;
  RollingModel rolling = RollingModel::kEpsd;
};

// Below the threshold: tan(alpha) = 0.8 mu_r, where the couple holds the grain.
inline RollingSetup holding_case() {
  RollingSetup s;
  s.tan_alpha = 0.8 * kRollingMuR;
  return s;
}

// Above the threshold: tan(alpha) = 2 mu_r, the grain's rolling friction as given.
inline RollingSetup rolling_case(double mu_r_grain) {
  RollingSetup s;
  s.tan_alpha = 2.0 * kRollingMuR;
  s.mu_r_grain = mu_r_grain;
  return s;
}

// The acceleration of a round grain (I = c m R^2) rolling down that slope with the couple at
// its cap mu_r R N (mu_r the pair's: the smaller of the two): g (sin - mu_r cos) / (1 + c).
template <int D>
double capped_rolling_acceleration(const RollingSetup& s, double g) {
  const double alpha = std::atan(s.tan_alpha);
  const double c = ParticleStore<D>::inertia_factor();
  const double mu_r = std::min(s.mu_r_grain, kRollingMuR);
  return g * (std::sin(alpha) - mu_r * std::cos(alpha)) / (1.0 + c);
}

// A rigid plane through the origin whose normal is the last axis ("up"), with the grain's
// friction and restitution and a rolling friction kRollingMuR; gravity g tilted by alpha
// towards +x; the grain's material with rolling friction `mu_r_grain`. Returns the grain's
// material index.
template <int D>
MaterialIndex add_tilted_plane(World<D>& w, Material grain, double mu_r_grain, double alpha,
                               double g) {
  using Vec = typename Space<D>::Vec;
  grain.rolling_friction = mu_r_grain;
  Material plane =
      make_material("plane", 1.0, 1.0, 0.0, grain.restitution, grain.friction, /*rigid=*/true);
  plane.rolling_friction = kRollingMuR;
  const MaterialIndex mi = w.materials.add(grain);
  const MaterialIndex wi = w.materials.add(plane);
  w.materials.finalize();
  Vec up = Vec::Zero(), along = Vec::Zero();
  up[D - 1] = 1.0;
  along[0] = 1.0;
  w.walls.push_back(make_plane<D>(Vec::Zero(), up, wi));
  w.gravity = g * (std::sin(alpha) * along - std::cos(alpha) * up);
  return mi;
}

// Grain k rolling forward along +x at v0 without slip on that plane: the contact point's
// velocity v + omega x (-R up) vanishes for omega = -v0/R in 2D (about z), +v0/R about y in 3D.
template <int D>
void roll_forward(World<D>& w, std::size_t k, double v0, double radius) {
  using Vec = typename Space<D>::Vec;
  Vec along = Vec::Zero();
  along[0] = 1.0;
  w.particles.v[k] = v0 * along;
  if constexpr (D == 2)
    w.particles.omega[k] = -v0 / radius;
  else
    w.particles.omega[k] = Vec(0.0, v0 / radius, 0.0);
}

}  // namespace sable::validation
