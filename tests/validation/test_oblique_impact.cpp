// Oblique impact of a sphere on a rigid plane with Coulomb friction: Chung & Ooi Test 4.
//
// Reference: Y.C. Chung, J.Y. Ooi, Granular Matter 13 (2011) 643-656, Test 4: alumina sphere
// (E = 380 GPa, nu = 0.23, rho = 4000 kg/m^3, R = 2.5 mm) hitting a rigid flat plane at
// |v| = 3.9 m/s, sphere-plane friction mu = 0.092, restitution e = 0.98, various incident
// angles theta from the plane normal.
//
// Rigid-body impulse theory (Maw, Barber & Fawcett 1976, Wear 38:101-114; the "gross sliding"
// branch in Chung & Ooi 2011, Test 4). With v_n = |v| cos(theta), v_t = |v| sin(theta), the
// normal impulse is J_n = m (1 + e_n) v_n. If the contact point slides for the whole impact,
// the tangential impulse is mu J_n, so
//     v_t'   = v_t - mu (1 + e_n) v_n,
//     omega' = (5/2) mu (1 + e_n) v_n / R      (I = 2/5 m R^2),
// and the slip velocity at the end, v_t - (7/2) mu (1 + e_n) v_n, must still be positive:
// gross sliding holds for tan(theta) > (7/2) mu (1 + e_n) = 0.637 (theta > 32.5 deg).
// e_n is the normal restitution MEASURED in the same run, so the check isolates the
// tangential law from the normal damping.
//
// Tolerance 1 %. Known departures from the rigid-body result: (i) the engine applies the
// friction at the middle of the overlap, lever arm R - delta/2 instead of R, which lowers
// omega' by about delta/(2R) weighted by the force, <= 0.2 % here (delta_max/R = 0.37 % at
// 45 deg); (ii) the Mindlin spring starts at zero and sticks for the first step(s) until
// k_t s reaches mu F_n: since k_t s / F_n = 6 (G*/Y*) tan(theta) ~ 1.3 tan(theta) >> mu from
// the first contact instant, this stick phase lasts about one step; (iii) time discretisation
// with dt = t_c/1000, O(1e-4). The measured agreement is better than 0.1 %; 1 % covers these
// with margin while still resolving a 10 % change of mu or of (1 + e_n) by a factor 10 (we
// check the tangential impulse v_t - v_t' as well as v_t', since at grazing incidence the
// impulse is only 5 % of v_t).

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "impact_helpers.hpp"

namespace sable::validation {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kRadius = 2.5e-3;
constexpr double kSpeed = 3.9;
constexpr double kMu = 0.092;
constexpr double kE = 0.98;

struct Rebound {
  double e_n;      // measured normal restitution
  double v_t;      // incident tangential velocity
  double v_n;      // incident normal speed (positive)
  double v_t_out;  // rebound tangential velocity
  double w_out;    // rebound spin about the axis that rolling forward would have (y)
  double max_overlap;
};

Rebound oblique_impact(double theta_deg) {
  const double theta = theta_deg * kPi / 180.0;
  const double v_t = kSpeed * std::sin(theta), v_n = kSpeed * std::cos(theta);
  const Material alumina = make_material("alumina", 4000.0, 3.8e11, 0.23, kE, kMu);
  const Material plane = make_material("rigid-plane", 1.0, 1.0, 0.0, kE, kMu, /*rigid=*/true);
  const double m = 4000.0 * 4.0 / 3.0 * kPi * kRadius * kRadius * kRadius;
  const double y_star = 3.8e11 / (1.0 - 0.23 * 0.23);
  const double dt = hertz_contact_time(m, kRadius, y_star, v_n) / 1000.0;

  World<3> w;
  w.model.normal = NormalLaws::id<HertzNormal>();
  w.model.tangential = TangentialModel::kHistory;
  setup_wall_impact<3>(w, alumina, plane, kRadius, Eigen::Vector3d(v_t, 0.0, -v_n), 5.0 * v_n * dt,
                       dt);
  const ImpactResult r = run_wall_impact(w, 1'000'000);
  EXPECT_TRUE(r.ended);
  return {r.restitution, v_t, v_n, w.particles.v[0].x(), w.particles.omega[0].y(), r.max_overlap};
}

TEST(ObliqueImpact, ChungOoiTest4GrossSlidingMatchesRigidBodyTheory) {
  for (double theta_deg : {45.0, 60.0, 75.0}) {
    const Rebound r = oblique_impact(theta_deg);
    const double limit = 3.5 * kMu * (1.0 + r.e_n);
    ASSERT_GT(std::tan(theta_deg * kPi / 180.0), limit) << "not in gross sliding";
    const double impulse = kMu * (1.0 + r.e_n) * r.v_n;  // tangential impulse / m
    const double v_t_expected = r.v_t - impulse;
    const double w_expected = 2.5 * impulse / kRadius;
    const std::string tag = "theta" + std::to_string(static_cast<int>(theta_deg));
    RecordProperty(tag + "_e_n", num(r.e_n));
    RecordProperty(tag + "_vt_out", num(r.v_t_out));
    RecordProperty(tag + "_vt_expected", num(v_t_expected));
    RecordProperty(tag + "_w_out", num(r.w_out));
    RecordProperty(tag + "_w_expected", num(w_expected));
    EXPECT_NEAR(r.v_t_out, v_t_expected, 0.01 * v_t_expected) << "theta = " << theta_deg;
    // The tangential impulse itself (a small part of v_t at grazing incidence), same 1 %.
    EXPECT_NEAR(r.v_t - r.v_t_out, impulse, 0.01 * impulse) << "theta = " << theta_deg;
    EXPECT_NEAR(r.w_out, w_expected, 0.01 * w_expected) << "theta = " << theta_deg;
    // The normal restitution of the LIGGGHTS Hertz damping, dashpot clipped at zero force
    // (Sable's default): about the clipped value, slightly above 0.98 (see
    // test_restitution.cpp); friction does not feed back on the normal force.
    EXPECT_GT(r.e_n, kE) << "theta = " << theta_deg;
    EXPECT_LT(r.e_n, 1.0) << "theta = " << theta_deg;
  }
}

TEST(ObliqueImpact, StickingRegimeSpinsLessThanSliding) {
  // Below the gross-sliding limit the contact point stops slipping (or reverses) during the
  // impact, so the tangential impulse is below mu J_n: the sphere leaves spinning forward
  // (omega' > 0) but slower than the sliding formula, and keeps more tangential velocity.
  for (double theta_deg : {10.0, 20.0}) {
    const Rebound r = oblique_impact(theta_deg);
    ASSERT_LT(std::tan(theta_deg * kPi / 180.0), 3.5 * kMu * (1.0 + r.e_n));
    const double impulse = kMu * (1.0 + r.e_n) * r.v_n;
    RecordProperty("theta" + std::to_string(static_cast<int>(theta_deg)) + "_w_out", num(r.w_out));
    EXPECT_GT(r.w_out, 0.0) << "theta = " << theta_deg;
    EXPECT_LT(r.w_out, 2.5 * impulse / kRadius) << "theta = " << theta_deg;
    EXPECT_GT(r.v_t_out, r.v_t - impulse) << "theta = " << theta_deg;
  }
}

}  // namespace
}  // namespace sable::validation
