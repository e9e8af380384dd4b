// The one-contact solvers of the NLGS (nlgs.hpp): the bi-potential prediction-correction local
// solver (Dumont, Fortin & Ouafik 2010, eq. 15) and the exact local solver (enumeration of
// take-off / stick / slide, Figure 4 of the paper). Explicitly instantiated for d = 2, 3. The
// projection on the Coulomb cone and the natural map are in nlgs_impl.hpp.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <numeric>

#include "sable/cd/nlgs.hpp"

namespace sable::cd {
namespace {

// The largest real root of the cubic x^3 + A x^2 + B x + C (there is always a real root):
// trigonometric form when all three are real, Cardano's otherwise.
double largest_cubic_root(double A, double B, double C) {
  const double P = B - A * A / 3.0, Q = 2.0 * A * A * A / 27.0 - A * B / 3.0 + C;
  const double shift = -A / 3.0;  // x = z + shift, z^3 + P z + Q = 0
  const double disc = 0.25 * Q * Q + P * P * P / 27.0;
  if (disc < 0.0) {  // three real roots (P < 0): the largest is k = 0
    const double rad = 2.0 * std::sqrt(-P / 3.0);
    const double arg = std::clamp(3.0 * Q / (P * rad), -1.0, 1.0);
    return shift + rad * std::cos(std::acos(arg) / 3.0);
  }
  // One real root: z = w - P / (3 w), w^3 = -Q/2 -+ sqrt(disc), the sign that avoids
  // cancellation.
  const double w = std::cbrt(-0.5 * Q - std::copysign(std::sqrt(disc), Q));
  return shift + (w != 0.0 ? w - P / (3.0 * w) : 0.0);
}

// The roots of y^2 + b y + c (real coefficients) into out[0], out[1].
void quadratic_roots(double b, double c, std::complex<double>* out) {
  const double disc = b * b - 4.0 * c;
  if (disc >= 0.0) {
    const double t = -0.5 * (b + std::copysign(std::sqrt(disc), b));  // no cancellation
    out[0] = t;
    out[1] = t != 0.0 ? c / t : 0.0;
  } else {
    out[0] = {-0.5 * b, 0.5 * std::sqrt(-disc)};
    out[1] = std::conj(out[0]);
  }
}

constexpr double kLocalTolerance = 1e-14;  // relative local natural map of the bi-potential loop
constexpr int kLocalCap = 5000;            // bi-potential local iterations at most
constexpr double kSlideAcceptance = 1e-9;  // a 3D sliding root must satisfy the law to this

// |F(r, U)| / max(|q|, |r|, |U|) for one contact (0 when everything is zero); q_norm = |q|,
// computed once by the caller (the bi-potential loop calls this at every local iteration).
template <int d>
double local_relative_error(const LVec<d>& r, const LVec<d>& U, double q_norm, double mu) {
  const double f = natural_map<d>(r, U, mu).norm();
  if (f == 0.0) return 0.0;
  const double den = std::max({q_norm, r.norm(), U.norm()});
  return den > 0.0 ? f / den : std::numeric_limits<double>::infinity();
}

// Largest eigenvalue of the symmetric part of a d x d block (closed form).
template <int d>
double max_eigenvalue(const LMat<d>& A) {
  const LMat<d> sym = 0.5 * (A + A.transpose());
  Eigen::SelfAdjointEigenSolver<LMat<d>> es;
  es.computeDirect(sym, Eigen::EigenvaluesOnly);
  return es.eigenvalues()[d - 1];
}

// Bi-potential prediction-correction (eq. 15 of the paper):
//   tau = r - rho [U_T + (U_N + mu |U_T|) e_N],   r <- proj(tau, K_mu),   U = W r + q,
// whose fixed points are exactly the solutions of De Saxce's law, for any rho > 0.
//
// Choice of rho. Frozen in an active state the iteration is r <- P(r - rho W r - ...), a
// Richardson iteration that contracts iff rho < 2 / lambda_max(W), at the rate
// max |1 - rho lambda_i(W)|. rho = 1 / W_NN therefore diverges or stalls when W_TT >> W_NN, and
// any rho from lambda_max alone is slow when W_NN << W_TT. Two steps:
//  1. A diagonal scaling that leaves the law invariant: with S = diag(s_N, s_T, s_T) and
//     r = S r^, the problem in r^ is the same law for W^ = S W S, q^ = S q and mu^ = mu s_N/s_T
//     (K_mu is mapped onto K_mu^, the dual cone and the De Saxce term alike, since the tangent
//     directions share one factor). s_N = W_NN^-1/2, s_T = mean(W_TT)^-1/2 give W^ a unit
//     diagonal (up to the T1/T2 anisotropy): no more N/T imbalance.
//  2. rho = 1 / lambda_max(W^) (symmetric part): the largest step with a monotone contraction in
//     the stick state (rate 1 - lambda_min/lambda_max). The "optimal" Richardson step
//     2 / (lambda_min + lambda_max) is faster on mildly conditioned blocks, but the De Saxce
//     term makes it cycle on strongly N-T coupled ones, where 1 / lambda_max converges.
// In the original variables this is the paper's iteration with rho_N = rho s_N^2 on the normal
// and rho_T = rho s_T^2 on the tangential part and the projection taken in the matching metric.
// Known limit: while sliding, r_N converges at the rate 1 - rho D / (1 + mu^2) (D = W_NN -
// mu W_NT e): with mu^2 W_TT / W_NN >> 1 (large mu^ after scaling) the iteration is slow, hence
// the generous cap (W = diag(1, 1000, 1000), mu = 0.3, sliding: ~2400 iterations to 1e-14).
template <int d>
LVec<d> solve_bipotential(const LMat<d>& W, const LVec<d>& q, double mu, const LVec<d>& r_in) {
  const double wn = W(0, 0);
  const double wt = W.diagonal().template tail<d - 1>().mean();
  const bool scale = wn > 0.0 && wt > 0.0 && std::isfinite(wn) && std::isfinite(wt);
  LVec<d> s = LVec<d>::Constant(scale ? 1.0 / std::sqrt(wt) : 1.0);
  if (scale) s[0] = 1.0 / std::sqrt(wn);
  const LMat<d> Wh = s.asDiagonal() * W * s.asDiagonal();
  const LVec<d> qh = s.cwiseProduct(q);
  const double muh = mu * s[0] / s[1];
  const double lmax = max_eigenvalue<d>(Wh);
  const double rho = lmax > 0.0 ? 1.0 / lmax : 1.0;
  LVec<d> rh = r_in.cwiseQuotient(s);
  const double q_norm = q.norm();
  for (int it = 0; it < kLocalCap; ++it) {
    const LVec<d> Uh = Wh * rh + qh;
    // Stop on the natural map of the original (unscaled) problem: U = S^-1 U^, r = S r^.
    if (local_relative_error<d>(s.cwiseProduct(rh), Uh.cwiseQuotient(s), q_norm, mu) <=
        kLocalTolerance)
      break;
    LVec<d> tau = rh - rho * Uh;
    tau[0] -= rho * muh * tangent_norm<d>(Uh);
    const LVec<d> next = project_cone<d>(tau, muh);
    if (next == rh) break;  // a floating-point fixed point: no further progress possible
    rh = next;
  }
  return s.cwiseProduct(rh);
}

// Sliding in 2D: r_T = -sigma mu r_N with sigma = sign(U_T), r_N from U_N = 0. Both signs are
// tried; a candidate is kept if r_N > 0 and sigma U_T >= 0. Among consistent candidates (two can
// exist when the N-T coupling is strong) the closest to r_in is returned.
bool slide_2d(const LMat<2>& W, const LVec<2>& q, double mu, const LVec<2>& r_in, LVec<2>& out) {
  bool found = false;
  double best = std::numeric_limits<double>::infinity();
  for (const double sigma : {1.0, -1.0}) {
    const double D = W(0, 0) - sigma * mu * W(0, 1);
    if (!(D > 0.0)) continue;
    const double rn = -q[0] / D;
    const LVec<2> r(rn, -sigma * mu * rn);
    const double ut = W(1, 0) * r[0] + W(1, 1) * r[1] + q[1];
    if (sigma * ut < 0.0) continue;
    const double dist = (r - r_in).squaredNorm();
    if (!found || dist < best) out = r, best = dist, found = true;
  }
  return found;
}

// Sliding in 3D: r = r_N (1, -mu e), e = (cos t, sin t) the sliding direction. U_N = 0 gives
// r_N = -q_N / D(e) with D(e) = W_NN - mu c.e (c = W_NT), and then D U_T = V(e) with
//   V(e) = -q_N b + q_N mu A e + D(e) q_T        (b = W_TN, A = W_TT).
// The law asks U_T = lambda e, lambda >= 0, D > 0: t is a root of g(t) = e x V(e). With
// e x v = e . (J v), J v = (v_y, -v_x):
//   g = L.e + e^T Q e,  L = J (W_NN q_T - q_N b),  Q = sym(q_N mu J A - mu (J q_T) c^T),
// a trigonometric polynomial of degree 2, hence at most 4 roots, found all at once: with
// u = tan((t - t0)/2), (1 + u^2)^2 g is a quartic in u, solved in closed form (quartic_roots),
// then each root is polished by Newton on g. The offset t0 is the one of 8
// angles with the largest |g(t0 + pi)| (the leading coefficient), so no root sits at u = inf.
struct SlideTrig {
  Eigen::Vector2d L;
  Eigen::Matrix2d Q;
  double g(const Eigen::Vector2d& e) const { return L.dot(e) + e.dot(Q * e); }
  double dg(const Eigen::Vector2d& e) const {  // dg/dt, e' = (-e_y, e_x)
    const Eigen::Vector2d ep(-e[1], e[0]);
    return L.dot(ep) + 2.0 * ep.dot(Q * e);
  }
};

SlideTrig slide_function(const LMat<3>& W, const LVec<3>& q, double mu) {
  const Eigen::Matrix2d J{{0.0, 1.0}, {-1.0, 0.0}};
  const Eigen::Vector2d b = W.block<2, 1>(1, 0), c = W.block<1, 2>(0, 1).transpose();
  const Eigen::Vector2d qt = q.tail<2>();
  const Eigen::Matrix2d M = q[0] * mu * J * W.block<2, 2>(1, 1) - mu * (J * qt) * c.transpose();
  return {J * (W(0, 0) * qt - q[0] * b), 0.5 * (M + M.transpose())};
}

// The sliding directions e of the (at most 4) real roots of g, polished; returns their
// number. No trigonometric function is evaluated: the 8 trial offsets are multiples of pi/4
// (a table), and a root is polished by Newton on u, with e(u) = R(t0) ((1 - u^2), 2u) /
// (1 + u^2) and dt/du = 2 / (1 + u^2) (sincos and atan were a tenth of a small problem's time).
int slide_roots(const SlideTrig& f, std::array<Eigen::Vector2d, 4>& roots) {
  constexpr double h = std::numbers::sqrt2 / 2.0;
  static constexpr std::array<std::array<double, 2>, 8> kEighths{
      {{1.0, 0.0}, {h, h}, {0.0, 1.0}, {-h, h}, {-1.0, 0.0}, {-h, -h}, {0.0, -1.0}, {h, -h}}};
  int best = 0;
  double lead = 0.0;
  for (int k = 0; k < 8; ++k) {  // g at t0 + pi, i.e. at -e(t0)
    const auto& c = kEighths[static_cast<std::size_t>(k)];
    const double gk = f.g(Eigen::Vector2d(-c[0], -c[1]));
    if (std::abs(gk) > std::abs(lead)) best = k, lead = gk;
  }
  if (lead == 0.0) return 0;  // g vanishes at 8 angles: degenerate (U_T = 0 for all e)
  const auto& c0 = kEighths[static_cast<std::size_t>(best)];
  Eigen::Matrix2d R;  // rotation by t0: e = R e'
  R << c0[0], -c0[1], c0[1], c0[0];
  const Eigen::Vector2d L = R.transpose() * f.L;
  const Eigen::Matrix2d Q = R.transpose() * f.Q * R;
  // e' = ((1 - u^2), 2u) / (1 + u^2): (1 + u^2)^2 g = sum c_k u^k.
  const double c4 = Q(0, 0) - L[0], c3 = 2.0 * (L[1] - 2.0 * Q(0, 1));
  const double c2 = 4.0 * Q(1, 1) - 2.0 * Q(0, 0), c1 = 2.0 * (L[1] + 2.0 * Q(0, 1));
  const double cc = L[0] + Q(0, 0);
  const auto e_of = [&R](double u) {
    const double w = 1.0 / (1.0 + u * u);
    return Eigen::Vector2d(R * Eigen::Vector2d((1.0 - u * u) * w, 2.0 * u * w));
  };
  const std::array<std::complex<double>, 4> us = quartic_roots(c4, c3, c2, c1, cc);
  int n = 0;
  for (const std::complex<double>& uc : us) {
    if (!(std::abs(uc.imag()) <= 1e-3 * (1.0 + std::abs(uc.real())))) continue;  // not real
    double u = uc.real();
    Eigen::Vector2d e = e_of(u);
    for (int it = 0; it < 8; ++it) {  // Newton on g(e(u)), kept while it improves
      const double gv = f.g(e), dv = f.dg(e) * 2.0 / (1.0 + u * u);
      if (gv == 0.0 || dv == 0.0) break;
      const double un = u - gv / dv;
      const Eigen::Vector2d en = e_of(un);
      if (!(std::abs(f.g(en)) < std::abs(gv))) break;
      u = un, e = en;
    }
    roots[static_cast<std::size_t>(n++)] = e;
  }
  return n;
}

bool slide_3d(const LMat<3>& W, const LVec<3>& q, double mu, const LVec<3>& r_in, LVec<3>& out) {
  std::array<Eigen::Vector2d, 4> roots{};
  const int n = slide_roots(slide_function(W, q, mu), roots);
  bool found = false;
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d& e = roots[static_cast<std::size_t>(i)];
    const double D = W(0, 0) - mu * (W(0, 1) * e[0] + W(0, 2) * e[1]);
    if (!(D > 0.0)) continue;
    LVec<3> r;
    r[0] = -q[0] / D;
    r.tail<2>() = -mu * r[0] * e;
    // The sign condition lambda >= 0 and the root's accuracy, checked on the law itself.
    if (!(local_relative_error<3>(r, W * r + q, q.norm(), mu) <= kSlideAcceptance)) continue;
    const double dist = (r - r_in).squaredNorm();
    if (!found || dist < best) out = r, best = dist, found = true;
  }
  return found;
}

// Exact local solver: take-off, stick, slide, in this order; bi-potential if no case is
// consistent (or the block is singular).
template <int d>
LVec<d> solve_exact(const LMat<d>& W, const LVec<d>& q, double mu, const LVec<d>& r_in) {
  if (q[0] >= 0.0) return LVec<d>::Zero();  // take-off: r = 0, U = q is admissible
  if (mu <= 0.0 && W(0, 0) > 0.0) {         // frictionless: r_T = 0, U_N = 0
    LVec<d> r = LVec<d>::Zero();
    r[0] = -q[0] / W(0, 0);
    return r;
  }
  LMat<d> Winv;
  bool invertible = false;
  // The determinant's scale, scale^d, as a product: std::pow would be 9 % of the NLGS's
  // instructions (callgrind on bench/pour_cd.sh).
  const double scale = W.cwiseAbs().maxCoeff();
  double scale_d = scale;
  for (int k = 1; k < d; ++k) scale_d *= scale;
  W.computeInverseWithCheck(Winv, invertible, 1e-13 * scale_d);
  if (invertible) {  // stick: U = 0
    LVec<d> r = -Winv * q;
    r -= Winv * (W * r + q);  // one step of iterative refinement (ill-conditioned W)
    if (r[0] > 0.0 && tangent_norm<d>(r) <= mu * r[0]) return r;
  }
  LVec<d> r;
  bool slides = false;
  if constexpr (d == 2) {
    slides = slide_2d(W, q, mu, r_in, r);
  } else {
    slides = slide_3d(W, q, mu, r_in, r);
  }
  if (slides) return r;
  return solve_bipotential<d>(W, q, mu, r_in);
}

}  // namespace

// The four roots of c4 u^4 + c3 u^3 + c2 u^2 + c1 u + c0 (c4 != 0), by Ferrari's method in
// real arithmetic, each real root polished by at most two Newton steps on the quartic.
// Closed form rather than the eigenvalues of the companion matrix: a 4 x 4 Hessenberg-QR was
// a third of the exact local solver's time on small problems (perf on Rover4613.dat). The
// caller keeps the nearly real roots, polishes them on g and checks each on the law itself,
// so rounding near a double root costs at most a root found slightly complex, as with QR.
std::array<std::complex<double>, 4> quartic_roots(double c4, double c3, double c2, double c1,
                                                  double c0) {
  const double a = c3 / c4, b = c2 / c4, c = c1 / c4, e = c0 / c4;
  // u = y - a/4: y^4 + p y^2 + q y + r = 0.
  const double a2 = a * a;
  const double p = b - 0.375 * a2;
  const double q = c - 0.5 * a * b + 0.125 * a2 * a;
  const double r = e - 0.25 * a * c + a2 * b / 16.0 - 3.0 * a2 * a2 / 256.0;
  // Resolvent cubic m^3 + p m^2 + (p^2/4 - r) m - q^2/8: negative at m = 0, so it has a
  // positive root, and with s = sqrt(2m) the quartic factors into real quadratics
  //   (y^2 - s y + p/2 + m + q/(2s)) (y^2 + s y + p/2 + m - q/(2s)).
  // q = 0 (or m = 0 by rounding) leaves a quadratic in y^2.
  const double m = q != 0.0 ? largest_cubic_root(p, 0.25 * p * p - r, -0.125 * q * q) : 0.0;
  std::array<std::complex<double>, 4> u{};
  if (m > 0.0) {
    const double sr = std::sqrt(2.0 * m), h = 0.5 * p + m, g = q / (2.0 * sr);
    quadratic_roots(-sr, h + g, &u[0]);
    quadratic_roots(sr, h - g, &u[2]);
  } else {
    std::array<std::complex<double>, 2> z{};
    quadratic_roots(p, r, z.data());
    u = {std::sqrt(z[0]), -std::sqrt(z[0]), std::sqrt(z[1]), -std::sqrt(z[1])};
  }
  const auto f = [&](double x) { return (((x + a) * x + b) * x + c) * x + e; };
  for (std::complex<double>& x : u) {
    x -= 0.25 * a;
    if (x.imag() != 0.0) continue;
    double t = x.real();
    for (int it = 0; it < 2; ++it) {
      const double fx = f(t), df = ((4.0 * t + 3.0 * a) * t + 2.0 * b) * t + c;
      if (fx == 0.0 || df == 0.0) break;
      const double tn = t - fx / df;
      if (!(std::abs(f(tn)) < std::abs(fx))) break;
      t = tn;
    }
    x = t;
  }
  return u;
}

template <int d>
LVec<d> solve_local(const LMat<d>& W, const LVec<d>& q, double mu, const LVec<d>& r,
                    LocalSolver kind) {
  if (kind == LocalSolver::kExact) return solve_exact<d>(W, q, mu, r);
  return solve_bipotential<d>(W, q, mu, r);
}

void fill_sweep_order(std::vector<std::size_t>& order, SweepOrder o, int sweep, Rng& rng) {
  std::iota(order.begin(), order.end(), std::size_t{0});
  if (o == SweepOrder::kAlternating && sweep % 2 == 1) std::reverse(order.begin(), order.end());
  if (o == SweepOrder::kShuffled) {
    for (std::size_t i = order.size(); i > 1; --i) std::swap(order[i - 1], order[rng.below(i)]);
  }
}

template LVec<2> solve_local<2>(const LMat<2>&, const LVec<2>&, double, const LVec<2>&,
                                LocalSolver);
template LVec<3> solve_local<3>(const LMat<3>&, const LVec<3>&, double, const LVec<3>&,
                                LocalSolver);

std::string_view to_string(LocalSolver s) {
  return s == LocalSolver::kExact ? "exact" : "bipotential";
}
std::string_view to_string(SweepOrder o) {
  switch (o) {
    case SweepOrder::kForward:
      return "forward";
    case SweepOrder::kAlternating:
      return "alternating";
    case SweepOrder::kShuffled:
      return "shuffled";
    case SweepOrder::kColoured:
      return "coloured";
  }
  return "?";
}
std::string_view to_string(Criterion c) {
  switch (c) {
    case Criterion::kQuad:
      return "quad";
    case Criterion::kMaxm:
      return "maxm";
    case Criterion::kNatural:
      return "natural";
  }
  return "?";
}

std::optional<LocalSolver> parse_local_solver(std::string_view s) {
  for (const auto v : {LocalSolver::kBipotential, LocalSolver::kExact})
    if (to_string(v) == s) return v;
  return std::nullopt;
}
std::optional<SweepOrder> parse_sweep_order(std::string_view s) {
  for (const auto v : {SweepOrder::kForward, SweepOrder::kAlternating, SweepOrder::kShuffled,
                       SweepOrder::kColoured})
    if (to_string(v) == s) return v;
  return std::nullopt;
}
std::optional<Criterion> parse_criterion(std::string_view s) {
  for (const auto v : {Criterion::kQuad, Criterion::kMaxm, Criterion::kNatural})
    if (to_string(v) == s) return v;
  return std::nullopt;
}

}  // namespace sable::cd
