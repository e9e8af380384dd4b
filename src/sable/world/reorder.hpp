// Spatial reordering of the grains' slots, at neighbour-list builds.
//
// The pair pass reads both grains of every contact. When slots follow space, a grain's
// partners sit in nearby slots and their data are in cache; a bed that flows (a drum, a
// hopper, a mixer) scrambles the slots, and every partner becomes a cache miss: a scrambled
// dense bed of 125,000 grains steps at 37-46 % of the speed (BM_DemStepOrder). Sorting the
// slots by neighbour cell, row by row (as LAMMPS' `atom_modify sort` bins atoms), puts each
// grain's partners in its own row of cells, the rows beside it and the layers of cells above
// and below it: a few fixed distances in slots, which the hardware prefetches. A Morton
// (Z-order) curve of the same cells is 25-32 % slower than rows on two threads
// (BM_DemStepOrder with the curve in place of the rows).
//
// Reordering moves every per-grain array (ParticleStore, the liquid films) and renames the
// slots in the neighbour lists so that each contact keeps its history: a pair whose members
// swap order gets its history negated (it is stored for its first grain), and both lists are
// sorted again. ParticleIds keep naming the same grains (IdRegistry::move). The new order
// depends only on the positions and the ids, so results stay the same for any number of
// threads, and a run resumed from a snapshot reorders at the same builds (the build count is
// saved).
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "sable/world/domain.hpp"
#include "sable/world/world.hpp"

namespace sable {

// What reorder_every = kReorderAuto does: a sort every kAutoReorderEvery builds (one costs
// about half a build: at most ~2.5 % of the list's upkeep), for beds of kAutoReorderMinGrains
// grains or more, by either solver. Smaller beds are left in their order: a bed that small is
// in cache as a whole and the DEM step runs it on one thread (DemSolver splits from 2,048
// items, grains plus near-list entries), so the order of its slots hardly matters, and its
// slots stay in the order the scenario made them. On dense lattices with shuffled slots
// (BM_DemStepOrder, BM_CdStepOrder):
// DEM, one thread: no loss at 2,197 grains, 19 % at 19,683, 54 % at 125,000; two threads:
// anywhere from none to 66 % at 2,197 and 19,683 grains, from one run to the next (the
// blocks' cut settles differently); contact dynamics, 10 sweeps a step: 3.2x slower at 2,197
// grains and 8.7x at 19,683, the NLGS iterates of a scrambled sweep order lingering in the
// exact local solver's costly sliding branch.
inline constexpr std::uint64_t kAutoReorderEvery = 20;
inline constexpr std::size_t kAutoReorderMinGrains = 1000;

// Whether the neighbour build numbered `build` (0: the first) is preceded by a sort, for
// reorder_every = `every` and n grains.
inline bool reorder_due(std::uint64_t every, std::uint64_t build, std::size_t n) {
  if (every == kReorderAuto) {
    if (n < kAutoReorderMinGrains) return false;
    every = kAutoReorderEvery;
  }
  return every > 0 && build % every == 0;
}

// A grain's place in cell order: its cell, then its id's index.
struct CellKey {
  std::uint64_t cell;
  std::uint32_t id;
  std::uint32_t slot;
  friend bool operator<(const CellKey& a, const CellKey& b) {
    return a.cell != b.cell ? a.cell < b.cell : a.id < b.id;
  }
};

// Grain slots sorted by the cell of edge `cell` of the grid over [lo, hi] that holds them,
// row by row, the axis of the most cells varying slowest (ties: the higher axis), the fewest
// fastest; within a cell, by id (`id[slot]`, its index): order[new] = old. Grains outside the
// grid count in its nearest cell. The order is a function of each grain's position and id
// alone, not of the slots they held: any subset of the grains (a process's share of them)
// sorts into the same relative order as the whole.
template <int D>
void cell_order(const std::vector<typename Space<D>::Vec>& x, const std::vector<ParticleId>& id,
                const typename Space<D>::Vec& lo, const typename Space<D>::Vec& hi, double cell,
                std::vector<std::uint32_t>& order, std::vector<CellKey>& scratch);

// Reorders a World's grains; owns its scratch so that a reorder inside the step does not
// allocate once sizes have settled.
template <int D>
class GrainReorder {
 public:
  // Moves the grains into cell order (cell_order: the neighbour cells, edge 2 R_max + skin,
  // over the list's domain), sets their order_key (the cell) and renames their slots everywhere
  // the World holds them. Returns false, moving no slot, when they already are in that order. Call
  // it just before NeighborList::build().
  // `domain`: the largest radius, which sizes the cells, is that of every process's grains.
  bool apply(World<D>& w, const Domain<D>& domain = Domain<D>{});
  // A neighbour-list build, preceded by apply() when reorder_due() names it (counting builds
  // from the first, by the saved build count, so that a resumed run sorts where the unbroken
  // one did): what both solvers call at every build. The order follows from the positions
  // alone, so it is the same for any number of threads.
  // For a process's share of the grains (world/domain.hpp), the count that decides a sort is
  // that of every process's grains.
  void build_lists(World<D>& w, const Domain<D>& domain = Domain<D>{}) {
    const std::uint64_t total = domain.total_grains();
    if (reorder_due(w.reorder_every, w.neighbors.builds, total ? total : w.particles.size()))
      apply(w, domain);
    w.neighbors.build(w.particles, w.walls);
  }
  std::uint64_t reorders = 0;  // how many times apply() moved the grains

 private:
  void relabel_pairs(PairList<D>& pl);
  void relabel_wall_pairs(WallPairList<D>& wl);
  void sort_by_grain(const std::vector<std::uint32_t>& grain, std::size_t n);
  std::vector<std::uint32_t> order_, new_slot_, entry_order_, count_;
  std::vector<CellKey> keys_;
  std::vector<std::uint8_t> seen_;
};

}  // namespace sable
