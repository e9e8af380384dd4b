// Janssen's silo model fitted to wall stresses (Dumont-Fortin-Ouafik 2010 eq. 4): the fit
// recovers K from profiles made by the model itself, exactly without noise and within its
// stated uncertainty with noise.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "sable/analysis/janssen.hpp"
#include "sable/core/error.hpp"

using namespace sable;

namespace {

JanssenInput silo(double k, double noise, std::uint64_t seed) {
  JanssenInput in;
  in.rho_b = 1900.0;
  in.g = 9.81;
  in.area_over_perimeter = 0.0135;  // a 2D silo 27 mm wide
  in.mu_w = 0.25;
  in.height = 0.12;
  std::mt19937_64 rng(seed);
  for (int b = 0; b < 12; ++b) {
    const double z = 0.005 + 0.01 * b;
    // Uniform noise in [-noise, noise] times the saturation stress.
    const double u = static_cast<double>(rng() >> 11) * 0x1.0p-53 * 2.0 - 1.0;
    in.depth.push_back(z);
    in.sigma_xx.push_back(janssen_wall_stress(in, k, z) + u * noise * 1000.0);
  }
  return in;
}

TEST(Janssen, RecoversKFromTheModelsOwnProfile) {
  for (double k : {0.4, 0.8, 1.5}) {
    const JanssenFit f = janssen_fit(silo(k, 0.0, 1));
    EXPECT_NEAR(f.k, k, 1e-6 * k);  // golden section to 1e-12 in log K; round-off in SS
    EXPECT_NEAR(f.r2, 1.0, 1e-9);
    EXPECT_NEAR(f.lambda, 0.0135 / (k * 0.25), 1e-6 * f.lambda);
    // The saturation rho g (A/P) / mu does not depend on K; sigma_zz(H) < rho g H always.
    EXPECT_NEAR(f.saturation, 1900.0 * 9.81 * 0.0135 / 0.25, 1e-9 * f.saturation);
    EXPECT_LT(f.sigma_zz_bottom, f.hydrostatic_bottom);
  }
}

// With 5 % noise (of the saturation stress) the estimate stays within 3 of its standard
// errors over 20 seeds, at least 19 times (a 3-sigma band holds 99.7 % of normal errors; the
// curvature estimate is approximate, so one miss is allowed).
TEST(Janssen, UncertaintyCoversTheTruth) {
  int inside = 0;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    const JanssenFit f = janssen_fit(silo(0.8, 0.05, seed));
    ASSERT_GT(f.k_stderr, 0.0);
    inside += std::abs(f.k - 0.8) < 3.0 * f.k_stderr ? 1 : 0;
  }
  EXPECT_GE(inside, 19);
}

TEST(Janssen, BadInputIsRefused) {
  JanssenInput in = silo(0.8, 0.0, 1);
  in.mu_w = 0.0;
  EXPECT_THROW(janssen_fit(in), InputError);  // frictionless walls: no Janssen effect
  in = silo(0.8, 0.0, 1);
  in.depth.resize(2);
  in.sigma_xx.resize(2);
  EXPECT_THROW(janssen_fit(in), InputError);  // two points cannot test a curve
}

}  // namespace
