// Elastic normal impact against Hertz theory: Chung & Ooi benchmark Tests 1 and 2.
//
// Reference: Y.C. Chung, J.Y. Ooi, "Benchmark tests for verifying discrete element modelling
// codes at particle impact level", Granular Matter 13 (2011) 643-656, Tests 1 and 2 (Table 2
// for the inputs, the analytic values quoted in the text). The closed-form Hertz solution
// (Johnson 1985, "Contact Mechanics", section 11.4) is recomputed here from the inputs:
//   delta_max = (15 m* v^2 / (16 Y* sqrt(R*)))^(2/5),
//   t_c       = 2.868 (m*^2 / (R* Y*^2 v))^(1/5),
//   F_max     = 4/3 Y* sqrt(R*) delta_max^(3/2),
// with v the approach speed, m* and R* the effective mass and radius, Y* the effective modulus.
//
// Tolerances. The published numbers: 1 % (the benchmark's own acceptance level). The closed
// form: 0.1 %. With dt = t_c / 1000 velocity Verlet's error on a Hertz impact is O((dt/t_c)^2)
// ~ 1e-6 relative; the contact start and end are interpolated linearly between steps (error
// O(dt^2) in time, a few 1e-6 of t_c), and the maxima are sampled at steps (relative error
// (pi dt / t_c)^2 / 8 ~ 1e-6). The 2.868 of the closed form is itself rounded (exact 2.8682,
// 0.007 %), so 0.1 % leaves a wide margin over every known error and still catches any wrong
// coefficient (a factor in Y*, R* or m* moves these values by several %).

#include <gtest/gtest.h>

#include <cmath>

#include "impact_helpers.hpp"

namespace sable::validation {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(HertzImpact, ChungOoiTest1TwoGlassSpheres) {
  // Two glass spheres, E = 48 GPa, nu = 0.2, rho = 2800 kg/m^3, R = 10 mm, +-10 m/s, e = 1,
  // frictionless. Published: t_c = 40.34 us, delta_max = 274.11 um (total overlap),
  // F_max = 10.697 kN.
  const Material glass = make_material("glass", 2800.0, 4.8e10, 0.2, 1.0, 0.0);
  const double r = 0.01, speed = 10.0;
  const double m = 2800.0 * 4.0 / 3.0 * kPi * r * r * r;
  const double m_eff = 0.5 * m, r_eff = 0.5 * r;
  const double y_star = 1.0 / (2.0 * (1.0 - 0.2 * 0.2) / 4.8e10);
  const double v = 2.0 * speed;
  const double tc_hertz = hertz_contact_time(m_eff, r_eff, y_star, v);
  const double dmax_hertz = hertz_max_overlap(m_eff, r_eff, y_star, v);
  const double fmax_hertz = hertz_force(r_eff, y_star, dmax_hertz);

  World<3> w;
  w.model.normal = NormalLaws::id<HertzNormal>();
  w.model.tangential = TangentialModel::kNone;
  const double dt = tc_hertz / 1000.0;
  setup_pair_impact(w, glass, r, speed, 10.0 * v * dt, dt);
  const ImpactResult res = run_pair_impact(w, 100000);
  ASSERT_TRUE(res.touched);
  ASSERT_TRUE(res.ended);

  RecordProperty("contact_time_us", num(res.contact_time * 1e6));
  RecordProperty("max_overlap_um", num(res.max_overlap * 1e6));
  RecordProperty("max_force_kN", num(res.max_force * 1e-3));
  EXPECT_NEAR(res.contact_time, 40.34e-6, 0.01 * 40.34e-6);
  EXPECT_NEAR(res.max_overlap, 274.11e-6, 0.01 * 274.11e-6);
  EXPECT_NEAR(res.max_force, 10.697e3, 0.01 * 10.697e3);
  EXPECT_NEAR(res.contact_time, tc_hertz, 1e-3 * tc_hertz);
  EXPECT_NEAR(res.max_overlap, dmax_hertz, 1e-3 * dmax_hertz);
  EXPECT_NEAR(res.max_force, fmax_hertz, 1e-3 * fmax_hertz);
  // Elastic: the spheres leave at the speed they came (e = 1 up to O(dt^2)).
  EXPECT_NEAR(res.restitution, 1.0, 1e-4);
}

TEST(HertzImpact, ChungOoiTest2AluminiumSphereOnRigidPlane) {
  // Aluminium alloy sphere, E = 70 GPa, nu = 0.3, rho = 2699 kg/m^3, R = 0.1 m, at 0.2 m/s on
  // a rigid plane (no gravity). Published: t_c = 731.66 us, delta_max = 49.717 um,
  // F_max = 11.370 kN.
  const Material al = make_material("al-alloy", 2699.0, 7.0e10, 0.3, 1.0, 0.0);
  const Material rigid = make_material("rigid", 1.0, 1.0, 0.0, 1.0, 0.0, /*rigid=*/true);
  const double r = 0.1, speed = 0.2;
  const double m = 2699.0 * 4.0 / 3.0 * kPi * r * r * r;
  const double y_star = 7.0e10 / (1.0 - 0.3 * 0.3);
  const double tc_hertz = hertz_contact_time(m, r, y_star, speed);
  const double dmax_hertz = hertz_max_overlap(m, r, y_star, speed);
  const double fmax_hertz = hertz_force(r, y_star, dmax_hertz);

  World<3> w;
  w.model.normal = NormalLaws::id<HertzNormal>();
  w.model.tangential = TangentialModel::kNone;
  const double dt = tc_hertz / 1000.0;
  setup_wall_impact<3>(w, al, rigid, r, Eigen::Vector3d(0.0, 0.0, -speed), 10.0 * speed * dt, dt);
  const ImpactResult res = run_wall_impact(w, 100000);
  ASSERT_TRUE(res.touched);
  ASSERT_TRUE(res.ended);

  RecordProperty("contact_time_us", num(res.contact_time * 1e6));
  RecordProperty("max_overlap_um", num(res.max_overlap * 1e6));
  RecordProperty("max_force_kN", num(res.max_force * 1e-3));
  EXPECT_NEAR(res.contact_time, 731.66e-6, 0.01 * 731.66e-6);
  EXPECT_NEAR(res.max_overlap, 49.717e-6, 0.01 * 49.717e-6);
  EXPECT_NEAR(res.max_force, 11.370e3, 0.01 * 11.370e3);
  EXPECT_NEAR(res.contact_time, tc_hertz, 1e-3 * tc_hertz);
  EXPECT_NEAR(res.max_overlap, dmax_hertz, 1e-3 * dmax_hertz);
  EXPECT_NEAR(res.max_force, fmax_hertz, 1e-3 * fmax_hertz);
  EXPECT_NEAR(res.restitution, 1.0, 1e-4);
}

}  // namespace
}  // namespace sable::validation
