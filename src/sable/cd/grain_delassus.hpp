// The grains' contact problem in assembled form, U = W r + q, for the semismooth Newton of
// fc_newton.hpp (the NLGS never needs W: it works through the grains' velocities).
//
// A contact a sees grain g with sign s_a,g (+1 for its grain i, -1 for its partner j) at the
// arm x_a,g from g's centre; its local velocity is s_a,g F_a^T (v_g + omega_g x x_a,g) summed
// over its grains, F_a its frame (columns n, t1, t2). An impulse F_b r_b of contact b on g
// changes v_g by m_g^-1 s_b,g F_b r_b and omega_g by I_g^-1 x_b,g x (s_b,g F_b r_b). So
//   W_ab = sum over the grains g that a and b share of
//          s_a,g s_b,g F_a^T [m_g^-1 P + I_g^-1 (x_b,g x P) x x_a,g]_(P = columns of F_b),
// computed with the same Space<D> operations (moment, spin_velocity) as the solver's apply(),
// so W r is what the sweeps' velocities see, to round-off. Walls have infinite mass: a
// grain-wall contact couples only through its grain. Wall bodies (stress-controlled walls)
// and rolling couples are not represented: the caller does not assemble such problems.
#pragma once

#include <vector>

#include "sable/cd/cd_solver.hpp"
#include "sable/cd/fc_problem.hpp"

namespace sable::cd {

// W from the step's contacts and the grains' masses and inertias; q the contacts' velocities
// with every impulse zero (the free velocities, gaps included); mu per contact. The reactions
// start at zero.
template <int D>
MatrixProblem<D> assemble_grain_problem(const typename CdSolver<D>::Contacts& c,
                                        const ParticleStore<D>& p, std::vector<LVec<D>> q);

}  // namespace sable::cd
