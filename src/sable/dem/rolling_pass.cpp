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
  using Vec = typename S::Vec;
  using Rot = typename S::Rot;
  const auto& p = w_.particles;
  auto& nl = w_.neighbors;
  auto& pl = nl.pairs;
  auto& wl = nl.wall_pairs;
  // A snapshot written without rolling resistance, resumed with it: the springs start at zero.
  if (pl.roll.size() != pl.size()) pl.roll.assign(pl.size(), S::zero_rot());
  if (wl.roll.size() != wl.size()) wl.roll.assign(wl.size(), S::zero_rot());
  pair_roll_.resize(pl.size(), S::zero_rot());
  wall_roll_.resize(wl.size(), S::zero_rot());
  // Each grain's 1 / (I + m R^2), once per step rather than twice per contact.
  const auto n_grains = static_cast<std::ptrdiff_t>(p.size());
  roll_inv_ic_.resize(p.size());
  double* const inv_ic = roll_inv_ic_.data();
#pragma omp parallel for schedule(static) if (n_grains >= kMinParallelRolling)
  for (std::ptrdiff_t g = 0; g < n_grains; ++g)
    inv_ic[g] = inverse_inertia_at_contact(p.inv_inertia[g], p.mass[g], p.radius[g]);
  // Raw pointers and plain copies, as in the force pass (stores through Eigen may alias).
  const Vec* const x = p.x.data();
  const Rot* const w = p.w.data();
  const double* const radius = p.radius.data();
  const MaterialIndex* const material = p.material.data();
  const std::uint32_t *const pi = pl.i.data(), *const pj = pl.j.data();
  const Vec* const force = pl.force.data();
  const double* const delta = pair_delta_.data();
  Rot* const theta = pl.roll.data();
  Rot* const out = pair_roll_.data();
  const PairTableView materials = w_.materials.pair_view();
  const ContactModel model = w_.model;
  const double dt = w_.dt;
  const double eta = model.rolling_damping;
  const std::uint32_t* const near = near_.index.data();
  const auto n_near = static_cast<std::ptrdiff_t>(near_.index.size());
#pragma omp parallel for schedule(static) if (n_near >= kMinParallelRolling)
  for (std::ptrdiff_t m = 0; m < n_near; ++m) {
    const std::size_t k = near[m];
    const std::uint32_t i = pi[k], j = pj[k];
    const PairParams& pp = materials(material[i], material[j]);
    if (delta[k] <= 0.0 || pp.rolling_friction == 0.0) {  // apart (or no resistance)
      theta[k] = S::zero_rot();
      out[k] = S::zero_rot();
      continue;
    }
    const Vec d = x[i] - x[j];
    const Vec n = d * (1.0 / d.norm());
    const double r_eff = radius[i] * radius[j] / (radius[i] + radius[j]);
    const RollingCoeffs c = rolling_coeffs(pp.rolling_friction, eta, r_eff,
                                           Normal::stiffness(pp, model, delta[k], r_eff),
                                           force[k].dot(n), inv_ic[i], inv_ic[j]);
    out[k] = rolling_moment<D>(n, Rot(w[i] - w[j]), c, dt, theta[k]);
  }
  const auto n_walls = static_cast<std::ptrdiff_t>(wl.size());
#pragma omp parallel for schedule(static) if (n_walls >= kMinParallelRolling)
  for (std::ptrdiff_t kk = 0; kk < n_walls; ++kk) {
    const auto k = static_cast<std::size_t>(kk);
    const std::uint32_t i = wl.i[k];
    const Wall<D>& wall = w_.walls[wl.wall[k]];
    const PairParams& pp = materials(material[i], wall.material);
    const double dk = wall_delta_[k];
    if (dk <= 0.0 || pp.rolling_friction == 0.0) {
      wl.roll[k] = S::zero_rot();
      wall_roll_[k] = S::zero_rot();
      continue;
    }
    Vec n;
    wall.distance(x[i], n);
    const double r = radius[i];
    const RollingCoeffs c =
        rolling_coeffs(pp.rolling_friction, eta, r, Normal::stiffness(pp, model, dk, r),
                       wl.force[k].dot(n), inv_ic[i], 0.0);
    wall_roll_[k] = rolling_moment<D>(n, w[i], c, dt, wl.roll[k]);
  }
  add_rolling_torques();
}

// Each grain's couples, in the accumulation's order: the couple of a contact acts as +M on its
// first grain and -M on its second (and on a wall, which does not turn).
template <int D>
void DemSolver<D>::add_rolling_torques() {
  using S = Space<D>;
  using Rot = typename S::Rot;
  auto& p = w_.particles;
  const auto n = static_cast<std::ptrdiff_t>(p.size());
  Rot* const torque = p.t.data();
  const Rot *const pair_roll = pair_roll_.data(), *const wall_roll = wall_roll_.data();
  const std::uint32_t* const near = near_.index.data();
  const std::uint32_t* const first_begin = near_.first_begin.data();
  const std::uint32_t* const second_begin = near_.second_begin.data();
  const std::uint32_t* const second_pairs = near_.second_pairs.data();
  const std::uint32_t* const wall_begin = w_.neighbors.wall_begin.data();
#pragma omp parallel for schedule(static) if (n >= kMinParallelRolling)
  for (std::ptrdiff_t ii = 0; ii < n; ++ii) {
    const auto i = static_cast<std::size_t>(ii);
    Rot t = S::zero_rot();
    for (std::uint32_t s = second_begin[i]; s < second_begin[i + 1]; ++s)
      t -= pair_roll[second_pairs[s]];
    for (std::uint32_t m = first_begin[i]; m < first_begin[i + 1]; ++m) t += pair_roll[near[m]];
    for (std::uint32_t k = wall_begin[i]; k < wall_begin[i + 1]; ++k) t += wall_roll[k];
    torque[i] += t;
  }
}

template void DemSolver<2>::rolling_torques<HertzNormal>();
template void DemSolver<2>::rolling_torques<LinearNormal>();
template void DemSolver<3>::rolling_torques<HertzNormal>();
template void DemSolver<3>::rolling_torques<LinearNormal>();

}  // namespace sable
