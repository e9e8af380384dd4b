// Contact detection: linked cells + Verlet lists with a skin, rebuilt on displacement.
//
// Candidates are grain pairs (i < j, by slot) whose gap is below the skin, and (grain, wall)
// pairs whose gap is below the skin. Both lists are kept sorted, and each entry carries the
// contact's history (tangential spring) and its last force right beside it, so the force loop
// streams through contiguous arrays. A rebuild merges old and new sorted lists to carry the
// history of persisting contacts. Rebuilds happen when some grain (or wall) has moved far
// enough that an unseen pair could touch: cost O(N) per step, memory O(N).
#pragma once

#include <cstdint>
#include <vector>

#include "sable/core/particles.hpp"
#include "sable/geometry/walls.hpp"

namespace sable {

template <int D>
struct PairList {
  using Vec = typename Space<D>::Vec;
  std::vector<std::uint32_t> i, j;  // slots, i < j
  std::vector<Vec> shear;           // tangential history (displacement)
  std::vector<Vec> force;           // last force on i (0 when not touching)
  // Liquid-bridge volume (m^3), kNoBridge where there is none; empty unless the contact law
  // has capillary cohesion (NeighborList::bridges), so dry runs carry nothing.
  std::vector<double> bridge;
  static constexpr double kNoBridge = -1.0;
  // Rolling spring (contact/rolling.hpp), empty unless the law has rolling resistance
  // (NeighborList::rolling).
  std::vector<typename Space<D>::Rot> roll;
  std::size_t size() const { return i.size(); }
  void clear() {
    i.clear();
    j.clear();
    shear.clear();
    force.clear();
    bridge.clear();
    roll.clear();
  }
};

// A bridge whose pair left the list at a rebuild (its gap grew beyond the skin). With the
// skin kept above every rupture distance this does not happen; if it does, the solver treats
// it as a rupture so that no liquid disappears unaccounted.
struct DroppedBridge {
  std::uint32_t i, j;
  double volume;
};

// Candidate grain-wall contacts, sorted by (grain, wall, element). `element` is the wall's
// list element (a mesh's triangle or segment; 0 for the other shapes); `feature` is the id of
// the surface feature whose contact the entry holds, which its history belongs to
// (geometry/mesh_wall.hpp: a mesh element answers for its face and the edges and vertices it
// owns, one at a time; 0 for the other shapes).
template <int D>
struct WallPairList {
  using Vec = typename Space<D>::Vec;
  std::vector<std::uint32_t> i;        // grain slot
  std::vector<std::uint32_t> wall;     // wall index
  std::vector<std::uint32_t> element;  // the wall's element
  std::vector<std::uint32_t> feature;  // the feature the history belongs to
  std::vector<Vec> shear;
  std::vector<Vec> force;                    // last force on the grain
  std::vector<typename Space<D>::Rot> roll;  // as PairList::roll
  std::size_t size() const { return i.size(); }
  void clear() {
    i.clear();
    wall.clear();
    element.clear();
    feature.clear();
    shear.clear();
    force.clear();
    roll.clear();
  }
};

// The largest squared distance between x[k] and ref[k] over all k (same sizes); exact and
// thread-independent (a max). What the lists' "may an unseen pair touch now?" tests measure.
template <int D>
double max_displacement2(const std::vector<typename Space<D>::Vec>& x,
                         const std::vector<typename Space<D>::Vec>& ref);

template <int D>
class NeighborList {
 public:
  using Vec = typename Space<D>::Vec;

  double skin = 0.0;
  Vec domain_lo = Vec::Zero(), domain_hi = Vec::Zero();  // cell grid extent
  PairList<D> pairs;
  WallPairList<D> wall_pairs;
  std::vector<Vec> x_ref;                                     // positions at the last build
  std::vector<Vec> wall_ref;                                  // wall points at the last build
  std::vector<typename Space<D>::Orientation> wall_ref_turn;  // and their orientations
  // Each wall's list reach at the last build: its grains within this gap are listed. The
  // whole skin, but half of it for a mesh that stood still then (list_reach()). Empty (the
  // whole skin for every wall) before a build or from a snapshot written without it.
  std::vector<double> wall_reach;
  std::uint64_t builds = 0;
  bool bridges = false;                        // pairs carry a bridge volume (capillary law)
  bool rolling = false;                        // both lists carry a rolling spring
  std::vector<DroppedBridge> dropped_bridges;  // filled by build(), consumed by the solver

  // Incidence of the wall list, derived from it (never saved): grain i is the grain of wall
  // pairs [wall_begin[i], wall_begin[i+1]). The DEM solver sums each grain's forces in this
  // fixed order (and its grain pairs through dem/near_list.hpp's incidence), which makes
  // results independent of the number of threads.
  std::vector<std::uint32_t> wall_begin;
  // Recompute the incidence if the lists changed since it was last made.
  void update_incidence(std::size_t n_grains);

  // True when some pair not in the lists might now be touching, or (with margin > 0) might
  // touch after every grain moves `margin` further: contact dynamics asks for the contacts
  // that can close during the coming step.
  bool needs_rebuild(const ParticleStore<D>& p, const std::vector<Wall<D>>& walls,
                     double margin = 0.0) const;
  // The same test, given the grains' largest squared displacement since x_ref (max_d2,
  // negative when x_ref does not hold every grain): the DEM step measures it in its drift
  // loop instead of reading every position again.
  bool needs_rebuild_after(double max_d2, const std::vector<Wall<D>>& walls,
                           double margin = 0.0) const;
  void build(const ParticleStore<D>& p, const std::vector<Wall<D>>& walls);
  // The gap within which a build lists the grains of `wall`. A grain and a wall close in by at
  // most dp + dw between builds, while grain pairs close in by 2 dp and force a rebuild at
  // dp = skin / 2: for a wall standing still (dw = 0), half the skin is then enough and
  // costs no extra rebuild. Only meshes take it: a fine mesh lists tens of elements per grain
  // within the skin (bench/mesh_floor.sh), a plane, box or cylinder one entry per grain near
  // it, whose list (and state hash) stay as they are. A moving wall keeps the whole skin, or
  // its own motion would make the rebuilds come sooner.
  double list_reach(const Wall<D>& wall) const;

 private:
  void build_cells(const ParticleStore<D>& p);
  void build_pairs(const ParticleStore<D>& p, PairList<D>& out);
  void partners_of(const ParticleStore<D>& p, std::size_t i, std::vector<std::uint32_t>& out) const;
  void build_wall_pairs(const ParticleStore<D>& p, const std::vector<Wall<D>>& walls,
                        WallPairList<D>& out);
  void bin_elements(const Wall<D>& wall, double reach);
  std::array<int, D> cell_coords(const Vec& x) const;

  bool incidence_valid_ = false;
  // Scratch reused between builds so a rebuild does not allocate once sizes have settled.
  std::array<int, D> ncell_{};
  double cell_size_ = 0.0;
  std::vector<std::uint32_t> cell_of_, cell_start_, cell_items_, scratch_;
  // A bounded wall's elements by cell (bin_elements), for one wall at a time.
  std::vector<std::uint32_t> element_start_, element_items_;
  std::vector<std::uint32_t> new_order_, tmp_;                   // the wall list's sort by grain
  std::vector<std::vector<std::uint32_t>> thread_i_, thread_j_;  // per-thread pair blocks
  PairList<D> new_pairs_;
  WallPairList<D> new_wall_pairs_;
};

}  // namespace sable
