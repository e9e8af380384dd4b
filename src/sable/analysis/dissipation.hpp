// Where the power goes: what the walls put into the grains, and what the contacts dissipate.
//
// At one instant, for the contacts of a sample (force F on grain i, relative velocity
// v_rel of i's contact point less the partner's, normal n, n_i its normal force, f_t its
// tangential force, gamma_n and gamma_t the normal law's damping at the overlap):
//  - contact power P_c = -sum F . v_rel: the power the contact forces take out of the grains'
//    (and walls') relative motion. Over any time, its integral is the energy dissipated plus
//    the change of the energy stored in the contacts' springs;
//  - dissipation P_d = P_n + P_t + P_s, its part that is lost:
//      P_n = sum gamma_n (v_rel . n)^2          the normal dashpots,
//      P_t = sum_sticking gamma_t |v_t|^2       the tangential dashpots of sticking contacts,
//      P_s = sum_sliding -f_t . v_t             Coulomb sliding (the spring held at mu f_n: the
//                                               work of f_t on the slip is lost);
//    a contact slides when its tangential spring's force k_t |xi| is at the cap mu f_n (within
//    1e-9: the kernel holds it there exactly; contact dynamics: |f_t| at the cap). The cap is
//    taken on the whole normal force, so a wet contact's sliding (whose cap leaves out the
//    bridge's pull) is counted as sticking;
//  - wall power P_w = sum_{contacts of w} F . v_w(x_c): the power wall w delivers to the
//    grains (its velocity at the contact point: for a wall turning at omega about a pivot,
//    P_w = -omega . M_w with M_w the torque the grains exert on it);
//  - kinetic energy K = sum (m v^2 + I w^2) / 2 and potential energy U = -sum m g . x.
// Energy balance: sum_w P_w + (gravity's power) = dK/dt + P_c, i.e.
// sum_w P_w = d(K + U)/dt + P_c; in a stationary state the input power sum_w P_w equals the
// mean dissipation <P_d> (the springs' energy does not grow without bound).
// The sample must be in the lab frame (velocities, not those relative to a turning frame:
// P_w and K depend on the frame; P_c and P_d do not). Contact dynamics has no dashpots and no
// springs: there P_d is P_c. Rolling resistance couples are not counted (a sample does not
// hold them).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "sable/analysis/report.hpp"
#include "sable/analysis/sample.hpp"

namespace sable {

struct PowerBudget {
  double time = 0.0;
  std::size_t contacts = 0, sliding = 0;
  double contact = 0.0;                                   // P_c (W; 2D: per thickness)
  double damping_normal = 0.0, damping_tangential = 0.0;  // P_n, P_t
  double sliding_power = 0.0;                             // P_s
  double kinetic = 0.0, potential = 0.0;                  // K, U (J)
  std::vector<std::string> wall_names;                    // the sample's walls, in order
  std::vector<double> wall_power;                         // P_w, by wall
  bool rigid = false;  // contact dynamics: no dashpots, no springs
  double dissipation() const {
    return rigid ? contact : damping_normal + damping_tangential + sliding_power;
  }
  double walls() const;
};

// Why polyhedral grains are refused (refuse_polyhedra()): the DEM law has a dashpot per
// manifold point and a spring per entry whose powers the lists do not keep, and a rotational
// energy needs each grain's inertia tensor.
inline constexpr const char* kDissipationPolyhedra =
    "the contact law's dashpots act at each manifold point, which the snapshot does not keep, "
    "so the dissipated power cannot be rebuilt";

// Throws InputError for a sample of polyhedral grains (kDissipationPolyhedra).
template <int D>
PowerBudget power_budget(const Sample<D>& s);

// dissipation.csv: one row per snapshot.
Table power_budget_table(const std::vector<PowerBudget>& rows);
// Means over the snapshots (with standard deviations and standard errors of the mean), the
// input power over the dissipation, and d(K + U)/dt from the first and last snapshots.
Summary power_budget_summary(const std::vector<PowerBudget>& rows);

}  // namespace sable
