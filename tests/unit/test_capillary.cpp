// The capillary-bridge law of Richefeu et al. (2009), eq. 1-8, against its formula written
// out by hand: several gaps, volumes and size ratios, the overlap branch, the rupture distance,
// and the symmetry in i and j.
#include <gtest/gtest.h>

#include <cmath>

#include "sable/contact/capillary.hpp"

using namespace sable;

namespace {

constexpr double kPi = 3.14159265358979323846;

// Eq. 7-8 written independently of the implementation.
double by_hand(double gamma, double theta, double ri, double rj, double vb, double delta) {
  const double kappa = 2.0 * kPi * gamma * std::cos(theta);
  const double big_r = std::sqrt(ri * rj);
  const double dmax = (1.0 + theta / 2.0) * std::pow(vb, 1.0 / 3.0);
  const double r = std::max(ri / rj, rj / ri);
  const double lambda = 0.9 / std::sqrt(2.0) * std::sqrt((1.0 / ri + 1.0 / rj) / r * vb);
  if (delta < 0.0) return -kappa * big_r;
  if (delta <= dmax) return -kappa * big_r * std::exp(-delta / lambda);
  return 0.0;
}

TEST(Capillary, MatchesTheFormula) {
  CapillaryParams p;
  p.surface_tension = 0.0728;
  for (double theta : {0.0, 0.3}) {
    p.contact_angle = theta;
    for (double vb : {1e-12, 1e-11, 5e-10}) {  // bridge volumes (m^3)
      for (double ratio : {1.0, 1.5, 3.0}) {   // size ratios R_j / R_i
        const double ri = 1e-3, rj = ratio * ri;
        const double dmax = Capillary::rupture_distance(p, vb);
        for (double frac : {-0.01, 0.0, 0.1, 0.5, 0.999, 1.001}) {
          const double delta = frac * dmax;
          const double want = by_hand(p.surface_tension, theta, ri, rj, vb, delta);
          // Same arithmetic in another order: round-off only.
          EXPECT_NEAR(Capillary::force(p, ri, rj, vb, delta), want, 1e-12 * std::abs(want) + 1e-300)
              << "vb " << vb << " ratio " << ratio << " delta/dmax " << frac;
        }
      }
    }
  }
}

TEST(Capillary, OverlapBranchRuptureAndSymmetry) {
  CapillaryParams p;
  const double ri = 1e-3, rj = 2e-3, vb = 1e-11;
  const double f0 = -2.0 * kPi * p.surface_tension * std::sqrt(ri * rj);
  // Overlap: the full adhesion force kappa R, whatever the overlap (eq. 1, 7).
  EXPECT_DOUBLE_EQ(Capillary::force(p, ri, rj, vb, -1e-6), f0);
  EXPECT_DOUBLE_EQ(Capillary::force(p, ri, rj, vb, -1e-4), f0);
  // Continuous at contact, zero beyond the rupture distance (1 + theta/2) V^(1/3) (eq. 3).
  EXPECT_DOUBLE_EQ(Capillary::force(p, ri, rj, vb, 0.0), f0);
  const double dmax = std::cbrt(vb);
  EXPECT_NEAR(Capillary::rupture_distance(p, vb), dmax, 1e-15);
  EXPECT_LT(Capillary::force(p, ri, rj, vb, dmax * (1 - 1e-9)), 0.0);
  EXPECT_EQ(Capillary::force(p, ri, rj, vb, dmax * (1 + 1e-9)), 0.0);
  // Symmetric in i and j (eq. 5 and 8 use max(Ri/Rj, Rj/Ri) and 1/Ri + 1/Rj).
  for (double delta : {-1e-6, 0.0, 1e-6, 1e-5})
    EXPECT_EQ(Capillary::force(p, ri, rj, vb, delta), Capillary::force(p, rj, ri, vb, delta));
  // The force halves over lambda ln 2 (eq. 4).
  const double lambda = Capillary::decay_length(p, ri, rj, vb);
  ASSERT_LT(lambda * std::log(2.0), dmax);
  EXPECT_NEAR(Capillary::force(p, ri, rj, vb, lambda * std::log(2.0)), 0.5 * f0,
              1e-12 * std::abs(f0));
}

}  // namespace
