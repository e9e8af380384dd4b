// The DEM solver's liquid bridges: the liquid of each step's bridge events moved between the
// bridges and the grains' films (world/liquid.hpp), on one process or across several.
// Included by dem_solver_impl.hpp.
#pragma once

#include <fmt/format.h>

#include <algorithm>
#include <utility>

#include "sable/core/error.hpp"
#include "sable/dem/dem_solver.hpp"
#include "sable/world/liquid.hpp"

namespace sable {

// Move the liquid of any bridge the last rebuild dropped and of this step's bridge events, in
// list order: each film then changes in the order of its grain's partners, the same on every
// process that owns the grain (world/domain.hpp). A new bridge whose rupture distance would
// exceed the skin raises the skin (1.05 times the widest new bridge of the step, over every
// process) and asks for a rebuild, so that no bridged pair can leave the list.
template <int D, class Laws>
void DemSolver<D, Laws>::settle_liquid() {
  auto& nl = world_.neighbors;
  auto& liquid = world_.liquid;
  const auto policy = world_.model.capillary.ruptured;
  if (liquid.film.size() != world_.particles.size())
    liquid.film.resize(world_.particles.size(), 0.0);
  for (const DroppedBridge& b : nl.dropped_bridges)
    release_bridge(liquid, policy, b.i, b.j, b.volume);
  nl.dropped_bridges.clear();
  formed_.clear();
  shares_.clear();
  if (events_ > 0) move_bridge_liquid();
  const bool split = domain_->distributed();
  if (split) join_bridge_shares();
  double reach = 0.0;
  for (const FormedBridge& f : formed_)
    reach = std::max(reach,
                     Capillary::rupture_distance(world_.model.capillary, nl.pairs.bridge[f.entry]));
  if (split) domain_->max(&reach, 1);
  if (reach > nl.skin) {
    nl.skin = 1.05 * reach;
    nl.x_ref.clear();  // forces a rebuild before the next force pass
  }
}

// The events of the step, in list order: a broken bridge's liquid released, a new bridge
// filled with half of each grain's film. Under MPI a ghost's film is not its owner's: the
// share a ghost gave is replaced by its owner's (join_bridge_shares), and each owned grain's
// share to a bridge with a ghost is kept for the ghost's owner.
template <int D, class Laws>
void DemSolver<D, Laws>::move_bridge_liquid() {
  auto& pl = world_.neighbors.pairs;
  auto& liquid = world_.liquid;
  const auto& p = world_.particles;
  const auto policy = world_.model.capillary.ruptured;
  for (std::size_t k = 0; k < pl.size(); ++k) {
    if (pair_event_[k] == 0) continue;
    const std::uint32_t i = pl.i[k], j = pl.j[k];
    if (pair_event_[k] == dem_detail::kBridgeBroken) {
      release_bridge(liquid, policy, i, j, pl.bridge[k]);
      pl.bridge[k] = PairList<D>::kNoBridge;
    } else {
      const BridgeTake t = take_bridge_liquid(liquid, i, j);
      const FormedBridge f{k, t.from_i, t.from_j};
      pl.bridge[k] = f.from_i + f.from_j;
      formed_.push_back(f);
      const bool ghost_i = (p.flags[i] & kGhost) != 0, ghost_j = (p.flags[j] & kGhost) != 0;
      if (ghost_i != ghost_j)
        shares_.push_back(ghost_j ? BridgeShare{p.id[i].index, p.id[j].index, f.from_i}
                                  : BridgeShare{p.id[j].index, p.id[i].index, f.from_j});
    }
    pair_event_[k] = 0;
  }
  events_ = 0;
}

// Under MPI, every step (collective): each bridge formed with a ghost gets the share its
// owner's process computed for the ghost's film, added in the serial order (first member's
// share first).
template <int D, class Laws>
void DemSolver<D, Laws>::join_bridge_shares() {
  domain_->exchange_bridge_shares(world_, shares_);
  auto key = [](const BridgeShare& s) { return std::pair{s.giver, s.partner}; };
  std::sort(shares_.begin(), shares_.end(),
            [&](const BridgeShare& a, const BridgeShare& b) { return key(a) < key(b); });
  const auto& p = world_.particles;
  auto& pl = world_.neighbors.pairs;
  auto owners_share = [&](std::uint32_t ghost, std::uint32_t partner) {
    const std::pair want{p.id[ghost].index, p.id[partner].index};
    const auto it = std::lower_bound(
        shares_.begin(), shares_.end(), want,
        [&](const BridgeShare& s, const std::pair<std::uint32_t, std::uint32_t>& x) {
          return key(s) < x;
        });
    if (it == shares_.end() || key(*it) != want)
      throw IoError(fmt::format("mpi: no share of liquid came for the bridge of grains {} and {}",
                                want.first, want.second));
    return it->volume;
  };
  for (FormedBridge& f : formed_) {
    const std::uint32_t i = pl.i[f.entry], j = pl.j[f.entry];
    const bool ghost_i = (p.flags[i] & kGhost) != 0, ghost_j = (p.flags[j] & kGhost) != 0;
    if (ghost_i == ghost_j) continue;
    if (ghost_i) f.from_i = owners_share(i, j);
    if (ghost_j) f.from_j = owners_share(j, i);
    pl.bridge[f.entry] = f.from_i + f.from_j;
  }
}

}  // namespace sable
