// Semismooth Newton on Alart-Curnier's function: see fc_newton.hpp.
#include "sable/cd/fc_newton.hpp"

#include <Eigen/SparseCore>
#include <Eigen/SparseLU>
#include <algorithm>
#include <cmath>
#include <vector>

namespace sable::cd {

namespace {

// F at one contact, and (with `A`, `B` not null) the blocks dF/du and dF/dr there.
template <int d>
LVec<d> ac_function(const LVec<d>& r, const LVec<d>& u, double mu, double rho_n, double rho_t,
                    LMat<d>* A, LMat<d>* B) {
  using Vt = Eigen::Matrix<double, d - 1, 1>;
  using Mt = Eigen::Matrix<double, d - 1, d - 1>;
  LVec<d> F;
  if (A != nullptr) {
    A->setZero();
    B->setZero();
  }
  const double tau_n = r[0] - rho_n * u[0];
  if (tau_n <= 0.0) {  // take-off: F = r
    F = r;
    if (B != nullptr) B->setIdentity();
    return F;
  }
  F[0] = rho_n * u[0];
  if (A != nullptr) (*A)(0, 0) = rho_n;
  const double radius = mu * tau_n;
  const Vt tau_t = r.template tail<d - 1>() - rho_t * u.template tail<d - 1>();
  const double t = tau_t.norm();
  if (t <= radius) {  // sticking: F_T = rho_T u_T
    F.template tail<d - 1>() = rho_t * u.template tail<d - 1>();
    if (A != nullptr) A->template bottomRightCorner<d - 1, d - 1>() = rho_t * Mt::Identity();
    return F;
  }
  // Sliding: F_T = r_T - radius tau_T / |tau_T|.
  const Vt dir = tau_t / t;
  F.template tail<d - 1>() = r.template tail<d - 1>() - radius * dir;
  if (A != nullptr) {
    const Mt P = (Mt::Identity() - dir * dir.transpose()) / t;  // d(tau/|tau|)/d tau
    B->template bottomRightCorner<d - 1, d - 1>() = Mt::Identity() - radius * P;
    A->template bottomRightCorner<d - 1, d - 1>() = radius * rho_t * P;
    B->template bottomLeftCorner<d - 1, 1>() = -mu * dir;
    A->template bottomLeftCorner<d - 1, 1>() = mu * rho_n * dir;
  }
  return F;
}

}  // namespace

template <int d>
NewtonResult solve_newton_ac(MatrixProblem<d>& p, const NewtonSettings& s) {
  using SpMat = Eigen::SparseMatrix<double>;
  const std::size_t n = p.size();
  NewtonResult res;
  res.residual = natural_map_error<d>(p);
  if (n == 0 || res.residual <= s.tolerance) {
    res.converged = true;
    return res;
  }
  const double start = res.residual;
  // rho from each contact's diagonal block: the scale at which u and r compare.
  std::vector<double> rho_n(n), rho_t(n);
  for (std::size_t a = 0; a < n; ++a) {
    const LMat<d>& W = p.W(a);
    rho_n[a] = 1.0 / W(0, 0);
    const double wt = W.diagonal().template tail<d - 1>().mean();
    rho_t[a] = wt > 0.0 ? 1.0 / wt : rho_n[a];
  }
  const auto rows = p.row_ptr();
  const auto cols = p.cols();
  const auto blocks = p.blocks();
  const auto N = static_cast<Eigen::Index>(d * n);
  std::vector<LVec<d>> r0(n), U(n), F(n);
  std::vector<LMat<d>> A(n), B(n);
  // F at the current reactions (and the Jacobian blocks when asked); returns |F|^2 / 2.
  const auto evaluate = [&](bool jacobian) {
    double merit = 0.0;
    for (std::size_t a = 0; a < n; ++a) {
      U[a] = p.velocity(a);
      F[a] = ac_function<d>(p.r(a), U[a], p.mu(a), rho_n[a], rho_t[a], jacobian ? &A[a] : nullptr,
                            jacobian ? &B[a] : nullptr);
      merit += 0.5 * F[a].squaredNorm();
    }
    return merit;
  };
  std::vector<Eigen::Triplet<double>> triplets;
  Eigen::SparseLU<SpMat> lu;
  bool analysed = false;
  constexpr std::size_t kMemory = 8;
  std::vector<double> recent;
  double merit = evaluate(true);
  for (int it = 0; it < s.max_iterations; ++it) {
    // J = B + A W (+ a shift that keeps it regular where W is singular), block by block.
    triplets.clear();
    for (std::size_t a = 0; a < n; ++a) {
      for (std::size_t k = rows[a]; k < rows[a + 1]; ++k) {
        LMat<d> J = A[a] * blocks[k];
        if (cols[k] == a) J += B[a];
        // Every entry of W's blocks, zeros too: the pattern stays W's, analysed once.
        for (int i = 0; i < d; ++i)
          for (int j = 0; j < d; ++j)
            triplets.emplace_back(static_cast<int>(d * a) + i, static_cast<int>(d * cols[k]) + j,
                                  J(i, j));
      }
    }
    SpMat J(N, N);
    J.setFromTriplets(triplets.begin(), triplets.end());
    // J is dimensionless (rho W ~ 1 on the diagonal); the shift shrinks with the residual, so
    // that the steps become Newton's as the iterate converges.
    J.diagonal().array() += 1e-12 + 0.1 * std::min(1.0, res.residual / start);
    J.makeCompressed();
    if (!analysed) {
      lu.analyzePattern(J);
      analysed = true;
    }
    lu.factorize(J);
    if (lu.info() != Eigen::Success) {
      res.failed = true;
      break;
    }
    Eigen::VectorXd rhs(N);
    for (std::size_t a = 0; a < n; ++a) rhs.segment<d>(static_cast<Eigen::Index>(d * a)) = -F[a];
    const Eigen::VectorXd dr = lu.solve(rhs);
    if (!dr.allFinite()) {
      res.failed = true;
      break;
    }
    for (std::size_t a = 0; a < n; ++a) r0[a] = p.r(a);
    // Backtrack: the full step first, halved until the merit falls by Armijo's fraction below
    // the largest of the last kMemory merits (non-monotone, Grippo et al. 1986: a semismooth
    // step that crosses a kink, a contact changing case, may raise the merit for a step or
    // two on its way down).
    recent.push_back(merit);
    if (recent.size() > kMemory) recent.erase(recent.begin());
    const double reference = *std::max_element(recent.begin(), recent.end());
    double t = 1.0, trial = merit;
    bool accepted = false;
    for (int ls = 0; ls < 30 && !accepted; ++ls, t *= 0.5) {
      for (std::size_t a = 0; a < n; ++a)
        p.apply(a, r0[a] + t * dr.segment<d>(static_cast<Eigen::Index>(d * a)) - p.r(a));
      trial = evaluate(false);
      accepted = trial <= reference - 1e-4 * t * 2.0 * merit;
    }
    ++res.iterations;
    if (!accepted) {
      p.set_reactions(r0);
      res.failed = true;
      break;
    }
    res.residual = natural_map_error<d>(p);
    if (res.residual <= s.tolerance) {
      res.converged = true;
      break;
    }
    merit = evaluate(true);
  }
  res.residual = natural_map_error<d>(p);
  res.converged = res.residual <= s.tolerance;
  return res;
}

template NewtonResult solve_newton_ac<2>(MatrixProblem<2>&, const NewtonSettings&);
template NewtonResult solve_newton_ac<3>(MatrixProblem<3>&, const NewtonSettings&);

}  // namespace sable::cd
