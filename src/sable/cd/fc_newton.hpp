// A semismooth Newton method on Alart and Curnier's formulation of the frictional contact
// problem (Alart & Curnier 1991; Acary, Bremond & Huber 2018, section 4), for problems with an
// assembled Delassus matrix (MatrixProblem). It finishes what the NLGS starts: Gauss-Seidel
// gets near a solution cheaply but can stall there (ill-conditioned or singular W: redundant
// contacts, long chains), where Newton's local convergence is quadratic.
//
// With rho_N, rho_T > 0 per contact, u = W r + q and tau_N = r_N - rho_N u_N,
//   F_N = r_N - max(tau_N, 0),
//   F_T = r_T - P_D(mu max(tau_N, 0)) (r_T - rho_T u_T),   P_D(s) the projection on the disk
//   of radius s (a segment in 2D);
// F(r) = 0 exactly at the solutions of the Coulomb problem. Each iteration solves
// (B + A W) dr = -F, A and B the blocks of a generalized Jacobian of F in u and r (take-off,
// sticking and sliding cases), with Eigen's sparse LU, then backtracks along dr until the
// merit |F|^2 / 2 falls (Armijo). A singular W (more contact directions than degrees of
// freedom) makes the Jacobian singular where contacts stick: a small diagonal shift
// (Levenberg) keeps each step defined. The iterate is the problem's own reactions.
#pragma once

#include "sable/cd/fc_problem.hpp"

namespace sable::cd {

struct NewtonSettings {
  double tolerance = 1e-4;  // Siconos' error (natural_map_error), as the NLGS's
  int max_iterations = 100;
};

struct NewtonResult {
  int iterations = 0;
  double residual = 0.0;  // natural_map_error at the end
  bool converged = false;
  bool failed = false;  // a step found no decrease of the merit, or the LU failed
};

template <int d>
NewtonResult solve_newton_ac(MatrixProblem<d>& p, const NewtonSettings& s);

}  // namespace sable::cd
