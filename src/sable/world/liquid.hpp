// The liquid of capillary bridges: putting it into a sample, and moving it when bridges
// rupture or form (Richefeu et al. 2009, section 2).
//
// Wetting. A gravimetric water content w gives the liquid volume V = w M / rho_l (M: mass of
// the free grains). It is shared among the eligible pairs, those whose gap is below the
// debonding distance (contacts included), each in proportion to its reduced diameter d_k:
// V_k = V d_k / S, S the sum of d_k over the eligible set. The debonding distance depends on
// V_k, which depends on the set; the set used is the largest one consistent with itself:
// pair k is eligible when gap_k <= delta_max(V_k), i.e. (gap_k / (1 + theta/2))^3 / d_k <=
// V / S. Sorting candidates by that key, the set is a prefix (the key grows and V / S shrinks
// along it), found in one pass. The neighbour-list skin is raised first, if needed, so that
// every bridge's rupture distance stays inside it: a bridged pair never leaves the list.
// With LiquidPairs::kContacts only the touching pairs (gap <= 0) are eligible: the same
// shares over fewer, larger bridges; pairs at a gap get a bridge only by touching later.
//
// Rupture and formation (applied by the DEM solver, in pair-list order, after the forces of a
// step). A bridge breaks when its gap exceeds delta_max; its liquid goes half to each grain's
// film (RupturedLiquid::kGrains) or leaves the sample (kLost). A bridge forms when two grains
// of a wetted sample touch and have none (no bridge forms at a distance); it takes half of
// each grain's film. Its attraction at contact, -kappa R, does not depend on its volume, so
// a bridge formed from dry films (volume 0) holds while the grains touch and breaks at once
// when they separate. Liquid is conserved: bridges + films + lost = total.
#pragma once

#include <cstddef>
#include <cstdint>

#include "sable/world/world.hpp"

namespace sable {

struct WettingResult {
  double volume = 0.0;              // liquid put in (m^3)
  std::size_t bridges = 0;          // eligible pairs, each given a bridge
  std::size_t contacts = 0;         // of which touching
  double debonding_distance = 0.0;  // the largest gap given a bridge (m)
  double max_rupture = 0.0;         // the largest bridge rupture distance (m)
};

// Which pairs the liquid goes to: every pair within its debonding distance (the paper's
// rule), or the touching pairs only.
enum class LiquidPairs { kEligible, kContacts };

// Distribute the liquid of `water_content` (kg of liquid per kg of grains) over the sample,
// replacing any liquid already there. Requires the capillary cohesion model; throws
// InputError otherwise, or when no pair of grains can hold a bridge.
template <int D>
WettingResult wet_grains(World<D>& w, double water_content, double liquid_density,
                         LiquidPairs pairs = LiquidPairs::kEligible);

struct LiquidBalance {
  double bridges = 0.0, films = 0.0, lost = 0.0, total = 0.0;
  std::size_t bridge_count = 0;
};
template <int D>
LiquidBalance liquid_balance(const World<D>& w);

// A ruptured bridge's liquid, per the policy.
inline void release_bridge(LiquidState& l, RupturedLiquid policy, std::uint32_t i, std::uint32_t j,
                           double volume) {
  if (policy == RupturedLiquid::kLost) {
    l.lost += volume;
    return;
  }
  l.film[i] += 0.5 * volume;
  l.film[j] += 0.5 * volume;
}

// The liquid a new bridge between i and j takes: half of each grain's film, returned as the
// two shares {from i, from j} (the bridge holds their sum, i's first).
struct BridgeTake {
  double from_i, from_j;
};
inline BridgeTake take_bridge_liquid(LiquidState& l, std::uint32_t i, std::uint32_t j) {
  const BridgeTake t{0.5 * l.film[i], 0.5 * l.film[j]};
  l.film[i] -= t.from_i;
  l.film[j] -= t.from_j;
  return t;
}

}  // namespace sable
