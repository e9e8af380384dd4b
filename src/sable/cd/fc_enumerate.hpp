// A direct solver for the smallest 2D frictional-contact problems: enumerate the state of
// every contact (take-off, stick, slide one way, slide the other), solve the linear system
// each combination sets, keep the first combination whose solution satisfies every
// inequality and the law to the tolerance. 4^n combinations of a 2n x 2n system, so only for
// a handful of contacts, where Gauss-Seidel may need hundreds of sweeps on strongly coupled
// contacts (Siconos' FC2D_SliderCrankLagrangian00000, 2 contacts: 166 sweeps) and a pivoting
// method solves the problem exactly in a microsecond (Siconos' fc2d ENUM and LEMKE do the
// same enumeration, or its pivoting form, on the 2D problem as an LCP).
#pragma once

#include "sable/cd/fc_problem.hpp"

namespace sable::cd {

// Contacts at most for which solve_fc tries the enumeration first (16 combinations of a 4 x 4
// system: about a microsecond; at 3 contacts, 64 of 6 x 6, more than the NLGS usually needs).
inline constexpr std::size_t kEnumerateMaxContacts = 2;

// Tries first the combination each contact's own block points to, then the others in a fixed
// order (each contact's state a base-4 digit, contact 0 the lowest); on success sets the
// problem's reactions and returns true. The acceptance test is
// fc_residual() <= tolerance, Siconos' error recomputed from scratch; on failure the reactions
// are left at zero.
bool solve_enumeration_2d(MatrixProblem<2>& p, double tolerance);

}  // namespace sable::cd
