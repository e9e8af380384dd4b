// Rolling resistance in contact dynamics (cd/cd_solver.cpp): a rigid disk (2D) and a rigid
// sphere (3D) on a plane, held below the rolling threshold, rolling at the capped couple above
// it, and braked to rest on a flat floor. The DEM counterpart is test_rolling_resistance.cpp.
//
// The law: the rigid limit of the elastic-plastic spring-dashpot couple of Ai, Chen, Rotter &
// Ooi (2011), "Assessment of rolling resistance models in discrete element simulations",
// Powder Technology 206, 269-282 (model type C): no spring, a rolling impulse m per contact
// (the couple times h) with |m| <= mu_r R* r_N (R* = R against a plane, r_N the normal
// impulse) that holds the relative rolling velocity at zero while below the cap and sits at the
// cap, against the rolling, otherwise. It is solved with the contact impulses by NLGS inside
// Moreau-Jean time stepping (Moreau 1988; Jean 1999, "The non-smooth contact dynamics method",
// CMAME 177, 235-257): v(t + h) = v(t) + h g + M^-1 (impulses), x(t + h) = x(t) + h v(t + h).
//
// Theory (rigid-body mechanics): a round body of inertia I = c m R^2 (c = 1/2 disk, 2/5 sphere)
// on a plane inclined at alpha, not slipping (mu = 0.5 is far above the friction any case here
// needs), with a resisting couple M:
// * at rest it needs M = F_t R = m g sin(alpha) R, available up to mu_r R m g cos(alpha): it
//   stays at rest iff tan(alpha) <= mu_r;
// * above that M is at its cap and a = g (sin(alpha) - mu_r cos(alpha)) / (1 + c), omega R = v;
// * on a flat floor the capped couple decelerates it at mu_r g / (1 + c): launched rolling at
//   v0 it stops after s = v0^2 (1 + c) / (2 mu_r g), at t = v0 (1 + c) / (mu_r g), and stays
//   there (a rigid couple stores nothing: no recoil, unlike the DEM spring).
//
// Rigid contact makes each of these exact in the scheme: the constraints hold at the end of
// every step, so the velocity changes by exactly h a per step, and the only errors are the
// NLGS tolerance and round-off. NLGS stops on the natural-map residual of the impulses,
// relative to max(|q|, |r|, |U|) ~ g h here (q: the free local velocity; m g h, the impulse,
// is smaller in these units): the contact velocities are exact to kTol g h each step. The
// rolling impulse is not in that residual, but NLGS solves it last in each sweep, exactly for
// one contact (closed form): the rolling velocity then is zero or the couple at its cap, to
// round-off. Tolerance 1e-12 with at most 1000 sweeps (the holding case, impulse and couple
// coupled through the spin, converges by a factor 1/(1 + c) per sweep: 63 (disk) and 75
// (sphere) sweeps from rest, one to four once warm-started).
//
// Set-up: the plane is y = 0 (2D) or z = 0 (3D), gravity tilted by alpha; R = 1 cm,
// 2500 kg/m^3, the disk 2R thick; mu = 0.5 and mu_r = 0.1 on grain and plane; h = 1e-4 s.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "impact_helpers.hpp"
#include "rolling_helpers.hpp"
#include "sable/cd/cd_solver.hpp"

namespace sable::validation {
namespace {

constexpr double kG = 9.81;
constexpr double kRadius = 0.01;
constexpr double kThickness = 2.0 * kRadius;  // 2D only
constexpr double kDensity = 2500.0;
constexpr double kMu = 0.5;
constexpr double kMuR = kRollingMuR;
constexpr double kDt = 1e-4;
constexpr double kTol = 1e-12;  // NLGS natural-map tolerance
// The end-of-step velocity error each step may leave: kTol times the residual's scale g h.
constexpr double kStepVelocityError = kTol * kG * kDt;

using Setup = RollingSetup;

// The grain's motion along the slope (+x), after every step.
struct Trace {
  std::vector<double> t, x, v, spin_r;  // spin_r: the rolling-forward spin times R
  std::vector<double> couple;           // the couple on the grain against rolling forward (N m)
  std::vector<double> couple_norm;      // its full magnitude (3D: all three components)
  std::vector<double> normal;           // the normal contact force (N)
  int max_sweeps = 0;
  bool all_converged = true;
};

// The spin component that rolls the grain forward along +x on a plane with normal +y (2D) or
// +z (3D): the contact point's velocity v + omega x (-R up) vanishes for omega = -v/R about z
// in 2D, +v/R about y in 3D (core/space.hpp: spin_velocity is omega x r).
double forward(double w) {
  return -w;
}
double forward(const Eigen::Vector3d& w) {
  return w.y();
}
double magnitude(double w) {
  return std::abs(w);
}
double magnitude(const Eigen::Vector3d& w) {
  return w.norm();
}

template <int D>
World<D> make_world(const Setup& s) {
  using Vec = typename Space<D>::Vec;
  const double alpha = std::atan(s.tan_alpha);
  World<D> w;
  w.model.rolling = s.rolling;
  const MaterialIndex mi = add_tilted_plane(w, make_material("grain", kDensity, 0.0, 0.0, 0.0, kMu),
                                            s.mu_r_grain, alpha, kG);
  w.thickness = kThickness;
  Vec up = Vec::Zero();
  up[D - 1] = 1.0;
  w.particles.add(Vec(kRadius * up), kRadius, kDensity, mi, kThickness);  // touching
  roll_forward(w, 0, s.v0, kRadius);
  w.dt = kDt;
  set_domain(w, -0.5, 0.5, 0.2 * kRadius);
  return w;
}

CdSettings settings() {
  CdSettings cs;
  cs.nlgs.tolerance = kTol;
  cs.nlgs.max_iterations = 1000;
  return cs;
}

template <int D>
void record(const World<D>& w, const CdSolver<D>& solver, Trace& tr) {
  const auto& p = w.particles;
  const auto& wl = w.neighbors.wall_pairs;
  tr.t.push_back(w.time);
  tr.x.push_back(p.x[0].x());
  tr.v.push_back(p.v[0].x());
  tr.spin_r.push_back(forward(p.omega[0]) * kRadius);
  double couple = 0.0, couple_norm = 0.0, normal = 0.0;
  for (std::size_t k = 0; k < wl.size(); ++k) {
    normal += wl.force[k][D - 1];
    if (wl.roll.size() == wl.size()) {  // empty without rolling resistance
      couple -= forward(wl.roll[k]);
      couple_norm += magnitude(wl.roll[k]);
    }
  }
  tr.couple.push_back(couple);
  tr.couple_norm.push_back(couple_norm);
  tr.normal.push_back(normal);
  tr.max_sweeps = std::max(tr.max_sweeps, solver.last_solve().iterations);
  tr.all_converged = tr.all_converged && solver.last_solve().converged;
}

template <int D>
Trace simulate(const Setup& s) {
  World<D> w = make_world<D>(s);
  CdSolver<D> solver(w, settings());
  solver.initialize();
  Trace tr;
  const auto steps = static_cast<std::size_t>(std::lround(s.duration / w.dt));
  for (std::size_t k = 0; k < steps; ++k) {
    solver.step();
    record(w, solver, tr);
  }
  return tr;
}

std::string dim_name(int d) {
  return d == 2 ? "disk" : "sphere";
}

double mass(int d) {
  return d == 2 ? ParticleStore<2>::grain_mass(kRadius, kDensity, kThickness)
                : ParticleStore<3>::grain_mass(kRadius, kDensity, kThickness);
}

void record_solver(const std::string& key, const Trace& tr) {
  ::testing::Test::RecordProperty(key + "_max_sweeps", tr.max_sweeps);
  EXPECT_TRUE(tr.all_converged) << key << ": NLGS converged every step";
}

// 1. Hold below the threshold: tan(alpha) = 0.8 mu_r.
//
// Rigid grains have no spring to deflect: the impulse and the couple hold both the contact
// point and the spin at zero from the first step. The end-of-step velocity is the contact
// point's (the spin is exactly zero, see the header), below kTol g h each step, so over the
// run the grain moves by at most T kTol g h (5e-16 m for T = 0.5 s) -- against the
// (1/2) g sin(alpha) / (1 + c) T^2 ~ 0.07 m that free rolling covers.
//
// The couple the solver reports (the lists' roll slot, impulse / h) must be the one statics
// needs, m g sin(alpha) R (the friction force m g sin(alpha) up the slope, at lever arm R,
// balanced), and 0.8 of its cap mu_r R m g cos(alpha). Its tolerance: the velocity residual
// kTol g h corresponds to an impulse error ~ m kTol g h, relative to the couple's impulse
// m g sin(alpha) R h / R: kTol / sin(alpha) ~ 1.3e-11; 1e-9 leaves room for the coupled
// impulse-couple block (its inverse is larger by up to (1 + c) / c = 3) and round-off.
// The normal force is m g cos(alpha) to the same 1e-9, and the grain's net contact torque
// (friction moment plus couple, in p.t) is zero to 1e-9 of the couple.
template <int D>
void check_hold() {
  const std::string dim = dim_name(D);
  const Setup s = holding_case();
  const double alpha = std::atan(s.tan_alpha);
  const double m = mass(D);
  const double c = ParticleStore<D>::inertia_factor();
  const Trace tr = simulate<D>(s);

  const double bound = s.duration * kStepVelocityError;
  const double free_roll = 0.5 * kG * std::sin(alpha) / (1.0 + c) * s.duration * s.duration;
  const double x_max = std::max(std::abs(*std::max_element(tr.x.begin(), tr.x.end())),
                                std::abs(*std::min_element(tr.x.begin(), tr.x.end())));
  const double couple_needed = m * kG * std::sin(alpha) * kRadius;
  const double cap = kMuR * kRadius * m * kG * std::cos(alpha);
  ::testing::Test::RecordProperty(dim + "_hold_x_max", num(x_max));
  ::testing::Test::RecordProperty(dim + "_hold_bound", num(bound));
  ::testing::Test::RecordProperty(dim + "_hold_couple", num(tr.couple.back()));
  ::testing::Test::RecordProperty(dim + "_hold_couple_needed", num(couple_needed));
  ::testing::Test::RecordProperty(dim + "_hold_cap", num(cap));
  ::testing::Test::RecordProperty(dim + "_hold_couple_rel_err",
                                  num(tr.couple.back() / couple_needed - 1.0));
  record_solver(dim + "_hold", tr);
  ASSERT_LT(bound, 1e-12 * free_roll) << "the bound must tell holding from rolling";
  EXPECT_LE(x_max, bound) << dim << ": the couple holds the grain";
  EXPECT_LE(std::abs(tr.v.back()), kStepVelocityError) << dim << ": at rest";
  EXPECT_LE(std::abs(tr.spin_r.back()), kStepVelocityError) << dim << ": not spinning";
  EXPECT_NEAR(tr.couple.back(), couple_needed, 1e-9 * couple_needed) << dim << ": couple";
  EXPECT_NEAR(tr.couple_norm.back(), couple_needed, 1e-9 * couple_needed) << dim;
  EXPECT_LT(tr.couple.back(), 0.81 * cap) << dim << ": below the cap";
  const double n_expected = m * kG * std::cos(alpha);
  EXPECT_NEAR(tr.normal.back(), n_expected, 1e-9 * n_expected) << dim << ": normal force";
}

template <int D>
double net_contact_torque_after_hold() {
  Setup s;
  s.tan_alpha = 0.8 * kMuR;
  World<D> w = make_world<D>(s);
  CdSolver<D> solver(w, settings());
  solver.initialize();
  for (int k = 0; k < 100; ++k) solver.step();
  return magnitude(w.particles.t[0]);
}

// 2. Roll above the threshold: tan(alpha) = 2 mu_r, the couple at its cap mu_r R N.
//
// Each step changes v by exactly h a (rigid contact: the constraints hold at the end of the
// step, from the first one), so v(T) = a T. Each step's velocity error is at most kTol g h,
// relative to the increment a h: kTol g / a ~ 1.5e-11 (capped) or 4e-12 (free); summed over
// the steps the relative error of v(T) / T stays that size. Checked to 1e-9 relative (margin
// for round-off, ~5000 steps of 1e-16). No slip: omega R = v to kTol g h per step (the
// contact point's velocity), checked to 1e-9 of v. The couple sits at its cap mu_r R N, and
// N = m g cos(alpha), both to 1e-9 (exact in the local solve; round-off).
//
// With mu_r = 0 on the grain, the pair's mu_r is min(0, 0.1) = 0: no couple at all (checked
// to 1e-12 of the capped one), free rolling at a = g sin(alpha) / (1 + c).
template <int D>
void check_roll(double mu_r_grain) {
  const std::string dim = dim_name(D) + (mu_r_grain > 0.0 ? "_capped" : "_free");
  const Setup s = rolling_case(mu_r_grain);
  const double alpha = std::atan(s.tan_alpha);
  const double mu_r_pair = std::min(mu_r_grain, kMuR);
  const double a_expected = capped_rolling_acceleration<D>(s, kG);
  const double n_expected = mass(D) * kG * std::cos(alpha);
  const Trace tr = simulate<D>(s);
  const double a = tr.v.back() / tr.t.back();
  ::testing::Test::RecordProperty(dim + "_a", num(a));
  ::testing::Test::RecordProperty(dim + "_a_expected", num(a_expected));
  ::testing::Test::RecordProperty(dim + "_a_rel_err", num(a / a_expected - 1.0));
  ::testing::Test::RecordProperty(dim + "_slip_rel", num(tr.spin_r.back() / tr.v.back() - 1.0));
  ::testing::Test::RecordProperty(dim + "_omegaR_over_v", num(tr.spin_r.back() / tr.v.back()));
  ::testing::Test::RecordProperty(dim + "_couple", num(tr.couple.back()));
  record_solver(dim, tr);
  EXPECT_NEAR(a, a_expected, 1e-9 * a_expected) << dim << " rolling";
  EXPECT_NEAR(tr.spin_r.back(), tr.v.back(), 1e-9 * tr.v.back()) << dim << ": no slip";
  EXPECT_NEAR(tr.normal.back(), n_expected, 1e-9 * n_expected) << dim << ": normal force";
  const double cap = kMuR * kRadius * n_expected;
  if (mu_r_pair > 0.0) {
    EXPECT_NEAR(tr.couple.back(), cap, 1e-9 * cap) << dim << ": couple at its cap";
    EXPECT_NEAR(tr.couple_norm.back(), cap, 1e-9 * cap) << dim << ": against the rolling";
  } else {
    EXPECT_LE(tr.couple_norm.back(), 1e-12 * cap) << dim << ": no couple";
  }
}

// The flat-floor run of Moreau-Jean with a constant deceleration a from v0: v_k = v0 - k a h
// while that is positive, then the step that would reverse the rolling sticks (it needs a
// couple v_k / h (1 + c) m R < the cap), v = 0, and x = h sum_k v_k.
struct DiscreteStop {
  double distance = 0.0;
  double time = 0.0;  // the end of the first step at rest
};

DiscreteStop discrete_stop(double v0, double a, double h) {
  DiscreteStop d;
  for (int k = 1;; ++k) {
    const double v = v0 - k * a * h;
    if (v <= 0.0) {
      d.time = k * h;
      return d;
    }
    d.distance += h * v;
  }
}

// 3. Stopping on a flat floor: launched at v0 = 0.1 m/s with omega0 = v0 / R.
//
// The couple is at its cap mu_r R m g from the first step (no spring to load), so
// v_k = v0 - k a h with a = mu_r g / (1 + c), exactly as the discrete sum above, whose
// distance and stopping time differ from the continuous s = v0^2 / (2 a) and t = v0 / a by
// less than v0 h / 2 + a h^2 / 2 (7e-4 of s) and h. Checked:
// * the deceleration, (v0 - v) / t at t = t_stop / 2, to 1e-9 relative (as test 2);
// * the distance against the discrete sum to 1e-9 relative (per-step velocity errors
//   kTol g h summed over t_stop / h steps and integrated: t_stop^2 kTol g ~ 2e-13 m, 3e-11 of
//   s), and against the continuous s to within v0 h (the scheme's O(h));
// * the step it stops at: the discrete one exactly, within h of t = v0 / a;
// * then it stays: no creep, no rolling back, the couple gone (nothing left to hold: a rigid
//   couple has no spring to unload). Over 0.3 s after the stop it moves by at most
//   0.3 s kTol g h, its velocity and spin stay below kTol g h, the couple below 1e-12 of its
//   cap.
template <int D>
void check_stop() {
  const std::string dim = dim_name(D);
  const double c = ParticleStore<D>::inertia_factor();
  const double v0 = 0.1;
  const double a_expected = kMuR * kG / (1.0 + c);
  const double s_expected = v0 * v0 / (2.0 * a_expected);
  const double t_expected = v0 / a_expected;
  const DiscreteStop ds = discrete_stop(v0, a_expected, kDt);
  Setup s;
  s.v0 = v0;
  s.duration = t_expected + 0.3;
  const Trace tr = simulate<D>(s);

  const auto k_mid = static_cast<std::size_t>(std::lround(0.5 * t_expected / kDt)) - 1;
  const double a = (v0 - tr.v[k_mid]) / tr.t[k_mid];
  std::size_t k_stop = 0;  // the first step at rest
  while (k_stop + 1 < tr.v.size() && tr.v[k_stop] > kStepVelocityError) ++k_stop;
  const double s_end = tr.x.back();
  const double cap = kMuR * kRadius * mass(D) * kG;
  const double creep = std::abs(tr.x.back() - tr.x[k_stop]);
  ::testing::Test::RecordProperty(dim + "_stop_a", num(a));
  ::testing::Test::RecordProperty(dim + "_stop_a_expected", num(a_expected));
  ::testing::Test::RecordProperty(dim + "_stop_s", num(s_end));
  ::testing::Test::RecordProperty(dim + "_stop_s_discrete", num(ds.distance));
  ::testing::Test::RecordProperty(dim + "_stop_a_rel_err", num(a / a_expected - 1.0));
  ::testing::Test::RecordProperty(dim + "_stop_s_rel_err", num(s_end / ds.distance - 1.0));
  ::testing::Test::RecordProperty(dim + "_stop_s_expected", num(s_expected));
  ::testing::Test::RecordProperty(dim + "_stop_t", num(tr.t[k_stop]));
  ::testing::Test::RecordProperty(dim + "_stop_t_expected", num(t_expected));
  ::testing::Test::RecordProperty(dim + "_stop_creep", num(creep));
  record_solver(dim + "_stop", tr);
  EXPECT_NEAR(a, a_expected, 1e-9 * a_expected) << dim << ": deceleration";
  EXPECT_NEAR(tr.couple[k_mid], cap, 1e-9 * cap) << dim << ": couple at its cap";
  EXPECT_NEAR(s_end, ds.distance, 1e-9 * ds.distance) << dim << ": distance (scheme)";
  EXPECT_NEAR(s_end, s_expected, v0 * kDt) << dim << ": stopping distance";
  EXPECT_NEAR(tr.t[k_stop], ds.time, 0.5 * kDt) << dim << ": stopping step";
  EXPECT_NEAR(tr.t[k_stop], t_expected, kDt) << dim << ": stopping time";
  EXPECT_LE(creep, 0.3 * kStepVelocityError) << dim << ": stays at rest";
  EXPECT_LE(std::abs(tr.v.back()), kStepVelocityError) << dim << ": at rest";
  EXPECT_LE(std::abs(tr.spin_r.back()), kStepVelocityError) << dim << ": not spinning";
  EXPECT_LE(tr.couple_norm.back(), 1e-12 * cap) << dim << ": no couple left";
}

TEST(RollingCd, DiskHoldsBelowThreshold) {
  check_hold<2>();
  EXPECT_LT(net_contact_torque_after_hold<2>(), 1e-9 * mass(2) * kG * kRadius);
}
TEST(RollingCd, SphereHoldsBelowThreshold) {
  check_hold<3>();
  EXPECT_LT(net_contact_torque_after_hold<3>(), 1e-9 * mass(3) * kG * kRadius);
}
TEST(RollingCd, DiskRollsAboveThresholdAtCappedCouple) {
  check_roll<2>(kMuR);
}
TEST(RollingCd, SphereRollsAboveThresholdAtCappedCouple) {
  check_roll<3>(kMuR);
}
TEST(RollingCd, DiskRollsFreelyWithoutGrainRollingFriction) {
  check_roll<2>(0.0);
}
TEST(RollingCd, SphereRollsFreelyWithoutGrainRollingFriction) {
  check_roll<3>(0.0);
}
TEST(RollingCd, DiskStopsOnFlatFloor) {
  check_stop<2>();
}
TEST(RollingCd, SphereStopsOnFlatFloor) {
  check_stop<3>();
}

}  // namespace
}  // namespace sable::validation
