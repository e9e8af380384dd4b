// The rolling-resistance pass of the DEM force computation (contact/rolling.hpp).
//
// It runs after the force passes and the accumulation, only when the contact law has a rolling
// sub-model, so a run without one pays nothing for it. It reads what the force passes left:
// which contacts touch (the overlap scratch) and their forces (the normal force caps the
// couple), computes each touching contact's couple into that contact's own slot, then adds
// the couples to the grains' torques in the fixed per-grain order of the accumulation
// (second-member entries, first-member entries, walls): the same bits for any number of
// threads, as every other sum of the step.
#include <omp.h>

#include "sable/dem/dem_solver.hpp"

namespace sable {

namespace {

// Below this many items a loop runs on one thread (as in dem_solver.cpp).
constexpr std::ptrdiff_t kMinParallelRolling = 2048;

}  // namespace

template <int D>
template <class Normal>
void DemSolver<D>::rolling_torques() {
  using S = Space<D>;
  const auto& p = w_.particles;
  auto& nl = w_.neighbors;
  auto& pl = nl.pairs;
  auto& wl = nl.wall_pairs;
  // A snapshot written without rolling resistance, resumed with it: the springs start at zero.
  if (pl.roll.size() != pl.size()) pl.roll.assign(pl.size(), S::zero_rot());
  if (wl.roll.size() != wl.size()) wl.roll.assign(wl.size(), S::zero_rot());
  pair_roll_.resize(pl.size(), S::zero_rot());
  wall_roll_.resize(wl.size(), S::zero_rot());
  const PairTableView materials = w_.materials.pair_view();
  const ContactModel model = w_.model;
  const double dt = w_.dt;
  const double eta = model.rolling_damping;
  auto inv_ic = [&](std::uint32_t g) {
    return inverse_inertia_at_contact(p.inv_inertia[g], p.mass[g], p.radius[g]);
  };
  // One contact: its couple on the first grain, or zero (and a reset spring) if it is apart.
  auto couple = [&](const typename S::Vec& n, double delta, const typename S::Vec& f,
                    const PairParams& pp, double r_eff, double m_eff, double inv_ic_i,
                    double inv_ic_j, const typename S::Rot& w_rel, typename S::Rot& theta) {
    if (delta <= 0.0 || pp.rolling_friction == 0.0) {
      theta = S::zero_rot();
      return S::zero_rot();
    }
    const double k_n = Normal::coeffs(pp, model, delta, r_eff, m_eff).kn;
    const RollingCoeffs c =
        rolling_coeffs(pp.rolling_friction, eta, r_eff, k_n, f.dot(n), inv_ic_i, inv_ic_j);
    return rolling_moment<D>(n, w_rel, c, dt, theta);
  };
  const std::uint32_t* const near = near_.index.data();
  const auto n_near = static_cast<std::ptrdiff_t>(near_.index.size());
#pragma omp parallel for schedule(static) if (n_near >= kMinParallelRolling)
  for (std::ptrdiff_t m = 0; m < n_near; ++m) {
    const std::size_t k = near[m];
    const std::uint32_t i = pl.i[k], j = pl.j[k];
    const typename S::Vec d = p.x[i] - p.x[j];
    const double dist = d.norm();
    const double rsum = p.radius[i] + p.radius[j];
    pair_roll_[k] = couple(d * (1.0 / dist), pair_delta_[k], pl.force[k],
                           materials(p.material[i], p.material[j]),
                           p.radius[i] * p.radius[j] / rsum, 1.0 / (p.inv_mass[i] + p.inv_mass[j]),
                           inv_ic(i), inv_ic(j), p.w[i] - p.w[j], pl.roll[k]);
  }
  const auto n_walls = static_cast<std::ptrdiff_t>(wl.size());
#pragma omp parallel for schedule(static) if (n_walls >= kMinParallelRolling)
  for (std::ptrdiff_t kk = 0; kk < n_walls; ++kk) {
    const auto k = static_cast<std::size_t>(kk);
    const std::uint32_t i = wl.i[k];
    const Wall<D>& wall = w_.walls[wl.wall[k]];
    typename S::Vec n;
    wall.distance(p.x[i], n);
    wall_roll_[k] = couple(n, wall_delta_[k], wl.force[k], materials(p.material[i], wall.material),
                           p.radius[i], p.mass[i], inv_ic(i), 0.0, p.w[i], wl.roll[k]);
  }
  add_rolling_torques();
}

// Each grain's couples, in the accumulation's order: the couple of a contact acts as +M on its
// first grain and -M on its second (and on a wall, which does not turn).
template <int D>
void DemSolver<D>::add_rolling_torques() {
  using S = Space<D>;
  auto& p = w_.particles;
  const auto& nl = w_.neighbors;
  const auto n = static_cast<std::ptrdiff_t>(p.size());
#pragma omp parallel for schedule(static) if (n >= kMinParallelRolling)
  for (std::ptrdiff_t ii = 0; ii < n; ++ii) {
    const auto i = static_cast<std::size_t>(ii);
    typename S::Rot t = S::zero_rot();
    for (std::uint32_t s = near_.second_begin[i]; s < near_.second_begin[i + 1]; ++s)
      t -= pair_roll_[near_.second_pairs[s]];
    for (std::uint32_t m = near_.first_begin[i]; m < near_.first_begin[i + 1]; ++m)
      t += pair_roll_[near_.index[m]];
    for (std::uint32_t k = nl.wall_begin[i]; k < nl.wall_begin[i + 1]; ++k) t += wall_roll_[k];
    p.t[i] += t;
  }
}

template void DemSolver<2>::rolling_torques<HertzNormal>();
template void DemSolver<2>::rolling_torques<LinearNormal>();
template void DemSolver<3>::rolling_torques<HertzNormal>();
template void DemSolver<3>::rolling_torques<LinearNormal>();

}  // namespace sable
