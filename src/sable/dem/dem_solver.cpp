#include "sable/dem/dem_solver.hpp"

#include <fmt/format.h>
#include <cmath>

#include "sable/world/guards.hpp"

namespace sable {

template <int D>
void DemSolver<D>::initialize() {
  w_.neighbors.build(w_.particles, w_.walls);
  compute_forces();
}

// One velocity-Verlet step. Forces at t are known on entry (from the previous step or
// initialize()), so the step is: half kick, drift, contact detection, forces at t + h,
// half kick. Gravity enters as an acceleration in the kicks.
template <int D>
void DemSolver<D>::step() {
  const double h = w_.dt;
  {
    auto scope = timers_.time(Phase::kIntegrate);
    kick(0.5 * h);
    drift(h);
    for (auto& wall : w_.walls) wall.point += h * wall.velocity;
  }
  {
    auto scope = timers_.time(Phase::kNeighbors);
    if (w_.neighbors.needs_rebuild(w_.particles, w_.walls))
      w_.neighbors.build(w_.particles, w_.walls);
  }
  compute_forces();
  {
    auto scope = timers_.time(Phase::kIntegrate);
    kick(0.5 * h);
  }
  w_.time += h;
  ++w_.step;
  check_grain_states(w_);
}

template <int D>
void DemSolver<D>::kick(double h) {
  auto& p = w_.particles;
  const auto g = w_.gravity;
  for (std::size_t k = 0; k < p.size(); ++k) {
    if (p.inv_mass[k] == 0.0) continue;
    p.v[k] += h * (p.f[k] * p.inv_mass[k] + g);
    p.w[k] += h * p.inv_inertia[k] * p.t[k];
  }
}

template <int D>
void DemSolver<D>::drift(double h) {
  auto& p = w_.particles;
  for (std::size_t k = 0; k < p.size(); ++k) {
    if (p.inv_mass[k] == 0.0) continue;
    p.x[k] += h * p.v[k];
    p.q[k] = Space<D>::rotate(p.q[k], p.w[k], h);
  }
}

template <int D>
void DemSolver<D>::compute_forces() {
  auto& p = w_.particles;
  for (std::size_t k = 0; k < p.size(); ++k) {
    p.f[k].setZero();
    p.t[k] = Space<D>::zero_rot();
  }
  diag_ = StepDiagnostics{};
  {
    auto scope = timers_.time(Phase::kForces);
    if (w_.model.normal == NormalModel::kHertz)
      pair_forces<HertzNormal>();
    else
      pair_forces<LinearNormal>();
  }
  {
    auto scope = timers_.time(Phase::kWallForces);
    if (w_.model.normal == NormalModel::kHertz)
      wall_forces<HertzNormal>();
    else
      wall_forces<LinearNormal>();
  }
}

template <int D>
template <class Normal>
void DemSolver<D>::pair_forces() {
  using S = Space<D>;
  auto& p = w_.particles;
  auto& pl = w_.neighbors.pairs;
  const double dt = w_.dt;
  for (std::size_t k = 0; k < pl.size(); ++k) {
    const std::uint32_t i = pl.i[k], j = pl.j[k];
    const typename S::Vec d = p.x[i] - p.x[j];
    const double rsum = p.radius[i] + p.radius[j];
    const double dist2 = d.squaredNorm();
    if (dist2 >= rsum * rsum) {
      // Apart: the contact (if any) has ended and forgets its history.
      pl.shear[k].setZero();
      pl.force[k].setZero();
      continue;
    }
    const double dist = std::sqrt(dist2);
    ContactGeometry<D> g;
    g.n = d / dist;
    g.delta = rsum - dist;
    // Lever arms from each centre to the middle of the overlap.
    const typename S::Vec arm_i = -(p.radius[i] - 0.5 * g.delta) * g.n;
    const typename S::Vec arm_j = (p.radius[j] - 0.5 * g.delta) * g.n;
    g.vrel = p.v[i] + S::spin_velocity(p.w[i], arm_i) - p.v[j] - S::spin_velocity(p.w[j], arm_j);
    g.r_eff = p.radius[i] * p.radius[j] / rsum;
    g.m_eff = 1.0 / (p.inv_mass[i] + p.inv_mass[j]);
    const PairParams& pp = w_.materials.pair(p.material[i], p.material[j]);
    const typename S::Vec f = contact_force<D, Normal>(g, pp, w_.model, dt, pl.shear[k]);
    pl.force[k] = f;
    p.f[i] += f;
    p.f[j] -= f;
    p.t[i] += S::moment(arm_i, f);
    p.t[j] += S::moment(arm_j, -f);
    diag_.max_overlap_ratio =
        std::max(diag_.max_overlap_ratio, g.delta / std::min(p.radius[i], p.radius[j]));
    ++diag_.touching;
  }
}

template <int D>
template <class Normal>
void DemSolver<D>::wall_forces() {
  using S = Space<D>;
  auto& p = w_.particles;
  auto& wl = w_.neighbors.wall_pairs;
  for (auto& wall : w_.walls) wall.force.setZero();
  const double dt = w_.dt;
  for (std::size_t k = 0; k < wl.size(); ++k) {
    const std::uint32_t i = wl.i[k];
    Wall<D>& wall = w_.walls[wl.wall[k]];
    ContactGeometry<D> g;
    const double dist = wall.distance(p.x[i], g.n);
    g.delta = p.radius[i] - dist;
    if (g.delta <= 0.0) {
      wl.shear[k].setZero();
      wl.force[k].setZero();
      continue;
    }
    const typename S::Vec arm_i = -(p.radius[i] - 0.5 * g.delta) * g.n;
    g.vrel = p.v[i] + S::spin_velocity(p.w[i], arm_i) - wall.velocity;
    g.r_eff = p.radius[i];
    g.m_eff = p.mass[i];
    const PairParams& pp = w_.materials.pair(p.material[i], wall.material);
    const typename S::Vec f = contact_force<D, Normal>(g, pp, w_.model, dt, wl.shear[k]);
    wl.force[k] = f;
    p.f[i] += f;
    p.t[i] += S::moment(arm_i, f);
    wall.force -= f;
    diag_.max_overlap_ratio = std::max(diag_.max_overlap_ratio, g.delta / p.radius[i]);
    ++diag_.touching;
  }
}

template class DemSolver<2>;
template class DemSolver<3>;

}  // namespace sable
