// The DEM step's work per grain (dem_solver_impl.hpp holds the step itself and the pair passes):
//   - the opening loop, kick_and_drift() (stage integrate): the first half kick and the
//     drift, measuring on the way how far the grains have moved since the two lists'
//     reference positions;
//   - the closing: per grain, its wall contacts, the sum of its forces and torques, the
//     second half kick and the check of its state. The dry pair pass closes its grains as it
//     goes (close_passed_grains(), close_gathered_chunks(): see DemSolver::dry_pair_forces);
//     wet runs in a loop of their own, closing_loop() (each chunk of grains in three short
//     runs).
// Each loop does all of a grain's operations in one visit, reading the grains' arrays once
// and meeting the thread team once. No grain's operations read what another's write, so
// each loop shares its grains among the threads in chunks (dem/grain_split.hpp): whichever
// thread does a grain, and however many threads run, the bits are the same.
#pragma once

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>

#include "sable/contact/registry.hpp"
#include "sable/dem/dem_solver.hpp"
#include "sable/dem/grain_pass.hpp"
#include "sable/world/guards.hpp"

namespace sable {

namespace dem_detail {

// This thread's part of a grain loop shared in chunks (dem/grain_split.hpp): its own blocks
// (timed, for the next cuts), then whatever chunks of the others' are left; body(g0, g1) does
// grains [g0, g1). Call split.open_chunks() before the loop.
template <class Body>
[[gnu::always_inline]] inline void share_grains(GrainSplit& split, Body&& body) {
  const int team = omp_get_num_threads(), thread = omp_get_thread_num();
  const int blocks = split.blocks();
  std::uint32_t g0 = 0, g1 = 0;
  for (int b = thread; b < blocks; b += team) {
    const double start = omp_get_wtime();
    const std::uint32_t own = split.bounds()[b], tail = split.tail(b);
    if (own < tail) body(own, tail);
    std::uint32_t done = tail - own;
    while (split.take_chunk(b, g0, g1)) {
      body(g0, g1);
      done += g1 - g0;
    }
    if (team == blocks) split.add_busy(b, omp_get_wtime() - start, double(done));
  }
  for (int k = 1; k < blocks; ++k)
    while (split.take_chunk((thread + k) % blocks, g0, g1)) body(g0, g1);
}

}  // namespace dem_detail

template <int D, class Laws>
typename DemSolver<D, Laws>::GrainPass DemSolver<D, Laws>::make_grain_pass(double h_kick) {
  auto& p = world_.particles;
  const auto& nl = world_.neighbors;
  const double keep = world_.viscous_rate > 0.0 ? 1.0 / (1.0 + world_.viscous_rate * h_kick) : 1.0;
  return {p.x.data(),
          p.v.data(),
          p.q.data(),
          p.omega.data(),
          p.f.data(),
          p.t.data(),
          p.inv_mass.data(),
          p.inv_inertia.data(),
          p.radius.data(),
          world_.gravity,
          keep,
          world_.max_speed,
          near_.index.data(),
          near_.first_begin.data(),
          near_.second_begin.data(),
          near_.second_pairs.data(),
          nl.wall_begin.data(),
          entry_walk(),
          nl.pairs.force.data(),
          nl.wall_pairs.force.data(),
          pair_moment_.data(),
          wall_moment_.data(),
          pair_roll_.data(),
          wall_roll_.data(),
          pair_delta_.data(),
          wall_delta_.data(),
          grain_flags_.data(),
          p.flags.data(),
          with_rolling()};
}

// The opening loop of every step (stage integrate): a half kick by h_kick, a drift by
// h_drift, and the largest squared displacements since the lists' reference positions (which
// the lists' "may an unseen pair touch now?" tests need), in one loop: each grain's position
// and velocity are read once instead of three times.
template <int D, class Laws>
typename DemSolver<D, Laws>::Displacements DemSolver<D, Laws>::kick_and_drift(double h_kick,
                                                                              double h_drift) {
  using S = Space<D>;
  GrainPass pass = make_grain_pass(h_kick);
  const auto& outer_ref = world_.neighbors.x_ref;
  const auto& near_ref = near_.reference();
  const typename S::Vec* const outer =
      outer_ref.size() == world_.particles.size() ? outer_ref.data() : nullptr;
  const typename S::Vec* const inner =
      near_ref.size() == world_.particles.size() ? near_ref.data() : nullptr;
  const bool turning = world_.track_orientation;
  GrainSplit& split = grain_loop_split(opening_split_);
  const int blocks = split.blocks();
  split.open_chunks();
  double neighbor_max2 = 0.0, near_max2 = 0.0;  // maxima: exact whatever the order
  // (clang-format breaks the reduction clause apart)
  // clang-format off
#pragma omp parallel num_threads(blocks) firstprivate(pass) \
    reduction(max : neighbor_max2, near_max2) if (blocks > 1)
  // clang-format on
  {
    dem_detail::share_grains(split, [&](std::size_t g0, std::size_t g1) {
      // Copies local to the chunk, whose address is not taken: the compiler keeps them in
      // registers (reached through the lambda's references, every store to x could alias them).
      const GrainPass c = pass;
      double o2 = 0.0, n2 = 0.0;
      for (std::size_t k = g0; k < g1; ++k) {
        if (c.ghost(k)) continue;  // its owner moves it (and measures how far)
        if (c.kick(k, h_kick)) {
          c.x[k] += h_drift * c.v[k];
          if (turning) c.q[k] = S::rotate(c.q[k], c.omega[k], h_drift);
        }
        if (outer) o2 = std::max(o2, (c.x[k] - outer[k]).squaredNorm());
        if (inner) n2 = std::max(n2, (c.x[k] - inner[k]).squaredNorm());
      }
      neighbor_max2 = std::max(neighbor_max2, o2);
      near_max2 = std::max(near_max2, n2);
    });
  }
  return {outer ? neighbor_max2 : -1.0, near_max2};
}

// The wet runs' closing loop over the grains (the dry pass closes its grains itself): per
// grain, its wall contacts, its sum from its contacts' slots (see GrainPass::sum), the second
// half kick by h_kick (none when 0: forces only) and the check of its state; true when some
// grain's state is unsound (check_grain_states() then names it).
template <int D, class Laws>
template <class Normal>
bool DemSolver<D, Laws>::closing_loop(double h_kick) {
  GrainPass pass = make_grain_pass(h_kick);
  GrainSplit& split = grain_loop_split(closing_split_);
  const int blocks = split.blocks();
  split.open_chunks();
  double max_ratio = 0.0;
  std::size_t touching = 0;
  int bad = 0;
#pragma omp parallel num_threads(blocks) firstprivate(pass) reduction(max : max_ratio) \
    reduction(+ : touching) reduction(| : bad) if (blocks > 1)
  {
    const double h = h_kick;  // a local: the compiler need not reload it after each call
    dem_detail::share_grains(split, [&](std::size_t g0, std::size_t g1) {
      // Three runs over the chunk (a few KiB: the second and third find it in the L1 cache):
      // its wall contacts (its grains' wall pairs are one run of the list), its sums, then
      // its kicks and checks. Each grain's operations keep their order (a wall contact reads
      // only its own grain, whose kick comes after either way): the same bits as one loop
      // doing all three per grain. But such a loop calls wall_contact() and carries the
      // gather's loops, and the compiler keeps its pointers on the stack: on bench/ab_dense.sh's
      // bed closed by this loop, the three runs take 7 % (one thread) to 13 % (two) less time.
      wall_contacts<Normal>(static_cast<std::uint32_t>(g0), static_cast<std::uint32_t>(g1),
                            max_ratio, touching);
      // The copy is the point: local to the chunk, its pointers stay in registers (see
      // kick_and_drift). NOLINTNEXTLINE(performance-unnecessary-copy-initialization)
      const GrainPass c = pass;
      for (std::size_t i = g0; i < g1; ++i) c.sum(i, true);
      int unsound = 0;
      for (std::size_t i = g0; i < g1; ++i) unsound |= c.close(i, h);
      bad |= unsound;
    });
  }
  diag_.max_overlap_ratio = std::max(diag_.max_overlap_ratio, max_ratio);
  diag_.touching += touching;
  return bad != 0;
}

// The dry pair pass's closing of grains [g0, g1) once it is past their entries (see
// dry_pair_forces: an entry (i, j) has i < j, so their sums are final): their wall contacts,
// then, for each grain whose sum the pass made (not kGathered), its walls' terms, its half
// kick by h (none when 0) and its check. 1 when one of them is unsound.
template <int D, class Laws>
template <class Normal>
int DemSolver<D, Laws>::close_passed_grains(const GrainPass& pass, std::uint32_t g0,
                                            std::uint32_t g1, double h, double& max_ratio,
                                            std::size_t& touching) {
  wall_contacts<Normal>(g0, g1, max_ratio, touching);
  const GrainPass c = pass;  // local: in registers (see kick_and_drift)
  for (std::size_t i = g0; i < g1; ++i)
    if (!(c.flags[i] & kGathered)) c.sum(i, false);
  int unsound = 0;
  for (std::size_t i = g0; i < g1; ++i)
    if (!(c.flags[i] & kGathered)) unsound |= c.close(i, h);
  return unsound;
}

// The closing of grains the dry pass left to the gather, after it (see dry_pair_forces): the
// sum from their contacts' slots, the half kick by h and the check; grains g[0..n) when `g`,
// else grains [g0, g0 + n) but those flagged kGathered (the list has them). 1 when one is
// unsound.
template <int D, class Laws>
int DemSolver<D, Laws>::close_gathered_grains(const GrainPass& pass, const std::uint32_t* g,
                                              std::uint32_t g0, std::size_t n, double h) {
  const GrainPass c = pass;
  auto grain = [&](std::size_t s) -> std::size_t { return g ? g[s] : g0 + s; };
  auto skip = [&](std::size_t i) { return !g && (c.flags[i] & kGathered); };
  for (std::size_t s = 0; s < n; ++s)
    if (!skip(grain(s))) c.sum(grain(s), true);
  int unsound = 0;
  for (std::size_t s = 0; s < n; ++s)
    if (!skip(grain(s))) unsound |= c.close(grain(s), h);
  return unsound;
}

// After the dry pass, on each thread once they have met (see dry_pair_forces): the closing of
// the grains it left to the gather, the listed ones (kGathered), then in each block those
// from where its tail's two ends met, handed out in chunks of kGatheredChunk by `next`.
// Relaxed: the meeting has ordered the pass's writes; which thread closes a grain changes
// nothing but the speed. 1 when one of them is unsound.
template <int D, class Laws>
int DemSolver<D, Laws>::close_gathered_chunks(const GrainPass& pass,
                                              std::atomic<std::uint32_t>& next, double h) {
  const GrainSplit& split = pair_split_;
  const int blocks = split.blocks();
  const std::uint32_t* const block = split.bounds();
  const std::uint32_t* const listed = gathered_list_.data();
  const auto n_list = static_cast<std::uint32_t>(gathered_list_.size());
  std::uint32_t n_gathered = n_list;
  for (int t = 0; t < blocks; ++t) n_gathered += block[t + 1] - split.first_taken_from_back(t);
  int bad = 0;
  for (;;) {
    std::uint32_t l0 = next.fetch_add(kGatheredChunk, std::memory_order_relaxed);
    if (l0 >= n_gathered) return bad;
    const std::uint32_t l1 = std::min(l0 + kGatheredChunk, n_gathered);
    if (l0 < n_list) {
      const std::uint32_t n = std::min(l1, n_list) - l0;
      bad |= close_gathered_grains(pass, listed + l0, 0, n, h);
      l0 += n;
    }
    // Past the list: the blocks' taken grains, one block's run after the other.
    std::uint32_t base = n_list;
    for (int t = 0; t < blocks && l0 < l1; ++t) {
      const std::uint32_t from = split.first_taken_from_back(t), size = block[t + 1] - from;
      if (l0 < base + size) {
        const std::uint32_t n = std::min(l1, base + size) - l0;
        bad |= close_gathered_grains(pass, nullptr, from + (l0 - base), n, h);
        l0 += n;
      }
      base += size;
    }
  }
}

}  // namespace sable
