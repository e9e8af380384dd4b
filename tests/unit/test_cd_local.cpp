// Contact dynamics, numerical core: projection on the Coulomb cone, natural map, the two local
// (one-contact) solvers and the NLGS loop on small explicit problems.
//
// Tolerances: constructed problems have O(1) data, so results are compared to 1e-12 relative
// (the local solvers stop at ~1e-14; the margin covers round-off growing with cond(W) <= 100).
#include <gtest/gtest.h>

#include <Eigen/QR>
#include <array>
#include <cmath>
#include <complex>
#include <cstring>
#include <iostream>
#include <vector>

#include "sable/cd/fc_enumerate.hpp"
#include "sable/cd/fc_problem.hpp"
#include "sable/cd/nlgs.hpp"

namespace {

using sable::Rng;
using namespace sable::cd;

template <int d>
double tnorm(const LVec<d>& x) {
  return x.template tail<d - 1>().norm();
}

template <int d>
LVec<d> random_vec(Rng& rng, double lo = -1.0, double hi = 1.0) {
  LVec<d> v;
  for (int i = 0; i < d; ++i) v[i] = rng.uniform(lo, hi);
  return v;
}

// A random point of K_mu.
template <int d>
LVec<d> random_in_cone(Rng& rng, double mu) {
  LVec<d> y = random_vec<d>(rng);
  y[0] = rng.uniform(0.0, 2.0);
  const double t = tnorm<d>(y);
  if (t > 0.0) y.template tail<d - 1>() *= rng.uniform(0.0, 1.0) * mu * y[0] / t;
  return y;
}

// A random SPD block with eigenvalues in [1, cond].
template <int d>
LMat<d> random_spd(Rng& rng, double cond) {
  LMat<d> A;
  for (int i = 0; i < d; ++i)
    for (int j = 0; j < d; ++j) A(i, j) = rng.uniform(-1.0, 1.0);
  const LMat<d> Q = Eigen::HouseholderQR<LMat<d>>(A).householderQ();
  LVec<d> ev;
  for (int i = 0; i < d; ++i) ev[i] = std::exp(rng.uniform(0.0, std::log(cond)));
  const LMat<d> W = Q * ev.asDiagonal() * Q.transpose();
  return 0.5 * (W + W.transpose());
}

// The law checked directly (not through natural_map): r in K, U~ = U + mu|U_T| e_N in K*,
// r . U~ = 0, all to `tol` relative to the size of the data.
template <int d>
void expect_law(const LVec<d>& r, const LVec<d>& U, double mu, double tol) {
  const double scale = std::max({r.norm(), U.norm(), 1e-300});
  LVec<d> ut = U;
  ut[0] += mu * tnorm<d>(U);
  EXPECT_LE(tnorm<d>(r) - mu * r[0], tol * scale) << "r outside the cone";
  EXPECT_GE(r[0], -tol * scale);
  EXPECT_LE(mu * tnorm<d>(ut) - ut[0], tol * scale) << "U~ outside the dual cone";
  EXPECT_LE(std::abs(r.dot(ut)), tol * scale * scale) << "no complementarity";
}

template <int d>
double local_error(const LMat<d>& W, const LVec<d>& q, double mu, const LVec<d>& r) {
  const LVec<d> U = W * r + q;
  return natural_map<d>(r, U, mu).norm() / std::max({q.norm(), r.norm(), U.norm()});
}

// --- projection ---------------------------------------------------------------------------

// The three cases on hand-made points, exact to round-off (1e-15).
TEST(CdCone, ThreeCases) {
  const double mu = 0.5;
  const LVec<3> inside(2.0, 0.3, -0.4);  // |x_T| = 0.5 <= 1
  EXPECT_EQ(project_cone<3>(inside, mu), inside);
  const LVec<3> polar(-2.0, 0.6, 0.8);  // mu |x_T| = 0.5 <= 2
  EXPECT_EQ(project_cone<3>(polar, mu), LVec<3>::Zero());
  // Boundary: x = (0, 1, 0) -> s = (0 + 0.5)/(1.25) = 0.4, p = (0.4, 0.2, 0).
  const LVec<3> p = project_cone<3>(LVec<3>(0.0, 1.0, 0.0), mu);
  EXPECT_NEAR((p - LVec<3>(0.4, 0.2, 0.0)).norm(), 0.0, 1e-15);
  // 2D, frictionless: T dropped, N clipped.
  EXPECT_EQ(project_cone<2>(LVec<2>(-1.0, 3.0), 0.0), LVec<2>::Zero());
  EXPECT_EQ(project_cone<2>(LVec<2>(2.0, 3.0), 0.0), LVec<2>(2.0, 0.0));
  EXPECT_EQ(project_cone<3>(LVec<3>(1.0, 0.0, 0.0), 0.0), LVec<3>(1.0, 0.0, 0.0));
}

// Random points: P x in K, P P x = P x, and the variational characterisation of a Euclidean
// projection on a convex set, (x - Px).(y - Px) <= 0 for every y in K (round-off: 1e-13).
template <int d>
void projection_properties() {
  Rng rng(11 + d);
  for (int t = 0; t < 2000; ++t) {
    const double mu = t % 10 == 0 ? 0.0 : rng.uniform(0.05, 2.0);
    const LVec<d> x = random_vec<d>(rng, -3.0, 3.0);
    const LVec<d> p = project_cone<d>(x, mu);
    const double s = x.norm();
    EXPECT_LE(tnorm<d>(p), mu * p[0] + 1e-14 * s);
    EXPECT_LE((project_cone<d>(p, mu) - p).norm(), 1e-14 * s);
    EXPECT_LE(std::abs((x - p).dot(p)), 1e-13 * s * s);  // cone: x - Px orthogonal to Px
    for (int k = 0; k < 5; ++k) {
      const LVec<d> y = random_in_cone<d>(rng, mu);
      EXPECT_LE((x - p).dot(y - p), 1e-13 * s * (s + y.norm()));
    }
  }
}
TEST(CdCone, Properties2D) {
  projection_properties<2>();
}
TEST(CdCone, Properties3D) {
  projection_properties<3>();
}

// The natural map vanishes on the three kinds of solutions and not elsewhere.
TEST(CdCone, NaturalMap) {
  const double mu = 0.4;
  EXPECT_EQ(natural_map<3>(LVec<3>::Zero(), LVec<3>(1.0, 2.0, 0.0), mu).norm(), 0.0);  // free
  EXPECT_EQ(natural_map<3>(LVec<3>(1.0, 0.2, 0.0), LVec<3>::Zero(), mu).norm(), 0.0);  // stick
  // slide: r on the boundary opposite to U_T, U_N = 0.
  EXPECT_LE(natural_map<3>(LVec<3>(1.0, -0.24, -0.32), LVec<3>(0.0, 3.0, 4.0), mu).norm(), 1e-16);
  EXPECT_GT(natural_map<3>(LVec<3>(1.0, 0.24, 0.32), LVec<3>(0.0, 3.0, 4.0), mu).norm(), 0.1);
  EXPECT_GT(natural_map<3>(LVec<3>(1.0, 0.0, 0.0), LVec<3>(0.5, 0.0, 0.0), mu).norm(), 0.1);
}

// --- local solvers -------------------------------------------------------------------------

template <int d>
struct Case {
  LMat<d> W;
  LVec<d> q;
  double mu;
  LVec<d> r;  // the known solution
};

// W = I: take-off, stick and slide solved by hand.
template <int d>
std::vector<Case<d>> identity_cases() {
  const LMat<d> I = LMat<d>::Identity();
  LVec<d> q_free = LVec<d>::Constant(0.3), q_stick = LVec<d>::Constant(0.1);
  q_stick[0] = -1.0;  // r = -q = (1, -0.1, ...), |r_T| <= 0.5
  LVec<d> q_slide = LVec<d>::Zero(), r_slide = LVec<d>::Zero();
  q_slide[0] = -1.0;  // r_N = 1; |q_T| = 2 > mu: r_T = -mu q_T/|q_T|, U_T = (|q_T| - mu) e
  q_slide[1] = 2.0;
  r_slide[0] = 1.0;
  r_slide[1] = -0.5;
  if constexpr (d == 3) {
    q_slide << -1.0, 1.2, -1.6;
    r_slide << 1.0, -0.3, 0.4;
  }
  LVec<d> r_stick = -q_stick;
  return {
      {I, q_free, 0.5, LVec<d>::Zero()}, {I, q_stick, 0.5, r_stick}, {I, q_slide, 0.5, r_slide}};
}

// Random SPD W (cond <= 10, moderate mu: the solution is unique), q built from a chosen
// solution of each kind: take-off (q_N > 0), stick (q = -W r, r inside K), slide (r on the
// boundary, U = (0, lambda e), q = U - W r).
template <int d>
std::vector<Case<d>> random_cases(Rng& rng, int n) {
  std::vector<Case<d>> out;
  for (int k = 0; k < n; ++k) {
    const LMat<d> W = random_spd<d>(rng, 10.0);
    const double mu = rng.uniform(0.1, 0.6);
    LVec<d> q = random_vec<d>(rng);
    q[0] = rng.uniform(0.1, 1.0);
    out.push_back({W, q, mu, LVec<d>::Zero()});
    LVec<d> r = random_in_cone<d>(rng, mu);
    r[0] += 0.1;
    out.push_back({W, -W * r, mu, r});
    LVec<d> e = random_vec<d>(rng);
    e[0] = 0.0;
    e.normalize();
    r = -mu * e;
    r[0] = 1.0;
    r *= rng.uniform(0.5, 2.0);
    out.push_back({W, rng.uniform(0.1, 2.0) * e - W * r, mu, r});
  }
  return out;
}

template <int d>
void check_cases(const std::vector<Case<d>>& cases) {
  for (const auto& c : cases) {
    for (const auto kind : {LocalSolver::kBipotential, LocalSolver::kExact}) {
      SCOPED_TRACE(testing::Message() << to_string(kind) << " d=" << d << " q=" << c.q.transpose());
      const LVec<d> r = solve_local<d>(c.W, c.q, c.mu, LVec<d>::Zero(), kind);
      const double scale = std::max(1.0, c.r.norm());
      EXPECT_LE((r - c.r).norm(), 1e-12 * scale);
      EXPECT_LE(local_error<d>(c.W, c.q, c.mu, r), 1e-12);
      expect_law<d>(r, c.W * r + c.q, c.mu, 1e-12);
      // A warm start elsewhere gives the same answer.
      const LVec<d> r2 = solve_local<d>(c.W, c.q, c.mu, LVec<d>::Constant(0.7), kind);
      EXPECT_LE((r2 - c.r).norm(), 1e-12 * scale);
    }
  }
}

// Known answers with W = I (exact to 1e-12 for both local solvers).
TEST(CdLocal, IdentityCases2D) {
  check_cases<2>(identity_cases<2>());
}
TEST(CdLocal, IdentityCases3D) {
  check_cases<3>(identity_cases<3>());
}

// Known answers on random SPD blocks, 100 of each kind per dimension.
TEST(CdLocal, RandomKnownSolutions2D) {
  Rng rng(5);
  check_cases<2>(random_cases<2>(rng, 100));
}
TEST(CdLocal, RandomKnownSolutions3D) {
  Rng rng(6);
  check_cases<3>(random_cases<3>(rng, 100));
}

// W_TT >> W_NN (W = diag(1, 1000, 1000)): rho = 1/W_NN would diverge on the tangential part and
// rho = 1/lambda_max crawl on the normal one; the scaled bi-potential (see local_solvers.cpp)
// reaches the law to 1e-12 in stick and in slide (~2400 iterations there, within the cap), and
// agrees with the exact solver.
template <int d>
void stiff_tangent() {
  LMat<d> W = LMat<d>::Identity() * 1000.0;
  W(0, 0) = 1.0;
  LVec<d> q_stick = LVec<d>::Constant(10.0), q_slide = LVec<d>::Constant(500.0);
  q_stick[0] = q_slide[0] = -1.0;  // r_N = 1; stick: |r_T| = 0.01 sqrt(d-1) <= mu = 0.3
  for (const LVec<d>& q : {q_stick, q_slide}) {
    const LVec<d> rb = solve_local<d>(W, q, 0.3, LVec<d>::Zero(), LocalSolver::kBipotential);
    const LVec<d> re = solve_local<d>(W, q, 0.3, LVec<d>::Zero(), LocalSolver::kExact);
    EXPECT_LE(local_error<d>(W, q, 0.3, rb), 1e-12);
    EXPECT_LE(local_error<d>(W, q, 0.3, re), 1e-12);
    // Relative to the data: the local stopping test is relative to max(|q|, |r|, |U|).
    EXPECT_LE((rb - re).norm(), 1e-12 * std::max(q.norm(), re.norm()));
    EXPECT_NEAR(re[0], 1.0, 1e-12);
  }
}
TEST(CdLocal, StiffTangent2D) {
  stiff_tangent<2>();
}
TEST(CdLocal, StiffTangent3D) {
  stiff_tangent<3>();
}

// Frictionless contact (mu = 0): r_T = 0, U_N = 0 when pressed (1e-14).
TEST(CdLocal, Frictionless) {
  Rng rng(9);
  const LMat<3> W = random_spd<3>(rng, 5.0);
  const LVec<3> q(-1.0, 0.5, 0.2);
  for (const auto kind : {LocalSolver::kBipotential, LocalSolver::kExact}) {
    const LVec<3> r = solve_local<3>(W, q, 0.0, LVec<3>::Zero(), kind);
    EXPECT_NEAR(r[1], 0.0, 1e-14);
    EXPECT_NEAR(r[2], 0.0, 1e-14);
    EXPECT_NEAR((W * r + q)[0], 0.0, 1e-13);
  }
}

// The exact solver on random blocks (cond(W) up to 1000, mu up to 1.5, where the bi-potential
// may cycle and the problem may have several solutions): always satisfies the law. 1e-11: the
// round-off of the stick solve grows with cond(W).
template <int d>
void exact_random() {
  Rng rng(100 + d);
  for (int t = 0; t < 3000; ++t) {
    const LMat<d> W = random_spd<d>(rng, 1000.0);
    const LVec<d> q = random_vec<d>(rng);
    const double mu = rng.uniform(0.0, 1.5);
    const LVec<d> r = solve_local<d>(W, q, mu, LVec<d>::Zero(), LocalSolver::kExact);
    ASSERT_LE(local_error<d>(W, q, mu, r), 1e-11) << "W=\n" << W << "\nq=" << q.transpose();
  }
}
TEST(CdLocal, ExactAlwaysSolves2D) {
  exact_random<2>();
}
TEST(CdLocal, ExactAlwaysSolves3D) {
  exact_random<3>();
}

// The closed-form quartic of the exact solver's sliding directions, on quartics built from
// known roots: four real, two real and a complex pair, two pairs, and coefficients spread over
// 1e-3..1e3. Every root found to 1e-9 relative (simple roots: Ferrari then Newton reaches
// ~1e-14; 1e-9 leaves room for the spread in size), conjugate pairs returned as pairs.
TEST(CdLocal, QuarticRootsFromKnownRoots) {
  using C = std::complex<double>;
  Rng rng(44);
  for (int t = 0; t < 3000; ++t) {
    std::array<C, 4> roots{};
    const double scale = std::pow(10.0, rng.uniform(-3.0, 3.0));
    for (C& z : roots) z = scale * rng.uniform(-2.0, 2.0);
    if (t % 3 >= 1) {  // a complex pair
      roots[2] = C(roots[2].real(), scale * rng.uniform(0.1, 2.0));
      roots[3] = std::conj(roots[2]);
    }
    if (t % 3 == 2) {  // a second pair
      roots[0] = C(roots[0].real(), scale * rng.uniform(0.1, 2.0));
      roots[1] = std::conj(roots[0]);
    }
    // A well-separated set only: a near-double root is found to ~sqrt(eps) at best.
    bool separated = true;
    for (std::size_t i = 0; i < 4; ++i)
      for (std::size_t j = i + 1; j < 4; ++j)
        separated = separated && std::abs(roots[i] - roots[j]) > 0.05 * scale;
    if (!separated) continue;
    // c(u) = c4 prod (u - z_i), c4 random in sign and size.
    std::array<C, 5> c{C(rng.uniform(0.5, 2.0) * (t % 2 ? -1.0 : 1.0))};  // c[k]: u^(4-k)
    for (std::size_t i = 0; i < 4; ++i) {
      for (std::size_t k = i + 1; k >= 1; --k) c[k] -= roots[i] * c[k - 1];
    }
    const std::array<C, 4> found =
        quartic_roots(c[0].real(), c[1].real(), c[2].real(), c[3].real(), c[4].real());
    for (const C& z : roots) {
      double best = 1e300;
      for (const C& f : found) best = std::min(best, std::abs(f - z));
      ASSERT_LE(best, 1e-9 * scale) << "t = " << t << ", root " << z;
    }
  }
}

// The enumeration of fc_enumerate.hpp on random 2-contact 2D problems: W symmetric positive
// definite (eigenvalues in [1, 100]), q random, mu in [0, 1]. A solution exists for any mu with
// such a W (Klarbring & Pang 1998), so one of the 16 combinations holds: the enumeration must
// succeed every time, to Siconos' error 1e-12 (the round-off of a 4 x 4 solve is ~1e-14 here).
// A 3-contact problem is beyond it: false, reactions left at zero.
TEST(CdLocal, EnumerationSolvesEveryTwoContactProblem) {
  Rng rng(45);
  for (int t = 0; t < 500; ++t) {
    const LMat<4> W = random_spd<4>(rng, 100.0);
    std::vector<LMat<2>> blocks;
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b) blocks.push_back(W.block<2, 2>(2 * a, 2 * b));
    const std::vector<LVec<2>> q{LVec<2>(rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0)),
                                 LVec<2>(rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0))};
    MatrixProblem<2> p({0, 2, 4}, {0, 1, 0, 1}, blocks, q,
                       {rng.uniform(0.0, 1.0), rng.uniform(0.0, 1.0)});
    ASSERT_TRUE(solve_enumeration_2d(p, 1e-12)) << "t = " << t;
    EXPECT_LE(fc_residual<2>(p), 1e-12);
  }
  std::vector<LMat<2>> diag(3, LMat<2>::Identity());
  MatrixProblem<2> three({0, 1, 2, 3}, {0, 1, 2}, diag,
                         {LVec<2>(-1.0, 0.0), LVec<2>(-1.0, 0.0), LVec<2>(-1.0, 0.0)},
                         {0.5, 0.5, 0.5});
  EXPECT_FALSE(solve_enumeration_2d(three, 1e-12));
  for (const LVec<2>& r : three.reactions()) EXPECT_EQ(r, LVec<2>::Zero());
}

// --- NLGS on small explicit problems ---------------------------------------------------------

// A dense d-dimensional test problem (the NlgsProblem concept with a full W).
template <int d>
struct DenseProblem {
  Eigen::MatrixXd Wf;
  Eigen::VectorXd qf, rf;
  std::vector<double> mus;
  std::vector<LMat<d>> diag;

  std::size_t size() const { return mus.size(); }
  const LMat<d>& W(std::size_t a) const { return diag[a]; }
  double mu(std::size_t a) const { return mus[a]; }
  Eigen::Map<LVec<d>> r(std::size_t a) { return Eigen::Map<LVec<d>>(rf.data() + d * a); }
  LVec<d> velocity(std::size_t a) const {
    return Wf.middleRows(d * static_cast<Eigen::Index>(a), d) * rf + qf.template segment<d>(d * a);
  }
  void apply(std::size_t a, const LVec<d>& dr) { rf.template segment<d>(d * a) += dr; }
  double q_norm() const { return qf.norm(); }
};

// n contacts, W = J J^T + 0.1 I (SPD, coupled), q_N < 0 for most contacts.
template <int d>
DenseProblem<d> coupled_problem(int n, std::uint64_t seed) {
  Rng rng(seed);
  const int m = d * n;
  Eigen::MatrixXd J(m, m);
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) J(i, j) = rng.uniform(-1.0, 1.0) / std::sqrt(m);
  DenseProblem<d> p;
  p.Wf = J * J.transpose() + 0.1 * Eigen::MatrixXd::Identity(m, m);
  p.qf = Eigen::VectorXd(m);
  for (int i = 0; i < m; ++i) p.qf[i] = rng.uniform(-1.0, 1.0) - (i % d == 0 ? 0.5 : 0.0);
  p.rf = Eigen::VectorXd::Zero(m);
  for (int a = 0; a < n; ++a) {
    p.mus.push_back(0.3);
    p.diag.push_back(p.Wf.template block<d, d>(d * a, d * a));
  }
  return p;
}

// NLGS converges (natural criterion, 1e-10) with every order and both local solvers, and the
// reported residual is the natural-map error recomputed afterwards.
template <int d>
void nlgs_converges() {
  for (const auto kind : {LocalSolver::kBipotential, LocalSolver::kExact}) {
    for (const auto order :
         {SweepOrder::kForward, SweepOrder::kAlternating, SweepOrder::kShuffled}) {
      SCOPED_TRACE(testing::Message() << to_string(kind) << ' ' << to_string(order) << " d=" << d);
      auto p = coupled_problem<d>(8, 3);
      NlgsSettings s;
      s.local = kind;
      s.order = order;
      s.tolerance = 1e-10;
      s.max_iterations = 2000;
      Rng rng(1);
      const NlgsResult res = solve_nlgs<d>(p, s, rng);
      EXPECT_TRUE(res.converged);
      EXPECT_LE(res.error, 1e-10);
      EXPECT_EQ(res.residual, natural_map_error<d>(p));
      EXPECT_GT(res.iterations, 1);
    }
  }
}
TEST(CdNlgs, Converges2D) {
  nlgs_converges<2>();
}
TEST(CdNlgs, Converges3D) {
  nlgs_converges<3>();
}

// The spaced checks' schedule: every sweep up to 20, then gaps of sweeps / 20 (so a solve
// stops at most 5 % of its sweeps after the first that met the tolerance), at most 25.
TEST(CdNlgs, SpacedChecksScheduleBoundsTheOvershoot) {
  int last = 0, checks = 0;
  for (int k = 1; k <= 5000; ++k) {
    if (!residual_due(k)) continue;
    ++checks;
    const int gap = k - last;
    EXPECT_LE(gap, std::max(1, k / 20)) << "check at " << k;
    EXPECT_LE(gap, 25) << "check at " << k;
    last = k;
  }
  for (int k = 1; k <= 20; ++k) EXPECT_TRUE(residual_due(k)) << k;
  // 2,000 sweeps (a capped silo step) take 164 checks instead of 2,000: under a tenth.
  checks = 0;
  for (int k = 1; k <= 2000; ++k) checks += residual_due(k) ? 1 : 0;
  EXPECT_LT(checks, 200);
}

// Spaced checks stop at a check at or after the sweep where every-sweep checks stop, at most
// 5 % of the sweeps later, converged to the same tolerance, with the same iterates up to
// there (the checks change nothing but when the loop stops).
TEST(CdNlgs, SpacedChecksStopAtTheFirstDueCheckPastConvergence) {
  for (const double tol : {1e-6, 1e-10}) {
    auto every = coupled_problem<3>(12, 5), spaced = coupled_problem<3>(12, 5);
    NlgsSettings s;
    s.tolerance = tol;
    s.max_iterations = 5000;
    s.relaxation = 0.2;  // slow: the solve runs past the first 20 sweeps, where checks space
    Rng ra(1), rb(1);
    const NlgsResult a = solve_nlgs<3>(every, s, ra);
    s.spaced_checks = true;
    const NlgsResult b = solve_nlgs<3>(spaced, s, rb);
    ASSERT_TRUE(a.converged && b.converged) << tol;
    ASSERT_GT(a.iterations, 20) << "the solve must outlast the every-sweep checks";
    std::cout << "tolerance " << tol << ": every-sweep checks stop after " << a.iterations
              << " sweeps, spaced checks after " << b.iterations << "\n";
    EXPECT_LE(b.error, tol);
    EXPECT_EQ(b.residual, natural_map_error<3>(spaced));
    int first_due = a.iterations;
    while (!residual_due(first_due)) ++first_due;
    EXPECT_EQ(b.iterations, first_due) << tol << ": every-sweep checks stopped at " << a.iterations;
    EXPECT_LE(b.iterations, a.iterations + std::max(1, a.iterations / 20));
  }
}

// Quad and Maxm stop the loop; the natural residual is filled anyway. Relaxation 0.8 too.
TEST(CdNlgs, QuadMaxmCriteria) {
  for (const auto crit : {Criterion::kQuad, Criterion::kMaxm}) {
    auto p = coupled_problem<3>(8, 4);
    NlgsSettings s;
    s.criterion = crit;
    s.tolerance = 1e-9;
    s.relaxation = 0.8;
    s.max_iterations = 5000;
    Rng rng(1);
    const NlgsResult res = solve_nlgs<3>(p, s, rng);
    EXPECT_TRUE(res.converged) << to_string(crit);
    EXPECT_LE(res.error, 1e-9);
    EXPECT_LE(res.residual, 1e-6) << to_string(crit);  // the velocity change bounds the law error
    EXPECT_EQ(res.residual, natural_map_error<3>(p));
  }
}

// Shuffled order: same seed, bit-identical reactions; max_iterations = 0 does nothing.
TEST(CdNlgs, ShuffledDeterministicAndZeroSweeps) {
  NlgsSettings s;
  s.order = SweepOrder::kShuffled;
  s.max_iterations = 7;
  auto a = coupled_problem<3>(10, 8), b = coupled_problem<3>(10, 8);
  Rng ra(42), rb(42);
  solve_nlgs<3>(a, s, ra);
  solve_nlgs<3>(b, s, rb);
  EXPECT_EQ(std::memcmp(a.rf.data(), b.rf.data(), sizeof(double) * a.rf.size()), 0);
  s.max_iterations = 0;
  auto c = coupled_problem<3>(10, 8);
  Rng rc(1);
  const NlgsResult res = solve_nlgs<3>(c, s, rc);
  EXPECT_EQ(res.iterations, 0);
  EXPECT_TRUE(c.rf.isZero(0.0));
  EXPECT_GT(res.residual, 0.0);
}

// Sweep orders: alternating reverses every other sweep; shuffled is a permutation.
TEST(CdNlgs, SweepOrders) {
  std::vector<std::size_t> o(5);
  Rng rng(3);
  fill_sweep_order(o, SweepOrder::kAlternating, 1, rng);
  EXPECT_EQ(o, (std::vector<std::size_t>{4, 3, 2, 1, 0}));
  fill_sweep_order(o, SweepOrder::kAlternating, 2, rng);
  EXPECT_EQ(o, (std::vector<std::size_t>{0, 1, 2, 3, 4}));
  fill_sweep_order(o, SweepOrder::kShuffled, 0, rng);
  std::vector<std::size_t> sorted = o;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(sorted, (std::vector<std::size_t>{0, 1, 2, 3, 4}));
}

// Names round-trip.
TEST(CdNlgs, Names) {
  for (const auto v : {LocalSolver::kBipotential, LocalSolver::kExact})
    EXPECT_EQ(parse_local_solver(to_string(v)), v);
  for (const auto v : {SweepOrder::kForward, SweepOrder::kAlternating, SweepOrder::kShuffled})
    EXPECT_EQ(parse_sweep_order(to_string(v)), v);
  for (const auto v : {Criterion::kQuad, Criterion::kMaxm, Criterion::kNatural})
    EXPECT_EQ(parse_criterion(to_string(v)), v);
  EXPECT_FALSE(parse_local_solver("newton").has_value());
}

// MatrixProblem: velocity() is q_a + sum_b W_ab r_b over the stored blocks; the same NLGS on
// it and on the dense form of the same problem gives the same reactions (bit-identical: the
// same operations in the same order up to the order of the block sums, hence 1e-14).
TEST(CdNlgs, MatrixProblemMatchesDense) {
  auto dense = coupled_problem<3>(6, 12);
  std::vector<std::size_t> row_ptr{0}, cols;
  std::vector<LMat<3>> blocks;
  std::vector<LVec<3>> q;
  for (int a = 0; a < 6; ++a) {
    for (int b = 0; b < 6; ++b) {
      cols.push_back(static_cast<std::size_t>(b));
      blocks.push_back(dense.Wf.block<3, 3>(3 * a, 3 * b));
    }
    row_ptr.push_back(cols.size());
    q.push_back(dense.qf.segment<3>(3 * a));
  }
  MatrixProblem<3> mp(row_ptr, cols, blocks, q, dense.mus);
  NlgsSettings s;
  s.tolerance = 1e-12;
  Rng r1(1), r2(1);
  solve_nlgs<3>(dense, s, r1);
  solve_nlgs<3>(mp, s, r2);
  for (std::size_t a = 0; a < 6; ++a)
    EXPECT_LE((mp.r(a) - dense.r(a)).norm(), 1e-12 * (1.0 + mp.r(a).norm()));
  EXPECT_NEAR(fc_residual<3>(mp), natural_map_error<3>(mp), 1e-15);
}

}  // namespace
