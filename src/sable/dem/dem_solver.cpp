#include "sable/dem/dem_solver.hpp"

#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "sable/contact/liquid.hpp"
#include "sable/core/error.hpp"
#include "sable/dem/passes.hpp"
#include "sable/world/guards.hpp"

namespace sable {

// Below this many grains or contacts a loop runs on one thread: waking a thread team costs
// more than the work. The result is the same bits either way.
constexpr std::ptrdiff_t kMinParallelItems = 2048;
constexpr std::uint8_t kBridgeFormed = 1, kBridgeBroken = 2;

// The opening half's maxima and flag, reduced over threads (exact: the same for any count).
#pragma omp declare reduction(drift_max       \
                              : dem::DriftMax \
                              : omp_out.merge(omp_in)) initializer(omp_priv = dem::DriftMax{})

template <int D>
void DemSolver<D>::initialize() {
  // The lists carry rolling springs exactly when the law has rolling resistance.
  w_.neighbors.rolling = w_.model.rolling != RollingModel::kNone;
  w_.neighbors.build(w_.particles, w_.walls);
  compute_forces();
}

// One velocity-Verlet step. Forces at t are known on entry (from the previous step or
// initialize()), so the step is: half kick and drift, contact detection, forces at t + h,
// half kick. Gravity enters as an acceleration in the kicks. Each pass over the grains does
// all it can: the drift measures how far the grains moved for the lists' staleness tests and
// checks the positions, and the closing half kick (with the guard on each grain's velocities)
// runs in the force pass's last loop, on each grain as soon as its sum is known.
template <int D>
void DemSolver<D>::step() {
  const double h = w_.dt;
  dem::DriftMax moved;
  {
    auto scope = timers_.time(Phase::kIntegrate);
    moved = kick_drift(0.5 * h, h);
    for (auto& wall : w_.walls) wall.point += h * wall.velocity;
  }
  {
    auto scope = timers_.time(Phase::kNeighbors);
    if (w_.neighbors.needs_rebuild_after(moved.since_build, w_.particles, w_.walls))
      w_.neighbors.build(w_.particles, w_.walls);
  }
  const bool sound = forces(moved.since_near, 0.5 * h) && !moved.bad;
  w_.time += h;
  ++w_.step;
  if (!sound) check_grain_states(w_);  // names the first bad grain and throws
}

// The grain loops below copy the arrays' addresses into locals first: through
// w_.particles every store of a vector (Eigen's SSE stores may alias anything) would make
// the compiler fetch each array's address again (see PairPass).

// A step's opening half in a loop of its own (dem::DriftPass): the half kick by h and the
// drift by h_drift.
template <int D>
dem::DriftMax DemSolver<D>::kick_drift(double h, double h_drift) {
  const dem::DriftPass<D> pass = drift_pass(h, h_drift);
  const auto n = static_cast<std::ptrdiff_t>(w_.particles.size());
  dem::DriftMax moved;
#pragma omp parallel for schedule(static) reduction(drift_max : moved) if (n >= kMinParallelItems)
  for (std::ptrdiff_t k = 0; k < n; ++k) pass.grain(static_cast<std::size_t>(k), moved);
  return pass.settle(moved);
}

template <int D>
dem::DriftPass<D> DemSolver<D>::drift_pass(double h, double h_drift) {
  auto& p = w_.particles;
  const auto& build_ref = w_.neighbors.x_ref;
  const auto& near_ref = near_.reference();
  return {p.x.data(),
          p.v.data(),
          p.q.data(),
          p.w.data(),
          p.f.data(),
          p.t.data(),
          p.inv_mass.data(),
          p.inv_inertia.data(),
          build_ref.size() == p.size() ? build_ref.data() : nullptr,
          near_ref.size() == p.size() ? near_ref.data() : nullptr,
          w_.gravity,
          h,
          h_drift,
          w_.viscous_rate > 0.0 ? 1.0 / (1.0 + w_.viscous_rate * h) : 1.0,
          w_.track_orientation};
}

// Forces so that the result does not depend on the number of threads:
//   1. per contact of the near list (the candidates that can touch now, see
//      dem/near_list.hpp): the force on its first grain, written into the contact's own slot
//      together with n x F and the overlap (for the torques), and in the dry pass added to
//      its grains' sums as it goes (dry_forces: one block of grains per thread);
//   2. per wall contact, its force in its slot (WallPass);
//   3. per grain (GrainPass::finish): for the grains the pass did not sum, the sum of its
//      contacts' forces and torques, in the same order (second-member pairs, first-member
//      pairs, wall pairs, by ascending index); with h_kick > 0 the closing half kick, and
//      the guard on the grain's state (false returned if some grain fails it).
// No atomics, no per-thread force copies, and no race: each thread writes only its own items.
// near_moved2: the grains' largest squared displacement since the near list's remake, if
// known (< 0: measured here).
template <int D>
bool DemSolver<D>::forces(double near_moved2, double h_kick) {
  auto& nl = w_.neighbors;
  nl.update_incidence(w_.particles.size());
  fit_scratch();
  diag_ = StepDiagnostics{};
  const bool wet = nl.bridges && nl.pairs.bridge.size() == nl.pairs.size();
  const bool rolling = w_.model.rolling != RollingModel::kNone;
  if (rolling) prepare_rolling(wet);
  refresh_near(near_moved2, wet, rolling);
  gathered_.resize(w_.particles.size());
  const dem::GrainPass<D> grains = grain_pass(wet, h_kick);
  const bool hertz = w_.model.normal == NormalModel::kHertz;
  bool sound = true;
  if (wet)
    sound = hertz ? wet_forces<HertzNormal>(grains) : wet_forces<LinearNormal>(grains);
  else if (rolling)
    sound = hertz ? dry_forces<HertzNormal, true>(grains) : dry_forces<LinearNormal, true>(grains);
  else
    sound =
        hertz ? dry_forces<HertzNormal, false>(grains) : dry_forces<LinearNormal, false>(grains);
  sum_wall_forces();
  return sound;
}

// The scratch is indexed by list entry: after a rebuild (or a snapshot's lists) it starts
// again from "apart" (-1 marks entries whose stored force must be cleared if they are apart,
// since they may carry a force from before the rebuild).
template <int D>
void DemSolver<D>::fit_scratch() {
  const auto& nl = w_.neighbors;
  if (scratch_build_ == nl.builds && pair_delta_.size() == nl.pairs.size() &&
      wall_delta_.size() == nl.wall_pairs.size())
    return;
  pair_moment_.assign(nl.pairs.size(), Space<D>::zero_rot());
  pair_delta_.assign(nl.pairs.size(), -1.0);
  wall_moment_.assign(nl.wall_pairs.size(), Space<D>::zero_rot());
  wall_delta_.assign(nl.wall_pairs.size(), -1.0);
  pair_event_.assign(nl.bridges ? nl.pairs.size() : 0, 0);
  pair_roll_.assign(nl.rolling ? nl.pairs.size() : 0, Space<D>::zero_rot());
  wall_roll_.assign(nl.rolling ? nl.wall_pairs.size() : 0, Space<D>::zero_rot());
  scratch_build_ = nl.builds;
}

// Remake the near list if it is stale. An entry left out is apart: cleared as the force pass
// would have.
template <int D>
void DemSolver<D>::refresh_near(double near_moved2, bool wet, bool rolling) {
  auto scope = timers_.time(Phase::kNeighbors);
  auto& nl = w_.neighbors;
  const auto& p = w_.particles;
  const bool stale =
      near_moved2 >= 0.0 ? near_.stale_after(near_moved2, p, nl, wet) : near_.stale(p, nl, wet);
  if (stale) {
    near_.remake(p, nl, w_.dt, wet, [&](std::size_t k) {
      dem::forget_if_ended(nl.pairs.shear.data(), nl.pairs.force.data(), pair_moment_.data(),
                           pair_delta_.data(), k, Space<D>::zero_rot());
      if (rolling) {
        nl.pairs.roll[k] = Space<D>::zero_rot();
        pair_roll_[k] = Space<D>::zero_rot();
      }
    });
  }
  diag_.near_remakes = near_.remakes;
}

// Before a pass with rolling resistance: each grain's 1 / (I + m R^2), once per step rather
// than twice per contact. (The lists hold one spring per entry whenever NeighborList::rolling
// is set: build() and load_snapshot() keep them so.) The wet pass has no couple (the scenario
// parser refuses the pair).
template <int D>
void DemSolver<D>::prepare_rolling(bool wet) {
  const auto& p = w_.particles;
  if (wet) throw InputError("rolling resistance with capillary bridges is not supported yet");
  const auto n = static_cast<std::ptrdiff_t>(p.size());
  roll_inv_ic_.resize(p.size());
  double* const inv_ic = roll_inv_ic_.data();
#pragma omp parallel for schedule(static) if (n >= kMinParallelItems)
  for (std::ptrdiff_t g = 0; g < n; ++g)
    inv_ic[g] = inverse_inertia_at_contact(p.inv_inertia[g], p.mass[g], p.radius[g]);
}

template <int D>
dem::PairPass<D> DemSolver<D>::pair_pass() {
  auto& p = w_.particles;
  auto& pl = w_.neighbors.pairs;
  return {p.x.data(),
          p.v.data(),
          p.w.data(),
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
          gathered_.data(),
          near_.second_begin.data(),
          near_.second_pairs.data(),
          w_.materials.pair_view(),
          w_.model,
          w_.dt,
          pl.roll.data(),
          pair_roll_.data(),
          roll_inv_ic_.data()};
}

template <int D>
dem::GrainPass<D> DemSolver<D>::grain_pass(bool all, double h_kick) {
  auto& p = w_.particles;
  const auto& nl = w_.neighbors;
  const double keep = w_.viscous_rate > 0.0 ? 1.0 / (1.0 + w_.viscous_rate * h_kick) : 1.0;
  return {p.f.data(),
          p.v.data(),
          p.t.data(),
          p.w.data(),
          p.radius.data(),
          p.inv_mass.data(),
          p.inv_inertia.data(),
          near_.index.data(),
          near_.first_begin.data(),
          near_.second_begin.data(),
          near_.second_pairs.data(),
          nl.wall_begin.data(),
          nl.pairs.force.data(),
          nl.wall_pairs.force.data(),
          pair_moment_.data(),
          wall_moment_.data(),
          pair_roll_.data(),
          wall_roll_.data(),
          pair_delta_.data(),
          wall_delta_.data(),
          gathered_.data(),
          all,
          w_.model.rolling != RollingModel::kNone,
          h_kick,
          keep,
          w_.max_speed,
          w_.gravity};
}

// The dry pass, in one parallel region with the wall contacts and the grains' last loop. Each
// thread takes a contiguous block of grains, about an equal share of the near list, and the
// entries whose first member is one of them (the list is sorted by first member). It adds
// each contact's force and torque to the two grains as it goes, in list order; a grain's
// terms come in the order GrainPass::finish sums them (second-member entries, whose first
// member is smaller, then first-member ones), so the sums are the same bits for any number of
// threads. Only the grains another thread's entries reach (flagged in own(); none on one
// thread, a few % on two) are left to finish(). Gathering every grain's sum afterwards cost
// 15 % of the step (perf, docs/BENCHMARKS.md).
template <int D>
template <class Normal, bool Roll>
bool DemSolver<D>::dry_forces(const dem::GrainPass<D>& grains) {
  dem::PairPass<D> pass = pair_pass();
  const std::uint32_t* const near = near_.index.data();
  const std::uint32_t* const first_begin = near_.first_begin.data();
  // A team if any of the region's loops is long: the pairs, or the grains (a dilute flow).
  const auto items = static_cast<std::ptrdiff_t>(
      std::max({near_.index.size(), w_.particles.size(), w_.neighbors.wall_pairs.size()}));
  double max_ratio = 0.0;
  std::size_t touching = 0;
  int bad = 0;
  PhaseTimers::Laps laps(timers_);
#pragma omp parallel firstprivate(pass) reduction(max : max_ratio) reduction(+ : touching) \
    reduction(| : bad) if (items >= kMinParallelItems)
  {
    const int threads = omp_get_num_threads();
#pragma omp single
    split_grains(threads);
    const auto t = static_cast<std::size_t>(omp_get_thread_num());
    const std::uint32_t g0 = grain_block_[t], g1 = grain_block_[t + 1];
    pass.own(g0, g1);
    // Before any thread reads another's flags (its entries reach later blocks' grains).
#pragma omp barrier
    // One thread: no grain is gathered, and the flags need not be read.
    if (threads == 1)
      pass.template entries<Normal, dem::Sum::kScatter, Roll>(near, first_begin[g0],
                                                              first_begin[g1], max_ratio, touching);
    else
      pass.template entries<Normal, dem::Sum::kScatterChecked, Roll>(
          near, first_begin[g0], first_begin[g1], max_ratio, touching);
#pragma omp barrier
    if (t == 0) laps.charge(Phase::kForces);
    finish_in_team<Normal, Roll>(grains, laps, max_ratio, touching, bad);
  }
  diag_.max_overlap_ratio = std::max(diag_.max_overlap_ratio, max_ratio);
  diag_.touching += touching;
  return bad == 0;
}

// Blocks of grains for `threads` threads, each with about an equal share of the near list.
template <int D>
void DemSolver<D>::split_grains(int threads) {
  const auto& begin = near_.first_begin;  // n + 1 entries
  const auto n_threads = static_cast<std::size_t>(threads);
  const std::size_t n_near = near_.index.size();
  grain_block_.assign(n_threads + 1, 0);
  grain_block_[n_threads] = static_cast<std::uint32_t>(begin.size() - 1);
  for (std::size_t t = 1; t < n_threads; ++t) {
    const std::uint32_t share = static_cast<std::uint32_t>(n_near * t / n_threads);
    // The grain whose entries hold entry `share`: the last g with begin[g] <= share.
    const auto g = std::upper_bound(begin.begin(), begin.end() - 1, share) - begin.begin() - 1;
    grain_block_[t] = std::max(grain_block_[t - 1], static_cast<std::uint32_t>(g));
  }
}

// The wet step's passes: the grain pairs (with their own loop), the liquid, then the wall
// contacts and every grain's sum in one parallel region.
template <int D>
template <class Normal>
bool DemSolver<D>::wet_forces(const dem::GrainPass<D>& grains) {
  {
    auto scope = timers_.time(Phase::kForces);
    wet_pair_forces<Normal>();
  }
  settle_liquid();
  const auto items =
      static_cast<std::ptrdiff_t>(std::max(w_.particles.size(), w_.neighbors.wall_pairs.size()));
  double max_ratio = 0.0;
  std::size_t touching = 0;
  int bad = 0;
  PhaseTimers::Laps laps(timers_);
#pragma omp parallel reduction(max : max_ratio) reduction(+ : touching) reduction(| : bad) \
    if (items >= kMinParallelItems)
  finish_in_team<Normal, false>(grains, laps, max_ratio, touching, bad);
  diag_.max_overlap_ratio = std::max(diag_.max_overlap_ratio, max_ratio);
  diag_.touching += touching;
  return bad == 0;
}

// The grain-pair pass with capillary bridges. As the dry pass, plus: a bridged pair that has
// separated feels the bridge's attraction until its gap exceeds the rupture distance; a
// touching pair gets the contact attraction -kappa R, and a bridge if it had none (formation
// is only recorded here; the liquid moves in settle_liquid, in list order, so the result does
// not depend on the number of threads). The force at contact does not depend on the volume.
template <int D>
template <class Normal>
void DemSolver<D>::wet_pair_forces() {
  using S = Space<D>;
  const auto& p = w_.particles;
  auto& pl = w_.neighbors.pairs;
  const CapillaryParams& cap = w_.model.capillary;
  const double kappa = Capillary::kappa(cap);
  const bool forming = w_.liquid.wet();
  dem::PairPass<D> pass = pair_pass();
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
          pair_event_[k] = kBridgeBroken;
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
      pair_event_[k] = kBridgeFormed;
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

// Move the liquid of this step's bridge events, in list order (deterministic), and of any
// bridge the last rebuild dropped. A new bridge whose rupture distance would exceed the skin
// raises the skin and asks for a rebuild, so that no bridged pair can leave the list.
template <int D>
void DemSolver<D>::settle_liquid() {
  auto& nl = w_.neighbors;
  auto& liquid = w_.liquid;
  const auto policy = w_.model.capillary.ruptured;
  if (liquid.film.size() != w_.particles.size()) liquid.film.resize(w_.particles.size(), 0.0);
  for (const DroppedBridge& b : nl.dropped_bridges)
    release_bridge(liquid, policy, b.i, b.j, b.volume);
  nl.dropped_bridges.clear();
  if (events_ == 0) return;
  auto& pl = nl.pairs;
  for (std::size_t k = 0; k < pl.size(); ++k) {
    if (pair_event_[k] == 0) continue;
    if (pair_event_[k] == kBridgeBroken) {
      release_bridge(liquid, policy, pl.i[k], pl.j[k], pl.bridge[k]);
      pl.bridge[k] = PairList<D>::kNoBridge;
    } else {
      pl.bridge[k] = take_bridge_liquid(liquid, pl.i[k], pl.j[k]);
      const double reach = Capillary::rupture_distance(w_.model.capillary, pl.bridge[k]);
      if (reach > nl.skin) {
        nl.skin = 1.05 * reach;
        nl.x_ref.clear();  // forces a rebuild before the next force pass
      }
    }
    pair_event_[k] = 0;
  }
  events_ = 0;
}

// The end of the force pass, run by every thread of the caller's parallel region (the loops
// are shared out by orphaned `omp for`; each thread's max_ratio, touching and bad are its own,
// reduced by the region): the wall contacts, then (after the loop's barrier: every slot is
// written) each grain's sum and closing kick. Thread 0 times the two phases. The views are
// copied and the counters kept in locals: through references, every store of a vector
// (Eigen's SSE stores may alias anything) would make the compiler reload the pointers and
// store the counters.
template <int D>
template <class Normal, bool Roll>
[[gnu::flatten]] void DemSolver<D>::finish_in_team(const dem::GrainPass<D>& grains,
                                                   PhaseTimers::Laps& laps, double& max_ratio,
                                                   std::size_t& touching, int& bad) {
  const bool timing = omp_get_thread_num() == 0;
  const dem::WallPass<D> walls = wall_pass();
  const auto n_walls = static_cast<std::ptrdiff_t>(w_.neighbors.wall_pairs.size());
  double ratio = 0.0;
  std::size_t count = 0;
  // Dynamic: the list is sorted by grain, and the touching contacts (the costly ones)
  // cluster where the grains lie on a wall; a static split left one thread most of them.
#pragma omp for schedule(dynamic, 128)
  for (std::ptrdiff_t k = 0; k < n_walls; ++k)
    walls.template entry<Normal, Roll>(static_cast<std::size_t>(k), ratio, count);
  max_ratio = std::max(max_ratio, ratio);
  touching += count;
  if (timing) laps.charge(Phase::kWallForces);
  const dem::GrainPass<D> local = grains;
  const auto n = static_cast<std::ptrdiff_t>(w_.particles.size());
  int failed = 0;
#pragma omp for schedule(static)
  for (std::ptrdiff_t i = 0; i < n; ++i)
    failed |= local.finish(static_cast<std::size_t>(i)) ? 0 : 1;
  bad |= failed;
  if (timing) laps.charge(Phase::kIntegrate);
}

template <int D>
dem::WallPass<D> DemSolver<D>::wall_pass() {
  auto& p = w_.particles;
  auto& wl = w_.neighbors.wall_pairs;
  return {p.x.data(),         p.v.data(),
          p.w.data(),         p.radius.data(),
          p.mass.data(),      p.material.data(),
          wl.i.data(),        wl.wall.data(),
          w_.walls.data(),    wl.shear.data(),
          wl.force.data(),    wall_moment_.data(),
          wall_delta_.data(), w_.materials.pair_view(),
          w_.model,           w_.dt,
          wl.roll.data(),     wall_roll_.data(),
          roll_inv_ic_.data()};
}

// Each wall's force: a short sequential sum over the wall list, in list order (deterministic).
template <int D>
void DemSolver<D>::sum_wall_forces() {
  const auto& wl = w_.neighbors.wall_pairs;
  for (auto& wall : w_.walls) wall.force.setZero();
  for (std::size_t k = 0; k < wl.size(); ++k) w_.walls[wl.wall[k]].force -= wl.force[k];
}

template class DemSolver<2>;
template class DemSolver<3>;

}  // namespace sable
