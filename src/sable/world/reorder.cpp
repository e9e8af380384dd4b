#include "sable/world/reorder.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

namespace sable {

namespace {

// Cells per axis at most, so that a cell's row-major index (the sort key) fits 64 bits.
template <int D>
constexpr double kMaxCellsPerAxis = D == 3 ? 2097152.0 : 4294967296.0;  // 2^21, 2^32

// a[new] = a[order[new]] for every slot, in place, one cycle of the permutation at a time
// (seen: scratch of the array's size). No copy of the array is made.
template <class T>
void apply_order(std::vector<T>& a, const std::vector<std::uint32_t>& order,
                 std::vector<std::uint8_t>& seen) {
  if (a.size() != order.size()) return;  // an array the run does not carry (empty)
  seen.assign(order.size(), 0);
  for (std::size_t s = 0; s < order.size(); ++s) {
    if (seen[s] || order[s] == s) continue;
    T first = std::move(a[s]);
    std::size_t k = s;
    while (order[k] != s) {
      a[k] = std::move(a[order[k]]);
      seen[k] = 1;
      k = order[k];
    }
    a[k] = std::move(first);
    seen[k] = 1;
  }
}

}  // namespace

template <int D>
void cell_order(const std::vector<typename Space<D>::Vec>& x, const std::vector<ParticleId>& id,
                const typename Space<D>::Vec& lo, const typename Space<D>::Vec& hi, double cell,
                std::vector<std::uint32_t>& order, std::vector<CellKey>& scratch) {
  // The axes from the slowest to the fastest varying: the longest extent first (ties: the
  // higher axis), so that a layer of cells, the span of slots a grain's partners lie in, is as
  // small as it can be (a tall column: horizontal layers).
  for (int d = 0; d < D; ++d)  // a huge domain: coarser cells rather than an overflow
    cell = std::max(cell, (hi[d] - lo[d]) / kMaxCellsPerAxis<D>);
  std::array<int, D> axis;
  std::array<double, D> ncell;
  for (int d = 0; d < D; ++d) {
    axis[d] = d;
    ncell[d] = std::clamp(std::ceil((hi[d] - lo[d]) / cell), 1.0, kMaxCellsPerAxis<D>);
  }
  std::sort(axis.begin(), axis.end(),
            [&](int a, int b) { return ncell[a] != ncell[b] ? ncell[a] > ncell[b] : a > b; });
  scratch.resize(x.size());
  for (std::size_t k = 0; k < x.size(); ++k) {
    std::uint64_t key = 0;
    for (int d : axis) {
      // Grains outside the grid (and NaN) fall into its first or last cells: still an order.
      const double c = std::clamp(std::floor((x[k][d] - lo[d]) / cell), 0.0, ncell[d] - 1.0);
      key = key * static_cast<std::uint64_t>(ncell[d]) +
            static_cast<std::uint64_t>(std::isnan(c) ? 0.0 : c);
    }
    scratch[k] = {key, id[k].index, static_cast<std::uint32_t>(k)};
  }
  std::sort(scratch.begin(), scratch.end());  // (cell, id): ids are unique, a total order
  order.resize(x.size());
  for (std::size_t k = 0; k < x.size(); ++k) order[k] = scratch[k].slot;
}

template <int D>
bool GrainReorder<D>::apply(World<D>& w, const Domain<D>& domain) {
  auto& p = w.particles;
  const std::size_t n = p.size();
  double rmax = 0.0;
  for (double r : p.radius) rmax = std::max(rmax, r);
  domain.max(&rmax, 1);  // every process sorts on the same cells
  auto& nl = w.neighbors;
  cell_order<D>(p.x, p.id, nl.domain_lo, nl.domain_hi, std::max(2.0 * rmax + nl.skin, 1e-300),
                order_, keys_);
  for (const CellKey& k : keys_) p.order_key[k.slot] = k.cell;  // moved with the slots below
  bool identity = true;
  for (std::size_t k = 0; k < n && identity; ++k) identity = order_[k] == k;
  if (identity) return false;

  p.for_each_array([this](auto& array) { apply_order(array, order_, seen_); });
  for (std::size_t s = 0; s < n; ++s) p.ids.move(p.id[s], static_cast<std::uint32_t>(s));
  apply_order(w.liquid.film, order_, seen_);
  apply_order(nl.x_ref, order_, seen_);

  new_slot_.resize(n);
  for (std::size_t s = 0; s < n; ++s) new_slot_[order_[s]] = static_cast<std::uint32_t>(s);
  relabel_pairs(nl.pairs);
  relabel_wall_pairs(nl.wall_pairs);
  for (DroppedBridge& b : nl.dropped_bridges) {
    b.i = new_slot_[b.i];
    b.j = new_slot_[b.j];
  }
  nl.wall_begin.clear();  // the incidence is made again (update_incidence)
  ++reorders;
  return true;
}

// entry_order_: a list's entries by grain (grain[k] < n), stably (a counting sort); count_[s]
// the end of grain s's entries in it.
template <int D>
void GrainReorder<D>::sort_by_grain(const std::vector<std::uint32_t>& grain, std::size_t n) {
  count_.assign(n + 1, 0);
  for (std::uint32_t g : grain) ++count_[g + 1];
  for (std::size_t s = 0; s < n; ++s) count_[s + 1] += count_[s];
  entry_order_.resize(grain.size());
  for (std::size_t k = 0; k < grain.size(); ++k)
    entry_order_[count_[grain[k]]++] = static_cast<std::uint32_t>(k);
}

// Pair k becomes (new_slot[i], new_slot[j]), its members swapped where that puts them out of
// order, with its history (displacement, last force, rolling spring: each stored for the
// first grain) negated; then the list is sorted by (i, j) again: a counting sort by the first
// grain, then each grain's few partners by insertion.
template <int D>
void GrainReorder<D>::relabel_pairs(PairList<D>& pl) {
  const std::size_t m = pl.size(), n = new_slot_.size();
  const bool roll = pl.roll.size() == m;
  for (std::size_t k = 0; k < m; ++k) {
    std::uint32_t a = new_slot_[pl.i[k]], b = new_slot_[pl.j[k]];
    if (a > b) {
      std::swap(a, b);
      pl.shear[k] = -pl.shear[k];
      pl.force[k] = -pl.force[k];
      if (roll) pl.roll[k] = -pl.roll[k];
    }
    pl.i[k] = a;
    pl.j[k] = b;
  }
  sort_by_grain(pl.i, n);
  // count_[s] is the end of grain s's row; its start is the previous grain's end.
  for (std::size_t s = 0, begin = 0; s < n; begin = count_[s++]) {
    for (std::size_t e = begin + 1; e < count_[s]; ++e) {
      const std::uint32_t k = entry_order_[e];
      std::size_t f = e;
      for (; f > begin && pl.j[entry_order_[f - 1]] > pl.j[k]; --f)
        entry_order_[f] = entry_order_[f - 1];
      entry_order_[f] = k;
    }
  }
  apply_order(pl.i, entry_order_, seen_);
  apply_order(pl.j, entry_order_, seen_);
  apply_order(pl.shear, entry_order_, seen_);
  apply_order(pl.force, entry_order_, seen_);
  apply_order(pl.bridge, entry_order_, seen_);
  apply_order(pl.roll, entry_order_, seen_);
}

// Wall pair k's grain renamed; the list sorted by (grain, wall) again: a stable counting sort
// by grain keeps each grain's walls in their order.
template <int D>
void GrainReorder<D>::relabel_wall_pairs(WallPairList<D>& wl) {
  const std::size_t m = wl.size(), n = new_slot_.size();
  for (std::size_t k = 0; k < m; ++k) wl.i[k] = new_slot_[wl.i[k]];
  sort_by_grain(wl.i, n);
  apply_order(wl.i, entry_order_, seen_);
  apply_order(wl.wall, entry_order_, seen_);
  apply_order(wl.element, entry_order_, seen_);  // a mesh's entries keep their element
  apply_order(wl.feature, entry_order_, seen_);  // and the feature their history belongs to
  apply_order(wl.shear, entry_order_, seen_);
  apply_order(wl.force, entry_order_, seen_);
  apply_order(wl.roll, entry_order_, seen_);
}

template void cell_order<2>(const std::vector<Space<2>::Vec>&, const std::vector<ParticleId>&,
                            const Space<2>::Vec&, const Space<2>::Vec&, double,
                            std::vector<std::uint32_t>&, std::vector<CellKey>&);
template void cell_order<3>(const std::vector<Space<3>::Vec>&, const std::vector<ParticleId>&,
                            const Space<3>::Vec&, const Space<3>::Vec&, double,
                            std::vector<std::uint32_t>&, std::vector<CellKey>&);
template class GrainReorder<2>;
template class GrainReorder<3>;

}  // namespace sable
