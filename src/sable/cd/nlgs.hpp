// Nonlinear Gauss-Seidel (NLGS) over contacts for frictional contact problems in local form:
//
//   find r_a in K_mu_a and U_a = sum_b W_ab r_b + q_a such that, for every contact a,
//   r_a and U_a + mu_a |U_T,a| e_N satisfy Coulomb's law in De Saxce's form
//   (r_a in K_mu, U~_a in K*_mu, r_a . U~_a = 0).
//
// Local vectors are ordered [N, T1] (2D) or [N, T1, T2] (3D), as in Siconos/FCLIB.
// The same NLGS code serves a generic problem with explicit W blocks (`sable fc3d FILE.dat`)
// and the contact-dynamics solver on grains (where U_a is computed from body velocities), so
// the two are checked against each other: a Problem only has to provide the operations
// documented on `NlgsProblem` below.
#pragma once

#include <Eigen/Core>
#include <array>
#include <complex>
#include <cstdint>
#include <optional>
#include <string_view>

#include "sable/cd/colouring.hpp"
#include "sable/core/rng.hpp"

namespace sable::cd {

template <int d>
using LVec = Eigen::Matrix<double, d, 1>;
template <int d>
using LMat = Eigen::Matrix<double, d, d>;

enum class LocalSolver : std::uint8_t {
  kBipotential,  // De Saxce-Feng bi-potential prediction-correction (Dumont-Fortin-Ouafik eq. 15)
  kExact,        // exact solution of the one-contact problem (enumeration / Newton)
};
// kColoured: blocks of contacts coloured so that one colour's blocks share no body, swept in
// parallel (colouring.hpp); only for a Problem that provides `colouring()`.
enum class SweepOrder : std::uint8_t { kForward, kAlternating, kShuffled, kColoured };
enum class Criterion : std::uint8_t {
  kQuad,     // LMGC90 'Quad': sqrt(sum |dU|^2 / sum |U|^2) over one sweep
  kMaxm,     // LMGC90 'Maxm': max |dU| / mean |U|
  kNatural,  // natural-map residual (Siconos' error), see natural_map_error()
};

struct NlgsSettings {
  LocalSolver local = LocalSolver::kBipotential;
  SweepOrder order = SweepOrder::kForward;
  Criterion criterion = Criterion::kNatural;
  double relaxation = 1.0;  // r_a <- (1 - relaxation) r_a + relaxation r_a_local
  double tolerance = 1e-4;
  int max_iterations = 1000;  // sweeps
  // Stagnation: when the criterion has not fallen by half over this many sweeps, a forward or
  // alternating order turns to a shuffled one for the rest of the solve (seeded: the rng of
  // solve_nlgs). A fixed order can cycle (Siconos' OneObject-i100000-316 sits at 1.7e-3 for
  // 20,000 forward sweeps; shuffled, it reaches 1e-6 in 313). 0: never.
  int stagnation_window = 100;
  // The first response to a stagnation; false: none (the grains' sweep, whose order matters).
  bool shuffle_on_stagnation = true;
  // Return at a stagnation that the shuffle did not cure (or, with a shuffled order or no
  // shuffle, at the first), with NlgsResult::stagnated set: a caller with a global method
  // takes over there.
  bool stop_on_stagnation = false;
  // The natural-map residual costs about one sweep (every contact's velocity again): with
  // spaced checks it is computed after each of the first 20 sweeps, then after every
  // (sweeps / 20)-th, at most every 25th (residual_due()), so that a long solve spends a few
  // % of its time on checks instead of ~45 %, and stops at the first due check that meets
  // the tolerance (where the residual stays below it once there, at most 5 % of its sweeps
  // after the first sweep that met it). false (the default; `sable fc3d`, whose sweep counts are
  // compared with Siconos'): after every sweep. A scenario chooses with [cd] residual_checks.
  bool spaced_checks = false;
};

// Whether solve_nlgs computes the natural-map residual after `sweeps` sweeps (spaced checks).
constexpr bool residual_due(int sweeps) {
  if (sweeps <= 20) return true;
  const int gap = sweeps / 20 < 25 ? sweeps / 20 : 25;
  return sweeps % gap == 0;
}

struct NlgsResult {
  int iterations = 0;     // sweeps done
  double error = 0.0;     // the chosen criterion's value at the end
  double residual = 0.0;  // natural-map residual at the end, whatever the criterion
  bool converged = false;
  int reordered_at = -1;   // the first shuffled sweep after a stagnation (-1: none)
  bool stagnated = false;  // stopped by stop_on_stagnation
};

// What NLGS needs from a problem (a concept, documented here, satisfied by MatrixProblem in
// fc_problem.hpp and by the grain problem in cd_solver.cpp):
//
//   std::size_t size() const;                      number of contacts
//   const LMat<d>& W(std::size_t a) const;         Delassus diagonal block W_aa
//   double mu(std::size_t a) const;                friction coefficient
//   LVec<d>& r(std::size_t a);                     current impulse (local frame)
//   LVec<d> velocity(std::size_t a) const;         U_a = sum_b W_ab r_b + q_a, current
//   void apply(std::size_t a, const LVec<d>& dr);  r_a += dr, and update whatever U_b depend on
//   double q_norm() const;                         ||q|| (for the natural-map normalisation)
//   void solve_extra(std::size_t a);               optional: called after each apply() of a
//                                                  sweep, for unknowns beside the impulse
//                                                  (the grain problem's rolling couples)
//   void extra_residual(std::size_t a, double& f2, double& r2, double& u2) const;
//                                                  optional: adds those unknowns' natural
//                                                  map (f2) and norms (r2, u2) to the
//                                                  sums of natural_map_error
//   const SweepColouring& colouring() const;       optional: the blocks of the kColoured
//                                                  order; apply() and solve_extra() of
//                                                  contacts in different blocks of a colour
//                                                  then run at once on different threads

// Euclidean projection of x onto the Coulomb cone K_mu = { |x_T| <= mu x_N }.
template <int d>
LVec<d> project_cone(const LVec<d>& x, double mu);

// The natural map of one contact: r - P_K(r - (U + mu |U_T| e_N)). Zero iff solved.
template <int d>
LVec<d> natural_map(const LVec<d>& r, const LVec<d>& U, double mu);

// The four roots of c4 u^4 + c3 u^3 + c2 u^2 + c1 u + c0 (c4 != 0; complex roots as conjugate
// pairs), in closed form: the exact local solver's sliding directions (local_solvers.cpp).
std::array<std::complex<double>, 4> quartic_roots(double c4, double c3, double c2, double c1,
                                                  double c0);

// Solve the one-contact problem U = W r + q (W = W_aa, q = U_a - W_aa r_a, everything else
// frozen) for r in K_mu. `r` holds the current value on entry (a starting guess).
template <int d>
LVec<d> solve_local(const LMat<d>& W, const LVec<d>& q, double mu, const LVec<d>& r,
                    LocalSolver kind);

// The nonlinear Gauss-Seidel loop. `rng` is used by SweepOrder::kShuffled only.
template <int d, class Problem>
NlgsResult solve_nlgs(Problem& problem, const NlgsSettings& s, Rng& rng);

// Siconos' error: ||r - P_K(r - (U + mu|U_T| e_N))|| / max(||q||, ||r||, ||U||), all norms over
// the whole problem, with the problem's extra unknowns if it has them (extra_residual); 0 when
// all three are zero.
template <int d, class Problem>
double natural_map_error(Problem& problem);

std::string_view to_string(LocalSolver);
std::string_view to_string(SweepOrder);
std::string_view to_string(Criterion);

// Inverses of to_string ("bipotential", "forward", "natural", ...); nullopt if unknown.
std::optional<LocalSolver> parse_local_solver(std::string_view);
std::optional<SweepOrder> parse_sweep_order(std::string_view);
std::optional<Criterion> parse_criterion(std::string_view);

}  // namespace sable::cd

#include "sable/cd/nlgs_impl.hpp"
