#pragma once

#include "sable/dem/dem_solver.hpp"

#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <type_traits>

#include "sable/contact/contact_lanes.hpp"
#include "sable/core/error.hpp"
#include "sable/core/grow.hpp"
#include "sable/dem/grain_pass.hpp"
#include "sable/world/guards.hpp"
#include "sable/world/liquid.hpp"

namespace sable {

namespace dem_detail {

inline constexpr std::uint8_t kBridgeFormed = 1, kBridgeBroken = 2;

// How the grain-pair passes sum forces per grain (see dry_pair_forces and the gather,
// GrainPass::sum): store in the contact's slots only, for the gather (kGather); add to both
// grains (kScatter); add to the grains not flagged kGathered, store for the others
// (kScatterChecked).
enum class Sum : std::uint8_t { kGather, kScatter, kScatterChecked };

}  // namespace dem_detail

template <int D, class Laws>
void DemSolver<D, Laws>::initialize() {
  if (polyhedral()) return polyhedra_->initialize();
  // The lists carry rolling springs exactly when the law has rolling resistance.
  world_.neighbors.rolling = with_rolling();
  build_lists();
  compute_forces();
}

// A World with polyhedral grains is stepped by PolyhedralDem (dem/polyhedral_dem.hpp), made
// on first use.
template <int D, class Laws>
bool DemSolver<D, Laws>::polyhedral() {
  if constexpr (D == 3) {
    if (world_.shapes.empty()) return false;
    if (!polyhedra_) polyhedra_ = std::make_unique<PolyhedralDem>(world_, timers_, diag_);
    return true;
  }
  return false;
}

// One velocity-Verlet step. The forces at t are known on entry (from the previous step or
// initialize()), so a step is: half kick and drift, contact forces at t + h, half kick with
// them. Gravity enters as an acceleration in the kicks. The stages, in order, each a function
// timed as its Phase (the name a summary prints):
//   integrate()          "integrate"  first half kick and drift of the grains; walls drift
//   update_neighbors()   "neighbors"  neighbour list rebuilt when due; near list remade when
//                                     stale
//   pair_pass()          "pair pass"  contact forces at t + h, and each grain's closing: its
//                                     sum, the second half kick, the check of its state (wet
//                                     runs: the bridges' liquid settled, then a closing loop)
//   total_wall_forces()  "closing"    each wall's total force, in list order
// Determinism: each grain's sum adds its terms in one fixed order (its second-member pairs,
// its first-member pairs, its walls, each by ascending index) whichever thread adds them,
// so the bits do not depend on the thread count. No atomics, no per-thread copies of the
// forces: each thread writes only its own grains and contacts.
template <int D, class Laws>
void DemSolver<D, Laws>::step() {
  if (polyhedral()) {  // here too: a resumed run steps without initialize()
    diag_ = StepDiagnostics{};
    return polyhedra_->step();
  }
  const double h = world_.dt;
  diag_ = StepDiagnostics{};
  Displacements moved;
  {
    auto scope = timers_.time(Phase::kIntegrate);
    moved = integrate(h);
  }
  if (domain_->distributed()) {
    auto scope = timers_.time(Phase::kExchange);
    domain_->refresh_ghosts(world_);
    // The lists' tests see every grain's displacement, measured by its owner.
    double m[2] = {moved.neighbor_max2, moved.near_max2};
    domain_->max(m, 2);
    moved = {m[0], m[1]};
  }
  {
    auto scope = timers_.time(Phase::kNeighbors);
    update_neighbors(&moved);
  }
  bool unsound = false;
  {
    auto scope = timers_.time(Phase::kPairPass);
    unsound = pair_pass(0.5 * h);
  }
  {
    auto scope = timers_.time(Phase::kClosing);
    total_wall_forces();
  }
  for (GrainSplit* split : {&opening_split_, &pair_split_, &closing_split_})
    split->end_step();  // the threads' times: the next cuts
  world_.time += h;
  ++world_.step;
  if (unsound) check_grain_states(world_);  // names the first unsound grain and throws
}

// The stages of step() from the lists on, at the current state and with no kick: the
// neighbour list as it is (no drift: the near list measures the displacements itself).
template <int D, class Laws>
void DemSolver<D, Laws>::compute_forces() {
  diag_ = StepDiagnostics{};
  {
    auto scope = timers_.time(Phase::kNeighbors);
    update_neighbors(nullptr);
  }
  {
    auto scope = timers_.time(Phase::kPairPass);
    (void)pair_pass(0.0);
  }
  auto scope = timers_.time(Phase::kClosing);
  total_wall_forces();
}

// Stage integrate: the grains' first half kick and drift (one loop, which also measures the
// displacements the lists' tests need), then the walls' drift.
template <int D, class Laws>
typename DemSolver<D, Laws>::Displacements DemSolver<D, Laws>::integrate(double h) {
  const Displacements moved = kick_and_drift(0.5 * h, h);
  for (auto& wall : world_.walls) wall.advance(h);
  return moved;
}

// Stage update_neighbors: the neighbour list rebuilt when some grain or wall has moved far
// enough that a pair it does not hold could touch, the scratch fitted to it, and the near
// list remade when stale. `moved`: the displacements the opening loop measured (null, from
// compute_forces(): no rebuild, the near list measures them itself).
template <int D, class Laws>
void DemSolver<D, Laws>::update_neighbors(const Displacements* moved) {
  auto& nl = world_.neighbors;
  if (moved && nl.needs_rebuild_after(moved->neighbor_max2, world_.walls)) build_lists();
  nl.update_incidence(world_.particles.size());
  fit_scratch_to_lists();
  update_near_list(moved);
}

// A neighbour-list build: with a decomposition, the grains first go to their owners and the
// ghosts are chosen again; the grains sorted first when due (world/reorder.hpp, counting the
// grains of every process); then the entries among ghosts alone are dropped.
template <int D, class Laws>
void DemSolver<D, Laws>::build_lists() {
  domain_->redistribute(world_);
  reorder_.build_lists(world_, *domain_);
  domain_->after_build(world_);
}

// The per-contact scratch is indexed by list entry: after a rebuild (or a snapshot's lists)
// it starts again from "apart" (-1 marks entries whose stored force must be cleared if they
// are apart, since they may carry a force from before the rebuild). With headroom
// (core/grow.hpp): a settling bed's lists grow at every rebuild.
template <int D, class Laws>
void DemSolver<D, Laws>::fit_scratch_to_lists() {
  const auto& nl = world_.neighbors;
  if (scratch_build_ == nl.builds && pair_delta_.size() == nl.pairs.size() &&
      wall_delta_.size() == nl.wall_pairs.size())
    return;
  const auto zero = Space<D>::zero_rot();
  assign_ahead(pair_moment_, nl.pairs.size(), zero);
  assign_ahead(pair_delta_, nl.pairs.size(), -1.0);
  assign_ahead(wall_moment_, nl.wall_pairs.size(), zero);
  assign_ahead(wall_delta_, nl.wall_pairs.size(), -1.0);
  assign_ahead(pair_event_, nl.bridges ? nl.pairs.size() : 0, std::uint8_t{0});
  assign_ahead(pair_roll_, nl.rolling ? nl.pairs.size() : 0, zero);
  assign_ahead(wall_roll_, nl.rolling ? nl.wall_pairs.size() : 0, zero);
  const bool meshes = std::any_of(world_.walls.begin(), world_.walls.end(),
                                  [](const Wall<D>& w) { return w.is_mesh(); });
  assign_ahead(feature_, meshes ? nl.wall_pairs.size() : 0, WallFeature<D>{});
  assign_ahead(hand_over_, meshes ? nl.wall_pairs.size() : 0, std::uint8_t{0});
  scratch_build_ = nl.builds;
}

// The near list remade when it may no longer hold every pair that can touch
// (dem/near_list.hpp). An entry it leaves out is apart: cleared as the pair pass would clear
// it.
template <int D, class Laws>
void DemSolver<D, Laws>::update_near_list(const Displacements* moved) {
  auto& nl = world_.neighbors;
  const bool wet = wet_run(), rolling = with_rolling();
  const bool remade = moved ? near_.stale_after(moved->near_max2, world_.particles, nl, wet)
                            : near_.stale(world_.particles, nl, wet, *domain_);
  if (remade) {
    near_.remake(world_.particles, nl, world_.dt, wet, *domain_, [&](std::size_t k) {
      dem_detail::forget_if_ended(nl.pairs.shear.data(), nl.pairs.force.data(), pair_moment_.data(),
                                  pair_delta_.data(), k, Space<D>::zero_rot());
      if (rolling) {
        nl.pairs.roll[k] = Space<D>::zero_rot();
        pair_roll_[k] = Space<D>::zero_rot();
      }
    });
  }
  diag_.near_remakes = near_.remakes;
  if (!feature_.empty()) update_mesh_reach(remade);
}

// Stage pair_pass: per contact of the near list, its force at the current positions, stored
// in its own slot with n x F and the overlap (for the torques); then each grain's closing:
// its wall contacts, its sum, the half kick by h_kick (none when 0) and the check of its
// state. Dry runs sum and close each grain inside the pass (dry_pair_forces); wet runs store
// every force, settle the bridges' liquid, then close every grain in a loop of their own
// (closing_loop). True when some grain's state is unsound after the kick.
template <int D, class Laws>
bool DemSolver<D, Laws>::pair_pass(double h_kick) {
  const bool wet = wet_run(), rolling = with_rolling();
  if (rolling) prepare_rolling(wet);
  const bool unsound = pair_forces_for_law(h_kick, wet, rolling);
  if (!wet) return unsound;
  settle_liquid();
  return closing_loop_for_law(h_kick);
}

// The pair forces for the World's contact law: the pass is compiled once per law of the
// table, and the law is chosen here, once per pass, never per contact. True when some grain's
// state is unsound after the kick (the dry pass closes its grains).
template <int D, class Laws>
bool DemSolver<D, Laws>::pair_forces_for_law(double h_kick, bool wet, bool rolling) {
  return Laws::visit(world_.model.normal, [&]<class Law>() {
    if (wet) {
      wet_pair_forces<Law>();
      return false;
    }
    return rolling ? dry_pair_forces<Law, true>(h_kick) : dry_pair_forces<Law, false>(h_kick);
  });
}

// The wet runs' closing loop for the World's contact law (its wall contacts).
template <int D, class Laws>
bool DemSolver<D, Laws>::closing_loop_for_law(double h_kick) {
  return Laws::visit(world_.model.normal, [&]<class Law>() { return closing_loop<Law>(h_kick); });
}

// Before a pass with rolling resistance: each grain's 1 / (I + m R^2), once per step rather
// than twice per contact. (The lists hold one spring per entry whenever NeighborList::rolling
// is set: build() and load_snapshot() keep them so.) The wet pass has no couple (the scenario
// parser refuses the pair).
template <int D, class Laws>
void DemSolver<D, Laws>::prepare_rolling(bool wet) {
  const auto& p = world_.particles;
  if (wet) throw InputError("rolling resistance with capillary bridges is not supported yet");
  const auto n = static_cast<std::ptrdiff_t>(p.size());
  roll_inv_ic_.resize(p.size());
  double* const inv_ic = roll_inv_ic_.data();
#pragma omp parallel for schedule(static) if (n >= kMinParallelItems)
  for (std::ptrdiff_t g = 0; g < n; ++g)
    inv_ic[g] = inverse_inertia_at_contact(p.inv_inertia[g], p.mass[g], p.radius[g]);
}

// What the grain-pair passes read and write, as raw pointers and plain copies taken once per
// pass. Reached through `this` and std::vector instead, every store of a force (Eigen's SSE
// stores may alias anything) makes the compiler fetch each array's address again: 4 % more
// instructions in the pass (cachegrind on bench/ab_dense.sh's dense bed). Each thread works
// on its own copy (firstprivate).
template <int D, class Laws>
struct DemSolver<D, Laws>::PairPass {
  using S = Space<D>;
  using Vec = typename S::Vec;
  using Rot = typename S::Rot;
  const Vec *x, *v;
  const Rot* omega;  // the grains' spins
  const double *radius, *inv_mass;
  const MaterialIndex* material;
  const std::uint32_t *i, *j;
  Vec *shear, *force;
  Rot* moment;
  double* delta;
  // The dry pass adds forces and torques to grains as it goes (see dry_pair_forces), except
  // to the grains flagged kGathered, which the gather (GrainPass::sum) sums from the
  // contacts' slots.
  Vec* grain_force;
  Rot* grain_torque;
  const std::uint8_t* flags;  // per grain: kGathered, kInTail
  const std::uint32_t *second_begin, *second_pairs;
  PairTableView materials;
  ContactModel model;
  double dt;
  // Rolling resistance only (dry_pair_forces<Normal, true>): the springs, each contact's couple on
  // its first grain (for the gather), and each grain's 1 / (I + m R^2).
  Rot *roll, *couple;
  const double* inv_ic;

  template <bool Roll = false>
  void forget(std::size_t k) const {
    if (delta[k] == 0.0) return;  // apart already: everything is zero
    if constexpr (Roll) {
      roll[k] = S::zero_rot();
      couple[k] = S::zero_rot();
    }
    dem_detail::forget_if_ended(shear, force, moment, delta, k, S::zero_rot());
  }

  // The rolling couple of touching pair k on grain a (contact/rolling.hpp), from the force
  // pass's geometry and force; stored for the gather.
  template <class Normal>
  [[gnu::always_inline]] Rot rolling_couple(std::size_t k, std::uint32_t a, std::uint32_t b,
                                            const ContactGeometry<D>& g, const PairParams& pp,
                                            const Vec& f) const {
    Rot m = sable::rolling_couple<D, Normal>(g, pp, model, dt, f, Rot(omega[a] - omega[b]),
                                             inv_ic[a], inv_ic[b], roll[k]);
    couple[k] = m;
    return m;
  }

  // Zero the sums of grains [g0, g1) (this thread's block), before the pass adds to them.
  void clear_sums(std::uint32_t g0, std::uint32_t g1) const {
    for (std::uint32_t g = g0; g < g1; ++g) {
      grain_force[g] = S::zero();
      grain_torque[g] = S::zero_rot();
    }
  }

  // The force of touching pair k (centre offset d = x_i - x_j, |d|^2 = dist2 < rsum^2), with
  // `cohesion` (<= 0) added to its normal force, stored in the pair's slots (n x F only where
  // the gather will read it: `How`), and summed per grain as `How` says; raises max_ratio
  // to the overlap over the smaller radius. Shared by the dry and the wet passes.
  template <class Normal, dem_detail::Sum How = dem_detail::Sum::kGather, bool Roll = false>
  [[gnu::always_inline]] void touch(std::size_t k, const Vec& d, double dist2, double rsum,
                                    double cohesion, double& max_ratio) const {
    const std::uint32_t a = i[k], b = j[k];
    const double dist = std::sqrt(dist2);
    ContactGeometry<D> g;
    g.n = d * (1.0 / dist);  // one division, not three
    g.delta = rsum - dist;
    // Lever arms from each centre to the middle of the overlap: -(R_i - delta/2) n for i,
    // +(R_j - delta/2) n for j, so the contact points' velocity difference is
    // v_i - v_j - ((R_i - delta/2) omega_i + (R_j - delta/2) omega_j) x n: one cross product.
    const double lever_i = radius[a] - 0.5 * g.delta, lever_j = radius[b] - 0.5 * g.delta;
    g.vrel = v[a] - v[b] - S::spin_velocity(lever_i * omega[a] + lever_j * omega[b], g.n);
    g.r_eff = radius[a] * radius[b] / rsum;
    g.m_eff = 1.0 / (inv_mass[a] + inv_mass[b]);
    const PairParams& pp = materials(material[a], material[b]);
    const Vec f = contact_force<D, Normal>(g, pp, model, dt, shear[k], cohesion);
    const Rot m = S::moment(g.n, f);
    Rot c = S::zero_rot();  // the rolling couple on a (b gets -c)
    if constexpr (Roll) c = rolling_couple<Normal>(k, a, b, g, pp, f);
    add<How, Roll>(k, a, b, f, m, c, lever_i, lever_j, g.delta, max_ratio);
  }

  // Touching pair k's force f on grain a, n x F = m, rolling couple c and overlap: stored in
  // its slots (n x F only where the gather will read it: `How`) and summed per grain as
  // `How` says; raises max_ratio to the overlap over the smaller radius.
  template <dem_detail::Sum How, bool Roll>
  [[gnu::always_inline]] void add(std::size_t k, std::uint32_t a, std::uint32_t b, const Vec& f,
                                  const Rot& m, const Rot& c, double lever_i, double lever_j,
                                  double overlap, double& max_ratio) const {
    force[k] = f;
    delta[k] = overlap;
    if constexpr (How == dem_detail::Sum::kScatter) {
      // Term for term as the gather would add them (see GrainPass::sum for the torques).
      grain_force[a] += f;
      grain_torque[a] -= lever_i * m;
      if constexpr (Roll) grain_torque[a] += c;
      grain_force[b] -= f;
      grain_torque[b] -= lever_j * m;
      if constexpr (Roll) grain_torque[b] -= c;
    } else if constexpr (How == dem_detail::Sum::kScatterChecked) {
      const std::uint8_t flag_a = flags[a] & kGathered, flag_b = flags[b];
      if (!flag_a) {
        grain_force[a] += f;
        grain_torque[a] -= lever_i * m;
        if constexpr (Roll) grain_torque[a] += c;
      }
      if (!(flag_b & kGathered)) {
        grain_force[b] -= f;
        grain_torque[b] -= lever_j * m;
        if constexpr (Roll) grain_torque[b] -= c;
      }
      // The gather reads n x F for a gathered grain, and for one in a tail that another
      // thread may take (a's own entries are then that thread's to do, not this pass's).
      if (flag_a | flag_b) moment[k] = m;
    } else {
      moment[k] = m;
    }
    const double r_min = std::min(radius[a], radius[b]);
    if (overlap > max_ratio * r_min) max_ratio = overlap / r_min;
  }

  // The dry pass over near-list entries [m0, m1) (see dry_pair_forces). Flattened: left to
  // its heuristics, GCC keeps some of Eigen's vector operations out of line here once the
  // translation unit holds a little more code, and the pass then takes 14 % more instructions
  // (cachegrind on bench/ab_dense.sh's dense bed).
  template <class Normal, dem_detail::Sum How, bool Roll>
  [[gnu::flatten]] void entries(const std::uint32_t* near, std::uint32_t m0, std::uint32_t m1,
                                double& max_ratio, std::size_t& touching) const {
    for (std::uint32_t m = m0; m < m1; ++m) {
      const std::size_t k = near[m];
      const Vec d = x[i[k]] - x[j[k]];
      const double rsum = radius[i[k]] + radius[j[k]];
      const double dist2 = d.squaredNorm();
      if (dist2 >= rsum * rsum) {
        forget<Roll>(k);
        continue;
      }
      touch<Normal, How, Roll>(k, d, dist2, rsum, 0.0, max_ratio);
      ++touching;
    }
  }

  // The dry pass for the Hertz law in 3D without rolling resistance (the pour's): the
  // touching entries of each stretch of the list go into lanes, their forces are computed as
  // one batch in SIMD registers (contact/contact_lanes.hpp), then stored and added to the
  // grains one by one in list order, as entries() does: the same bits, and a quarter less
  // time in the pass (bench/ab_dense.sh -t 1 measures it).
  template <dem_detail::Sum How>
  [[gnu::flatten]] void entries_in_lanes(const std::uint32_t* near, std::uint32_t m0,
                                         std::uint32_t m1, double& max_ratio,
                                         std::size_t& touching) const requires(D == 3) {
    ContactLanes lanes;  // on the stack: each thread its own
    for (std::uint32_t m = m0; m < m1;) {
      int n = 0;
      for (; m < m1 && n < ContactLanes::kWidth; ++m) {
        const std::size_t k = near[m];
        const std::uint32_t a = i[k], b = j[k];
        const Vec d = x[a] - x[b];
        const double rsum = radius[a] + radius[b];
        const double dist2 = d.squaredNorm();
        if (dist2 >= rsum * rsum) {
          forget(k);
          continue;
        }
        fill(lanes, n++, k, a, b, d, dist2, rsum);
      }
      contact_lanes_hertz(lanes, n, model, dt);
      for (int l = 0; l < n; ++l) {
        const auto k = static_cast<std::size_t>(lanes.entry[l]);
        shear[k] = Vec(lanes.sx[l], lanes.sy[l], lanes.sz[l]);
        add<How, false>(k, lanes.a[l], lanes.b[l], Vec(lanes.fx[l], lanes.fy[l], lanes.fz[l]),
                        Rot(lanes.mx[l], lanes.my[l], lanes.mz[l]), S::zero_rot(), lanes.lever_a[l],
                        lanes.lever_b[l], lanes.delta[l], max_ratio);
      }
      touching += static_cast<std::size_t>(n);
    }
  }

  // The entries whose first member is one of grains [g0, g1) (begin: first_begin), summed as
  // `How` says: in SIMD lanes for the Hertz law in 3D without rolling resistance, else one
  // by one. The same bits either way.
  template <class Normal, dem_detail::Sum How, bool Roll>
  [[gnu::always_inline]] void entries_of_grains(const std::uint32_t* near,
                                                const std::uint32_t* begin, std::uint32_t g0,
                                                std::uint32_t g1, double& max_ratio,
                                                std::size_t& touching) const {
    if constexpr (D == 3 && std::is_same_v<Normal, HertzNormal> && !Roll)
      entries_in_lanes<How>(near, begin[g0], begin[g1], max_ratio, touching);
    else
      entries<Normal, How, Roll>(near, begin[g0], begin[g1], max_ratio, touching);
  }

  // Lane l of `lanes` from touching entry k (grains a, b; d = x_a - x_b). A member template:
  // the explicit instantiation of DemSolver<2> must not instantiate it, and clang 14 does so
  // for a constrained member that is not a template.
  template <int E = D>
  [[gnu::always_inline]] void fill(ContactLanes& lanes, int l, std::size_t k, std::uint32_t a,
                                   std::uint32_t b, const Vec& d, double dist2, double rsum) const
      requires(E == 3) {
    lanes.entry[l] = static_cast<std::uint32_t>(k);
    lanes.a[l] = a;
    lanes.b[l] = b;
    lanes.dx[l] = d.x();
    lanes.dy[l] = d.y();
    lanes.dz[l] = d.z();
    lanes.dist2[l] = dist2;
    lanes.rsum[l] = rsum;
    lanes.ra[l] = radius[a];
    lanes.rb[l] = radius[b];
    lanes.inv_mass_a[l] = inv_mass[a];
    lanes.inv_mass_b[l] = inv_mass[b];
    const Vec dv = v[a] - v[b];
    lanes.dvx[l] = dv.x();
    lanes.dvy[l] = dv.y();
    lanes.dvz[l] = dv.z();
    lanes.wax[l] = omega[a].x();
    lanes.way[l] = omega[a].y();
    lanes.waz[l] = omega[a].z();
    lanes.wbx[l] = omega[b].x();
    lanes.wby[l] = omega[b].y();
    lanes.wbz[l] = omega[b].z();
    lanes.set_params(l, materials(material[a], material[b]));
    lanes.sx[l] = shear[k].x();
    lanes.sy[l] = shear[k].y();
    lanes.sz[l] = shear[k].z();
  }
};

template <int D, class Laws>
typename DemSolver<D, Laws>::PairPass DemSolver<D, Laws>::make_pair_pass() {
  auto& p = world_.particles;
  auto& pl = world_.neighbors.pairs;
  return {p.x.data(),
          p.v.data(),
          p.omega.data(),
          p.radius.data(),
          p.inv_mass.data(),
          p.material.data(),
          pl.i.data(),
          pl.j.data(),
          pl.shear.data(),
          pl.force.data(),
          pair_moment_.data(),
          pair_delta_.data(),
          p.f.data(),
          p.t.data(),
          grain_flags_.data(),
          near_.second_begin.data(),
          near_.second_pairs.data(),
          world_.materials.pair_view(),
          world_.model,
          world_.dt,
          pl.roll.data(),
          pair_roll_.data(),
          roll_inv_ic_.data()};
}

// The dry pass. Each thread takes a contiguous block of grains, about an equal share of the
// near list, and the entries whose first member is one of them (the list is sorted by first
// member). It adds each contact's force and torque to the two grains as it goes, in list
// order; a grain's terms come in the order the gather sums them (second-member entries,
// whose first member is smaller, then first-member ones), so the sums are the same bits for
// any number of threads. Only the grains another block's entries reach (flagged kGathered
// by update_pair_split(); none on one thread, a few % on two) are left to the gather: a
// gather of every grain's sum would take 17 % of a one-thread step (perf on bench/ab_dense.sh's
// dense bed). The blocks and flags change only between passes (update_pair_split(): after a
// near-list remake, or when the threads' speeds move the cut).
//
// The closing (walls, sums, half kick by h_kick, check: close_passed_grains()) follows every
// kCloseChunk grains: an entry (i, j) has i < j, so once the pass is past grain g nothing
// in it adds to g or reads it again: g's sum is final, and its data are still in the caches
// (a separate loop would read every grain again, and on two threads lines the other core has
// written: bench/ab_dense.sh -s runs 4-16 % faster on two threads with the closing here).
//
// The last kPairTail of each block's work (its tail) is shared (dem/grain_split.hpp): the
// block's thread takes it from the front, in chunks, adding and closing as before; a thread
// done with its own block takes chunks from the far end, whose entries only store their
// forces (Sum::kGather; the pass writes n x F for every entry whose second member lies in a
// tail, kInTail, since either end may take it). After the pass, the threads meeting once,
// the grains left to the gather are closed (close_gathered_chunks()): the flagged ones, and in
// each block those from where its tail's two ends met. Their wall contacts were made by
// whoever did their rows. True when some grain's state is unsound after the kick.
template <int D, class Laws>
template <class Normal, bool Roll>
bool DemSolver<D, Laws>::dry_pair_forces(double h_kick) {
  // The pass clears its grains' sums (clear_sums()) as well as visiting the entries: a bed
  // with few contacts is still worth the threads, and clearing them all on one thread would
  // leave the other threads' grains in its cache for the next kick.
  update_pair_split();
  GrainSplit& split = pair_split_;
  const int blocks = split.blocks();
  split.open_chunks();
  PairPass pass = make_pair_pass();
  GrainPass closing = make_grain_pass(h_kick);
  const std::uint32_t* const near = near_.index.data();
  const std::uint32_t* const begin = near_.first_begin.data();
  const std::uint32_t* const block = split.bounds();
  std::atomic<std::uint32_t> next_gathered{0};  // close_gathered_chunks()'s chunks
  double max_ratio = 0.0;
  std::size_t touching = 0;
  int bad = 0;
#pragma omp parallel num_threads(blocks) firstprivate(pass, closing) reduction(max : max_ratio) \
    reduction(+ : touching) reduction(| : bad) if (blocks > 1)
  {
    // A block per thread; with fewer threads than blocks, some take two: the same bits.
    const int team = omp_get_num_threads(), thread = omp_get_thread_num();
    // Grains [r0, r1) of this thread's block: their entries, added to the sums as the pass
    // goes, then their closing, every kCloseChunk grains (their data still in the caches).
    auto add_and_close = [&](std::uint32_t r0, std::uint32_t r1) {
      while (r0 < r1) {
        const std::uint32_t r = r1 - r0 > kCloseChunk ? r0 + kCloseChunk : r1;
        // One block: no grain is gathered, and the flags need not be read.
        if (blocks == 1)
          pass.template entries_of_grains<Normal, dem_detail::Sum::kScatter, Roll>(
              near, begin, r0, r, max_ratio, touching);
        else
          pass.template entries_of_grains<Normal, dem_detail::Sum::kScatterChecked, Roll>(
              near, begin, r0, r, max_ratio, touching);
        bad |= close_passed_grains<Normal>(closing, r0, r, h_kick, max_ratio, touching);
        r0 = r;
      }
    };
    std::uint32_t c0 = 0, c1 = 0;
    for (int t = thread; t < blocks; t += team) {
      const double start = omp_get_wtime();
      const std::uint32_t g0 = block[t], tail = split.tail(t);
      pass.clear_sums(g0, block[t + 1]);
      add_and_close(g0, tail);
      double work = double(begin[tail] - begin[g0]) + double(tail - g0);  // the cut's units
      while (split.take_chunk(t, c0, c1)) {
        add_and_close(c0, c1);
        work += double(begin[c1] - begin[c0]) + double(c1 - c0);
      }
      if (team == blocks) split.add_busy(t, omp_get_wtime() - start, work);
    }
    // Then the other blocks' tails, from their far ends: those entries only store their
    // forces, and their grains are closed after the pass.
    for (int k = 1; k < blocks; ++k) {
      const int t = (thread + k) % blocks;
      while (split.take_chunk_from_back(t, c0, c1)) {
        pass.template entries_of_grains<Normal, dem_detail::Sum::kGather, Roll>(
            near, begin, c0, c1, max_ratio, touching);
        wall_contacts<Normal>(c0, c1, max_ratio, touching);
      }
    }
    if (blocks > 1) {
#pragma omp barrier
      bad |= close_gathered_chunks(closing, next_gathered, h_kick);
    }
  }
  diag_.max_overlap_ratio = std::max(diag_.max_overlap_ratio, max_ratio);
  diag_.touching += touching;
  return bad != 0;
}

// The pair pass's blocks of grains (dem/grain_split.hpp), cut again after a near-list remake,
// when the grain or the thread count changed, or when the threads' measured speeds ask for
// it. Each block gets its share of the work: its near-list entries, plus one per grain
// (clear_sums() zeroes each grain's sums). Cut by entries alone, a bed whose contacts sit in
// a few grains (a fall, where only the landed layers touch) would give one thread nearly
// every grain (bench/peers/compare.sh --stiff, phase (a): two threads 1.03-1.08x as fast as
// one cut by entries, 1.53-1.56x cut by work). Then the flags: a grain is
// kGathered when it is the second member of an entry whose first member is in an earlier
// block (its first such entry has the smallest first member): that block's thread would add
// to it, in a race and out of order; kInTail for the grains of a block's shared tail, which
// another thread may take (dry_pair_forces). The kGathered grains are also listed, for their
// closing after the pass. (Grains the near list does not hold are cut by count, and the cut
// is made again once it holds them; the pass always finds them held.)
template <int D, class Laws>
void DemSolver<D, Laws>::update_pair_split() {
  const std::size_t n = world_.particles.size();
  const std::size_t items = near_.index.size() + n;
  const int blocks = items >= kMinParallelItems ? omp_get_max_threads() : 1;
  if (split_remake_ == near_.remakes && pair_split_.fits(n, blocks)) return;
  const auto& begin = near_.first_begin;  // n + 1 offsets when the list holds every grain
  pair_split_.cut(n, blocks, begin);
  grain_flags_.assign(n, 0);
  gathered_list_.clear();
  if (begin.size() != n + 1) {
    split_remake_ = ~std::uint64_t{0};
    return;
  }
  const auto& sb = near_.second_begin;
  const auto& first = world_.neighbors.pairs.i;
  const std::uint32_t* const bound = pair_split_.bounds();
  for (int t = 0; t < blocks; ++t) {
    const std::uint32_t tail = pair_split_.tail(t);
    for (std::uint32_t g = bound[t]; g < bound[t + 1]; ++g)
      grain_flags_[g] =
          (sb[g] < sb[g + 1] && first[near_.second_pairs[sb[g]]] < bound[t] ? kGathered : 0) |
          (g >= tail ? kInTail : 0);
  }
  for (std::uint32_t g = 0; g < n; ++g)
    if (grain_flags_[g] & kGathered) gathered_list_.push_back(g);
  split_remake_ = near_.remakes;
}

// A grain loop's blocks: each loop has its own, cut by grain count and timed alone, so that
// each loop's threads finish together (the opening loop's work is even per grain, the closing
// loop's is not: wall contacts, gathered grains; one cut balancing the sum of the loops would
// leave each loop's threads waiting for one another in turn).
template <int D, class Laws>
GrainSplit& DemSolver<D, Laws>::grain_loop_split(GrainSplit& split) {
  const std::size_t n = world_.particles.size();
  const bool team = static_cast<std::ptrdiff_t>(n) >= kMinParallelItems;
  const int blocks = team ? omp_get_max_threads() : 1;
  if (!split.fits(n, blocks)) split.cut(n, blocks, {});
  return split;
}

// The grain-pair pass with capillary bridges. As dry_pair_forces, plus: a bridged pair that has
// separated feels the bridge's attraction until its gap exceeds the rupture distance; a
// touching pair gets the contact attraction -kappa R, and a bridge if it had none (formation
// is only recorded here; the liquid moves in settle_liquid, in list order, so the result does
// not depend on the number of threads). The force at contact does not depend on the volume.
template <int D, class Laws>
template <class Normal>
void DemSolver<D, Laws>::wet_pair_forces() {
  using S = Space<D>;
  const auto& p = world_.particles;
  auto& pl = world_.neighbors.pairs;
  const CapillaryParams& cap = world_.model.capillary;
  const double kappa = Capillary::kappa(cap);
  const bool forming = world_.liquid.wet();
  PairPass pass = make_pair_pass();
  const std::uint32_t* const near = near_.index.data();  // every entry: a wet run keeps all
  const auto n_near = static_cast<std::ptrdiff_t>(near_.index.size());
  double max_ratio = 0.0;
  std::size_t touching = 0, events = 0;
#pragma omp parallel for schedule(static) firstprivate(pass) reduction(max : max_ratio) \
    reduction(+ : touching, events) if (n_near >= kMinParallelItems)
  for (std::ptrdiff_t m = 0; m < n_near; ++m) {
    const std::size_t k = near[m];
    const std::uint32_t i = pl.i[k], j = pl.j[k];
    const typename S::Vec d = p.x[i] - p.x[j];
    const double rsum = p.radius[i] + p.radius[j];
    const double dist2 = d.squaredNorm();
    const double volume = pl.bridge[k];
    if (dist2 >= rsum * rsum) {
      const double gap = std::sqrt(dist2) - rsum;
      if (volume < 0.0 || !Capillary::holds(cap, volume, gap)) {
        if (volume >= 0.0) {
          pair_event_[k] = dem_detail::kBridgeBroken;
          ++events;
        }
        pass.forget(k);
        continue;
      }
      pl.shear[k].setZero();
      const double f0 = -kappa * std::sqrt(p.radius[i] * p.radius[j]);
      const double decay = Capillary::decay_length(cap, p.radius[i], p.radius[j], volume);
      pl.force[k] = f0 * std::exp(-gap / decay) / (gap + rsum) * d;
      pair_moment_[k] = S::zero_rot();  // along the line of centres: no torque
      pair_delta_[k] = -1.0;            // a stored force to clear when the bridge breaks
      continue;
    }
    if (volume < 0.0 && forming) {
      pair_event_[k] = dem_detail::kBridgeFormed;
      ++events;
    }
    const double cohesion =
        volume >= 0.0 || forming ? -kappa * std::sqrt(p.radius[i] * p.radius[j]) : 0.0;
    pass.template touch<Normal>(k, d, dist2, rsum, cohesion, max_ratio);
    ++touching;
  }
  diag_.max_overlap_ratio = std::max(diag_.max_overlap_ratio, max_ratio);
  diag_.touching += touching;
  events_ = events;
}

}  // namespace sable

#include "sable/dem/bridge_liquid_impl.hpp"
#include "sable/dem/grain_loops_impl.hpp"
#include "sable/dem/wall_contacts_impl.hpp"
