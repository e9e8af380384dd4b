// The rolling-resistance law (contact/rolling.hpp), on its own: the EPSD couple of Iwashita &
// Oda / Ai et al. model C in its elastic regime (a damped spring on the accumulated relative
// rolling), at full mobilisation (the couple capped at mu_r R* F_n, the spring held at the cap,
// no damping), in 3D with the twisting part of the spin left out and the spring carried into
// the turned tangent plane with its length, and its coefficients from their definitions. A
// damped couple beyond the cap is capped too (the spring then stays elastic).
//
// Tolerances: the law is a handful of additions and multiplications per call, so a result
// computed here the same way agrees to a few roundings, 2^-53 = 1.1e-16 relative each; 1e-15
// relative (about nine of them) bounds every comparison below unless a comment says otherwise.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "sable/contact/rolling.hpp"

namespace {

using sable::rolling_moment;
using sable::RollingCoeffs;
using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;

constexpr double kRel = 1e-15;  // a few roundings, relative (see the file's comment)

// Coefficients with a cap far above anything the elastic tests reach.
constexpr RollingCoeffs kElastic{/*k_r=*/2.5e-3, /*m_max=*/1.0, /*c_r=*/4.0e-5};

// (a) 2D, elastic: a constant relative spin w for n steps winds the spring to theta = n w dt
// and the couple is the damped spring -k_r theta - c_r w at every step (both terms oppose the
// spin: no cancellation, so the relative tolerance holds for the sum too).
TEST(RollingLaw, ElasticRegimeIsADampedSpring2D) {
  const Vec2 n(0.6, 0.8);  // unused in 2D: the spin is about z, always in the contact plane
  const double w = 37.0, dt = 1.3e-6;
  double theta = 0.0;
  for (int step = 1; step <= 6; ++step) {
    const double m = rolling_moment<2>(n, w, kElastic, dt, theta);
    const double expected_theta = step * w * dt;
    EXPECT_NEAR(theta, expected_theta, kRel * expected_theta) << "step " << step;
    const double expected_m = -kElastic.k_r * expected_theta - kElastic.c_r * w;
    EXPECT_NEAR(m, expected_m, kRel * std::abs(expected_m)) << "step " << step;
  }
  // Still elastic: the spring's couple is far below the cap (so the test above tested the
  // elastic branch, not the capped one).
  EXPECT_LT(kElastic.k_r * std::abs(theta), 1e-3 * kElastic.m_max);
}

// (a) 3D, elastic: the same with a spin in the tangent plane of n = z (no twisting part, and
// a normal along an axis keeps the projection exact), so theta = n w dt componentwise.
TEST(RollingLaw, ElasticRegimeIsADampedSpring3D) {
  const Vec3 n(0.0, 0.0, 1.0);
  const Vec3 w(37.0, -21.0, 0.0);
  const double dt = 1.3e-6;
  Vec3 theta = Vec3::Zero();
  for (int step = 1; step <= 6; ++step) {
    const Vec3 m = rolling_moment<3>(n, w, kElastic, dt, theta);
    const Vec3 expected_theta = (step * dt) * w;
    EXPECT_LE((theta - expected_theta).norm(), kRel * expected_theta.norm()) << "step " << step;
    const Vec3 expected_m = -kElastic.k_r * expected_theta - kElastic.c_r * w;
    EXPECT_LE((m - expected_m).norm(), kRel * expected_m.norm()) << "step " << step;
    EXPECT_EQ(theta.z(), 0.0);  // in the tangent plane, exactly: nothing along z is added
  }
}

// (b) 2D, full mobilisation: k_r = 100, cap 2.5, w dt = 0.01 rad per step, so the spring's
// couple is 1, 2, then would be 3 > 2.5: from the third step on the couple is exactly the cap
// (to round-off) and theta is held at cap / k_r. The damping (0.1 N m) keeps the damped
// couple of the first two steps below the cap. The spin reversed then unloads the spring
// elastically from the cap, not from where it would have been.
TEST(RollingLaw, CappedCoupleHoldsTheSpringAtTheLimit2D) {
  const RollingCoeffs c{/*k_r=*/100.0, /*m_max=*/2.5, /*c_r=*/0.01};
  const double w = 10.0, dt = 1e-3;
  double theta = 0.0;
  double m = rolling_moment<2>(Vec2(1, 0), w, c, dt, theta);
  EXPECT_NEAR(m, -100.0 * 0.01 - 0.01 * w, kRel * 1.1);  // elastic, damped
  m = rolling_moment<2>(Vec2(1, 0), w, c, dt, theta);
  EXPECT_NEAR(m, -100.0 * 0.02 - 0.01 * w, kRel * 2.1);  // still elastic: 2.1 < 2.5
  for (int step = 3; step <= 8; ++step) {
    m = rolling_moment<2>(Vec2(1, 0), w, c, dt, theta);
    // |M| = M_max, opposing the spin (the damping term would make it 2.6).
    EXPECT_NEAR(m, -c.m_max, kRel * c.m_max) << "step " << step;
    EXPECT_NEAR(theta, c.m_max / c.k_r, kRel * c.m_max / c.k_r) << "step " << step;
  }
  // Reversal: theta = 0.025 - 0.01 = 0.015, elastic again, damped by the reversed spin.
  m = rolling_moment<2>(Vec2(1, 0), -w, c, dt, theta);
  EXPECT_NEAR(theta, 0.015, kRel * 0.025);
  EXPECT_NEAR(m, -100.0 * 0.015 + 0.01 * w, kRel * 1.5);
  // And the cap holds the other way round: theta goes 0.005, -0.005, -0.015, -0.025, then is
  // held at -0.025 (the fifth and sixth steps would take it to -0.035).
  for (int step = 0; step < 6; ++step) m = rolling_moment<2>(Vec2(1, 0), -w, c, dt, theta);
  EXPECT_NEAR(m, c.m_max, kRel * c.m_max);
  EXPECT_NEAR(theta, -c.m_max / c.k_r, kRel * c.m_max / c.k_r);
}

// (b) 3D, full mobilisation: the spring is loaded to the cap rolling about x (theta held at
// 0.025 x), then one step rolls about y: theta = (0.025, 0.01, 0) is beyond the cap and is
// scaled back onto it, keeping its direction: |theta| = M_max / k_r and M = -k_r theta, so
// |M| = M_max, antiparallel to the spring, with no damping term: c_r = 0.7 would add 7 N m
// along -y before the cap and turn the couple away from the spring (by ~52 degrees).
TEST(RollingLaw, CappedCoupleHoldsTheSpringAtTheLimit3D) {
  const RollingCoeffs c{/*k_r=*/100.0, /*m_max=*/2.5, /*c_r=*/0.7};
  const Vec3 n(0.0, 0.0, 1.0);
  const double dt = 1e-3;
  Vec3 theta = Vec3::Zero();
  Vec3 m;
  for (int step = 0; step < 5; ++step) m = rolling_moment<3>(n, Vec3(10, 0, 0), c, dt, theta);
  EXPECT_LE((theta - Vec3(0.025, 0, 0)).norm(), kRel * 0.025);
  EXPECT_LE((m - Vec3(-2.5, 0, 0)).norm(), kRel * 2.5);
  m = rolling_moment<3>(n, Vec3(0, 10, 0), c, dt, theta);
  const Vec3 direction = Vec3(0.025, 0.01, 0.0).normalized();
  EXPECT_NEAR(m.norm(), c.m_max, kRel * c.m_max);
  EXPECT_LE((theta - (c.m_max / c.k_r) * direction).norm(), kRel * c.m_max / c.k_r);
  EXPECT_LE((m + c.m_max * direction).norm(), kRel * c.m_max);
}

// Between the two regimes: a spring below the cap whose damped couple exceeds it (a contact
// closing between grains that already roll) gets the damped couple scaled down to M_max,
// in its own direction, and the spring is not touched (it is still elastic). 2D: k_r = 100,
// cap 2.5, c_r w = 7: the couple is -2.5 while theta winds 0.01, 0.02, then theta is held
// at the cap. 3D: a spring (0, 0.01, 0) rolled about x: theta = (0.01, 0.01, 0), the damped
// couple -(1, 1, 0) - (7, 0, 0) = -(8, 1, 0) is scaled to length 2.5.
TEST(RollingLaw, DampedCoupleIsCappedToo) {
  const RollingCoeffs c{/*k_r=*/100.0, /*m_max=*/2.5, /*c_r=*/0.7};
  const double dt = 1e-3;
  double theta = 0.0;
  for (const double expected : {0.01, 0.02, 0.025}) {
    EXPECT_NEAR(rolling_moment<2>(Vec2(1, 0), 10.0, c, dt, theta), -2.5, kRel * 2.5);
    EXPECT_NEAR(theta, expected, kRel * expected);
  }
  Vec3 theta3(0.0, 0.01, 0.0);
  const Vec3 m = rolling_moment<3>(Vec3(0, 0, 1), Vec3(10, 0, 0), c, dt, theta3);
  EXPECT_LE((theta3 - Vec3(0.01, 0.01, 0.0)).norm(), kRel * 0.01);
  EXPECT_LE((m + 2.5 * Vec3(8.0, 1.0, 0.0).normalized()).norm(), kRel * 2.5);
}

// No repulsive normal force, no couple: with M_max = 0 (rolling_coeffs of F_n <= 0) a loaded
// spring is released to zero and the couple is zero, exactly (theta times 0).
TEST(RollingLaw, NoNormalForceNoCouple) {
  const RollingCoeffs c = sable::rolling_coeffs(0.1, 0.3, 1e-3, 1e5, -2.0, 1e6, 1e6);
  EXPECT_EQ(c.m_max, 0.0);
  double theta2 = 0.05;
  EXPECT_EQ(rolling_moment<2>(Vec2(1, 0), 3.0, c, 1e-5, theta2), 0.0);
  EXPECT_EQ(theta2, 0.0);
  Vec3 theta3(0.01, -0.02, 0.0);
  EXPECT_EQ(rolling_moment<3>(Vec3(0, 0, 1), Vec3(1, 2, 3), c, 1e-5, theta3), Vec3::Zero());
  EXPECT_EQ(theta3, Vec3::Zero());
}

// (c) 3D: twisting (spin about n) is not rolling. A pure twist leaves the spring unloaded
// and gives no couple, exactly for n along an axis; with an oblique normal and a spin with
// both parts, the spring winds by the tangential part only and the couple has no component
// along n. Oblique n = (1, 2, 2)/3 is rounded, so w.n n removes the twist to a few roundings
// of |w| ~ 50, not of the tangential part ~ 10: 1e-14 relative to the latter bounds it.
TEST(RollingLaw, TwistingDoesNotLoadTheSpring) {
  Vec3 theta = Vec3::Zero();
  for (int step = 0; step < 5; ++step) {
    const Vec3 m = rolling_moment<3>(Vec3(0, 0, 1), Vec3(0, 0, 40.0), kElastic, 1e-5, theta);
    EXPECT_EQ(m, Vec3::Zero());
  }
  EXPECT_EQ(theta, Vec3::Zero());

  const Vec3 n = Vec3(1.0, 2.0, 2.0) / 3.0;
  const Vec3 tangential = 10.0 * Vec3(2.0, -2.0, 1.0) / 3.0;  // perpendicular to n, |.| = 10
  const Vec3 w = tangential + 45.0 * n;
  const double dt = 1e-5;
  theta = Vec3::Zero();
  Vec3 m;
  for (int step = 0; step < 5; ++step) m = rolling_moment<3>(n, w, kElastic, dt, theta);
  const Vec3 expected_theta = (5 * dt) * tangential;
  EXPECT_LE((theta - expected_theta).norm(), 1e-14 * expected_theta.norm());
  const Vec3 expected_m = -kElastic.k_r * expected_theta - kElastic.c_r * tangential;
  EXPECT_LE((m - expected_m).norm(), 1e-14 * expected_m.norm());
  EXPECT_LE(std::abs(m.dot(n)), 1e-14 * m.norm());
  EXPECT_LE(std::abs(theta.dot(n)), 1e-14 * theta.norm());
}

// (e) 3D: when the contact turns (n from z to (sin a, 0, cos a), a turn by a about y) the
// spring theta0 = (s, 0, 0) is brought into the new tangent plane with its length: it becomes
// s (cos a, 0, -sin a), the spring turned with the contact (not the projection, which would
// shorten it by cos a). No spin this step, so the couple is the spring alone, -k_r theta.
TEST(RollingLaw, SpringKeepsItsLengthWhenTheContactTurns) {
  const double s = 3e-3;
  for (const double a : {1e-3, 0.3, 1.2}) {
    const Vec3 n(std::sin(a), 0.0, std::cos(a));
    Vec3 theta(s, 0.0, 0.0);
    const Vec3 m = rolling_moment<3>(n, Vec3::Zero(), kElastic, 1e-5, theta);
    EXPECT_NEAR(theta.norm(), s, kRel * s) << "turn " << a;
    EXPECT_LE(std::abs(theta.dot(n)), kRel * s) << "turn " << a;
    EXPECT_LE((theta - s * Vec3(std::cos(a), 0.0, -std::sin(a))).norm(), kRel * s) << "turn " << a;
    EXPECT_LE((m + kElastic.k_r * theta).norm(), kRel * kElastic.k_r * s) << "turn " << a;
  }
  // A spring along the new normal (a quarter turn) has no direction left in the tangent
  // plane: it is released (zero, not a division by zero's NaN).
  Vec3 theta(s, 0.0, 0.0);
  const Vec3 m = rolling_moment<3>(Vec3(1, 0, 0), Vec3::Zero(), kElastic, 1e-5, theta);
  EXPECT_EQ(theta, Vec3::Zero());
  EXPECT_EQ(m, Vec3::Zero());
}

// (d) The coefficients against numbers worked by hand from their definitions,
//   k_r = 2.25 k_n mu_r^2 R*^2, c_r = eta_r 2 sqrt(k_r / (1/I_i + 1/I_j)), M_max = mu_r R* F_n:
// mu_r = 0.1, R* = 5e-4 m, k_n = 2e5 N/m: k_r = 2.25 * 2e5 * 0.01 * 2.5e-7 = 1.125e-3 N m/rad;
// inverse inertias about the contact 2e3 and 2.5e3 (sum 4.5e3): sqrt(k_r / 4.5e3) = 5e-4, so
// c_r = 0.3 * 2 * 5e-4 = 3e-4 N m s/rad; F_n = 3 N: M_max = 0.1 * 5e-4 * 3 = 1.5e-4 N m.
// A wall (inverse inertia 0) counts only the grain's; two fixed grains give no damping; a
// tensile normal force no cap. Hand values are decimal: kRel covers their rounding too.
TEST(RollingLaw, CoefficientsFromTheirDefinitions) {
  const RollingCoeffs c = sable::rolling_coeffs(0.1, 0.3, 5e-4, 2e5, 3.0, 2e3, 2.5e3);
  EXPECT_NEAR(c.k_r, 1.125e-3, kRel * 1.125e-3);
  EXPECT_NEAR(c.c_r, 3e-4, kRel * 3e-4);
  EXPECT_NEAR(c.m_max, 1.5e-4, kRel * 1.5e-4);
  // Against a wall: sqrt(1.125e-3 / 4.5e3) unchanged by moving all the inertia to one side.
  const RollingCoeffs wall = sable::rolling_coeffs(0.1, 0.3, 5e-4, 2e5, 3.0, 4.5e3, 0.0);
  EXPECT_NEAR(wall.c_r, 3e-4, kRel * 3e-4);
  // Critical damping (eta_r = 1) is 2 sqrt(k_r I_r): 1e-3 here.
  EXPECT_NEAR(sable::rolling_coeffs(0.1, 1.0, 5e-4, 2e5, 3.0, 2e3, 2.5e3).c_r, 1e-3, kRel * 1e-3);
  const RollingCoeffs fixed = sable::rolling_coeffs(0.1, 0.3, 5e-4, 2e5, 3.0, 0.0, 0.0);
  EXPECT_EQ(fixed.c_r, 0.0);
  EXPECT_NEAR(fixed.k_r, 1.125e-3, kRel * 1.125e-3);
  EXPECT_EQ(sable::rolling_coeffs(0.1, 0.3, 5e-4, 2e5, -3.0, 2e3, 2.5e3).m_max, 0.0);
  // mu_r = 0: no spring, no damping, no couple.
  const RollingCoeffs none = sable::rolling_coeffs(0.0, 0.3, 5e-4, 2e5, 3.0, 2e3, 2.5e3);
  EXPECT_EQ(none.k_r, 0.0);
  EXPECT_EQ(none.c_r, 0.0);
  EXPECT_EQ(none.m_max, 0.0);
}

// The inertia about the contact point, I + m R^2 (parallel axes): for a sphere I = 2/5 m R^2,
// so 1 / (7/5 m R^2); for a disk I = 1/2 m R^2, so 1 / (3/2 m R^2). m = 2e-3 kg, R = 1e-3 m:
// 1 / 2.8e-9 and 1 / 3e-9. A fixed grain (inverse inertia 0) stays 0.
TEST(RollingLaw, InverseInertiaAboutTheContactPoint) {
  const double m = 2e-3, r = 1e-3;
  const double sphere = sable::inverse_inertia_at_contact(1.0 / (0.4 * m * r * r), m, r);
  EXPECT_NEAR(sphere, 1.0 / 2.8e-9, kRel * (1.0 / 2.8e-9));
  const double disk = sable::inverse_inertia_at_contact(1.0 / (0.5 * m * r * r), m, r);
  EXPECT_NEAR(disk, 1.0 / 3e-9, kRel * (1.0 / 3e-9));
  EXPECT_EQ(sable::inverse_inertia_at_contact(0.0, m, r), 0.0);
}

}  // namespace
