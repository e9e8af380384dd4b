#include "sable/collision/neighbor_list.hpp"

#include <omp.h>
#include <algorithm>
#include <cmath>
#include <tuple>
#include <utility>

#include "sable/core/grow.hpp"
#include "sable/core/parallel.hpp"

namespace sable {

template <int D>
double max_displacement2(const std::vector<typename Space<D>::Vec>& x,
                         const std::vector<typename Space<D>::Vec>& ref) {
  using Vec = typename Space<D>::Vec;
  double max_d2 = 0.0;  // a max is exact whatever the order: thread-independent
  const auto n = static_cast<std::ptrdiff_t>(x.size());
  const Vec* const xp = x.data();
  const Vec* const rp = ref.data();
#pragma omp parallel for schedule(static) reduction(max : max_d2) if (n >= kMinParallelScan)
  for (std::ptrdiff_t k = 0; k < n; ++k) max_d2 = std::max(max_d2, (xp[k] - rp[k]).squaredNorm());
  return max_d2;
}

template <int D>
bool NeighborList<D>::needs_rebuild(const ParticleStore<D>& p, const std::vector<Wall<D>>& walls,
                                    double margin) const {
  if (x_ref.size() != p.size()) return true;
  return needs_rebuild_after(max_displacement2<D>(p.x, x_ref), walls, margin);
}

template <int D>
bool NeighborList<D>::needs_rebuild_after(double max_d2, const std::vector<Wall<D>>& walls,
                                          double margin) const {
  if (max_d2 < 0.0 || wall_ref.size() != walls.size() || wall_ref_turn.size() != walls.size())
    return true;
  const double dp = std::sqrt(max_d2) + margin;
  // Two grains close in by at most 2 dp; a grain and wall w by at most dp + dw, dw the
  // largest distance the wall's surface moved (a turning body's far end moves fastest; for a
  // wall that only translates, exactly the shift of its point), against the wall's reach.
  if (2.0 * dp >= skin) return true;
  const bool reaches = wall_reach.size() == walls.size();
  for (std::size_t w = 0; w < walls.size(); ++w) {
    const double dw = walls[w].moved_since(wall_ref[w], wall_ref_turn[w], domain_lo, domain_hi);
    if (dp + dw >= (reaches ? wall_reach[w] : skin)) return true;
  }
  return false;
}

template <int D>
double NeighborList<D>::list_reach(const Wall<D>& wall) const {
  const bool still = wall.velocity == Vec::Zero() && !wall.turning();
  return wall.is_mesh() && still ? 0.5 * skin : skin;
}

template <int D>
void NeighborList<D>::build_cells(const ParticleStore<D>& p) {
  const std::size_t n = p.size();
  double rmax = 0.0;
  for (double r : p.radius) rmax = std::max(rmax, r);
  // Cells hold every partner within 2 rmax + skin; never more cells than ~4 per grain, so a
  // huge domain with few grains costs memory O(N), not O(volume).
  cell_size_ = std::max(2.0 * rmax + skin, 1e-300);
  // A domain wider than 1e300 (or than a double holds: an infinite extent) is cut as if it
  // were 1e300 wide, and the count of cells stays a double until it is small: a tiny cell in
  // a huge domain would otherwise overflow the cast to int, or the product of the counts.
  const Vec ext = (domain_hi - domain_lo).cwiseMax(cell_size_).cwiseMin(1e300);
  for (;;) {
    double total = 1.0;
    for (int d = 0; d < D; ++d) {
      const double cells = ext[d] / cell_size_;
      ncell_[d] = cells < 1e9 ? std::max(1, static_cast<int>(cells)) : 1'000'000'000;
      total *= static_cast<double>(ncell_[d]);
    }
    if (total <= 4.0 * static_cast<double>(n) + 64.0) break;
    cell_size_ *= 1.26;
  }
  std::size_t total = 1;
  for (int d = 0; d < D; ++d) total *= static_cast<std::size_t>(ncell_[d]);
  cell_of_.resize(n);
  cell_start_.assign(total + 1, 0);
  for (std::size_t k = 0; k < n; ++k) {
    std::size_t c = 0;
    for (int d = D - 1; d >= 0; --d) {
      // Grains outside the domain fall into the boundary cells: still correct, only slower
      // (NaN into the first: the cast is made on a value known to fit).
      const double q = std::floor((p.x[k][d] - domain_lo[d]) / cell_size_);
      const int ci = q > 0.0 ? (q < ncell_[d] - 1.0 ? static_cast<int>(q) : ncell_[d] - 1) : 0;
      c = c * static_cast<std::size_t>(ncell_[d]) + static_cast<std::size_t>(ci);
    }
    cell_of_[k] = static_cast<std::uint32_t>(c);
    ++cell_start_[c + 1];
  }
  for (std::size_t c = 0; c < total; ++c) cell_start_[c + 1] += cell_start_[c];
  cell_items_.resize(n);
  scratch_.assign(cell_start_.begin(), cell_start_.end() - 1);
  for (std::size_t k = 0; k < n; ++k)
    cell_items_[scratch_[cell_of_[k]]++] = static_cast<std::uint32_t>(k);
}

// The partners j > i of grain i within reach, ascending, appended to `out`. The 3^D cells
// around grain i's come as 3^(D-1) rows along axis 0, the fastest-varying in the cell index:
// a row's cells are consecutive there, so its grains are one run of cell_items_, read without
// a division per cell (the same candidates in the same order as cell by cell).
template <int D>
void NeighborList<D>::partners_of(const ParticleStore<D>& p, std::size_t i,
                                  std::vector<std::uint32_t>& out) const {
  const std::size_t first = out.size();
  std::array<int, D> ci;
  std::size_t c = cell_of_[i];
  for (int d = 0; d < D; ++d) {
    ci[d] = static_cast<int>(c % static_cast<std::size_t>(ncell_[d]));
    c /= static_cast<std::size_t>(ncell_[d]);
  }
  const int x0 = std::max(ci[0] - 1, 0), x1 = std::min(ci[0] + 1, ncell_[0] - 1);
  const Vec xi = p.x[i];
  const double ri = p.radius[i];
  const bool fixed = p.inv_mass[i] == 0.0;
  constexpr int rows = D == 3 ? 9 : 3;
  for (int r = 0; r < rows; ++r) {
    const int y = ci[1] + r % 3 - 1;
    if (y < 0 || y >= ncell_[1]) continue;
    std::size_t row = static_cast<std::size_t>(y);
    if constexpr (D == 3) {
      const int z = ci[2] + r / 3 - 1;
      if (z < 0 || z >= ncell_[2]) continue;
      row += static_cast<std::size_t>(z) * static_cast<std::size_t>(ncell_[1]);
    }
    row *= static_cast<std::size_t>(ncell_[0]);
    const std::uint32_t end = cell_start_[row + static_cast<std::size_t>(x1) + 1];
    for (std::uint32_t k = cell_start_[row + static_cast<std::size_t>(x0)]; k < end; ++k) {
      const std::uint32_t j = cell_items_[k];
      if (j <= i) continue;
      if (fixed && p.inv_mass[j] == 0.0) continue;  // two fixed grains
      const double reach = ri + p.radius[j] + skin;
      if ((xi - p.x[j]).squaredNorm() < reach * reach) out.push_back(j);
    }
  }
  std::sort(out.begin() + static_cast<std::ptrdiff_t>(first), out.end());
}

// In parallel: each thread collects the pairs of a contiguous, ascending block of grains
// (static schedule), and the blocks are joined in order, so the list is the same sorted list
// whatever the number of threads.
template <int D>
void NeighborList<D>::build_pairs(const ParticleStore<D>& p, PairList<D>& out) {
  out.clear();
  const auto n = static_cast<std::ptrdiff_t>(p.size());
  const bool parallel = n >= kMinParallelScan;
  const int threads = parallel ? omp_get_max_threads() : 1;
  thread_i_.resize(static_cast<std::size_t>(threads));
  thread_j_.resize(static_cast<std::size_t>(threads));
#pragma omp parallel num_threads(threads) if (parallel)
  {
    // The block grows in vectors of the thread's own: the threads' vector objects in
    // thread_j_ sit side by side, in one cache line, and a push_back on each, in turn from
    // both cores, made the search as slow on two threads as on one.
    const auto t = static_cast<std::size_t>(omp_get_thread_num());
    std::vector<std::uint32_t> bi = std::move(thread_i_[t]), bj = std::move(thread_j_[t]);
    bi.clear();
    bj.clear();
#pragma omp for schedule(static) nowait
    for (std::ptrdiff_t ii = 0; ii < n; ++ii) {
      partners_of(p, static_cast<std::size_t>(ii), bj);
      bi.resize(bj.size(), static_cast<std::uint32_t>(ii));
    }
    thread_i_[t] = std::move(bi);
    thread_j_[t] = std::move(bj);
  }
  std::size_t total = 0;
  for (const auto& block : thread_j_) total += block.size();
  reserve_ahead(out.i, total);  // see core/grow.hpp
  reserve_ahead(out.j, total);
  for (std::size_t t = 0; t < thread_i_.size(); ++t) {
    out.i.insert(out.i.end(), thread_i_[t].begin(), thread_i_[t].end());
    out.j.insert(out.j.end(), thread_j_[t].begin(), thread_j_[t].end());
  }
  assign_ahead(out.shear, out.size(), Vec(Vec::Zero()));
  assign_ahead(out.force, out.size(), Vec(Vec::Zero()));
  if (bridges) assign_ahead(out.bridge, out.size(), PairList<D>::kNoBridge);
  if (rolling) assign_ahead(out.roll, out.size(), Space<D>::zero_rot());
}

// The cell coordinates of x, clamped into the grid (as build_cells places the grains).
template <int D>
std::array<int, D> NeighborList<D>::cell_coords(const Vec& x) const {
  std::array<int, D> c;
  for (int d = 0; d < D; ++d) {
    const double q = std::floor((x[d] - domain_lo[d]) / cell_size_);
    c[d] = q > 0.0 ? (q < ncell_[d] - 1.0 ? static_cast<int>(q) : ncell_[d] - 1) : 0;
  }
  return c;
}

// A bounded wall's elements binned in the grains' cells: each element in every cell its box,
// grown by `reach`, overlaps (clamped into the grid like the grains, so a grain within reach
// of an element finds it in its own cell). Ascending elements within a cell.
template <int D>
void NeighborList<D>::bin_elements(const Wall<D>& wall, double reach) {
  const auto& mesh = *wall.mesh();
  std::size_t total = 1;
  for (int d = 0; d < D; ++d) total *= static_cast<std::size_t>(ncell_[d]);
  element_start_.assign(total + 1, 0);
  auto for_cells = [&](std::uint32_t e, auto&& f) {
    Vec lo, hi;
    mesh.element_box(e, lo, hi);
    const auto a = cell_coords((lo.array() - reach).matrix());
    const auto b = cell_coords((hi.array() + reach).matrix());
    std::array<int, D> c = a;
    for (;;) {
      std::size_t index = 0;
      for (int d = D - 1; d >= 0; --d)
        index = index * static_cast<std::size_t>(ncell_[d]) + static_cast<std::size_t>(c[d]);
      f(index);
      int d = 0;
      while (d < D && c[d] == b[d]) c[d] = a[d], ++d;
      if (d == D) break;
      ++c[d];
    }
  };
  for (std::uint32_t e = 0; e < mesh.elements(); ++e)
    for_cells(e, [&](std::size_t c) { ++element_start_[c + 1]; });
  for (std::size_t c = 0; c < total; ++c) element_start_[c + 1] += element_start_[c];
  element_items_.resize(element_start_[total]);
  scratch_.assign(element_start_.begin(), element_start_.end() - 1);
  for (std::uint32_t e = 0; e < mesh.elements(); ++e)
    for_cells(e, [&](std::size_t c) { element_items_[scratch_[c]++] = e; });
}

// Grain-wall candidates: for each grain (ascending), each wall (ascending) whose surface is
// within the wall's reach (list_reach); a mesh's elements within it, ascending, from the
// grain's cell.
template <int D>
void NeighborList<D>::build_wall_pairs(const ParticleStore<D>& p, const std::vector<Wall<D>>& walls,
                                       WallPairList<D>& out) {
  out.clear();
  double rmax = 0.0;
  for (double r : p.radius) rmax = std::max(rmax, r);
  auto add = [&](std::size_t i, std::size_t w, std::uint32_t e) {
    out.i.push_back(static_cast<std::uint32_t>(i));
    out.wall.push_back(static_cast<std::uint32_t>(w));
    out.element.push_back(e);
  };
  Vec n;
  wall_reach.resize(walls.size());
  for (std::size_t w = 0; w < walls.size(); ++w) {
    const Wall<D>& wall = walls[w];
    const double reach = wall_reach[w] = list_reach(wall);
    if (wall.is_mesh()) {
      bin_elements(wall, rmax + reach);
      for (std::size_t i = 0; i < p.size(); ++i) {
        if (p.inv_mass[i] == 0.0) continue;
        const std::uint32_t c = cell_of_[i];
        for (std::uint32_t k = element_start_[c]; k < element_start_[c + 1]; ++k)
          if (wall.mesh()->element_distance(p.x[i], element_items_[k]) - p.radius[i] < reach)
            add(i, w, element_items_[k]);
      }
      continue;
    }
    for (std::size_t i = 0; i < p.size(); ++i)
      if (p.inv_mass[i] != 0.0 && wall.distance(p.x[i], n) - p.radius[i] < reach) add(i, w, 0);
  }
  // Found wall by wall; the list is sorted by (grain, wall, element): a stable sort by grain.
  const std::size_t m = out.size();
  scratch_.assign(p.size() + 1, 0);
  for (std::size_t k = 0; k < m; ++k) ++scratch_[out.i[k] + 1];
  for (std::size_t i = 0; i < p.size(); ++i) scratch_[i + 1] += scratch_[i];
  new_order_.resize(m);
  for (std::size_t k = 0; k < m; ++k)
    new_order_[scratch_[out.i[k]]++] = static_cast<std::uint32_t>(k);
  auto permute = [&](std::vector<std::uint32_t>& a) {
    tmp_.resize(m);
    for (std::size_t k = 0; k < m; ++k) tmp_[k] = a[new_order_[k]];
    a.swap(tmp_);
  };
  permute(out.i);
  permute(out.wall);
  permute(out.element);
  assign_ahead(out.feature, out.size(), std::uint32_t{0});
  assign_ahead(out.shear, out.size(), Vec(Vec::Zero()));
  assign_ahead(out.force, out.size(), Vec(Vec::Zero()));
  if (rolling) assign_ahead(out.roll, out.size(), Space<D>::zero_rot());
}

// Copy history of entries present in both sorted lists (keyed by key(list, k), ordered).
// `skipped(o)` is called for every old entry with no match in the new list, in order.
template <class List, class Key, class Skipped>
static void carry_history(const List& old_list, List& new_list, Key key, Skipped skipped) {
  std::size_t o = 0;
  for (std::size_t k = 0; k < new_list.size(); ++k) {
    while (o < old_list.size() && key(old_list, o) < key(new_list, k)) skipped(o++);
    if (o < old_list.size() && key(old_list, o) == key(new_list, k)) {
      if constexpr (requires { new_list.feature; }) new_list.feature[k] = old_list.feature[o];
      new_list.shear[k] = old_list.shear[o];
      new_list.force[k] = old_list.force[o];
      if constexpr (requires { new_list.bridge; })
        if (!new_list.bridge.empty()) new_list.bridge[k] = old_list.bridge[o];
      if (!new_list.roll.empty() && old_list.roll.size() == old_list.size())
        new_list.roll[k] = old_list.roll[o];
      ++o;
    }
  }
  while (o < old_list.size()) skipped(o++);
}

template <int D>
void NeighborList<D>::build(const ParticleStore<D>& p, const std::vector<Wall<D>>& walls) {
  build_cells(p);
  build_pairs(p, new_pairs_);
  const bool had_bridges = pairs.bridge.size() == pairs.size() && !pairs.bridge.empty();
  carry_history(
      pairs, new_pairs_, [](const auto& l, std::size_t k) { return std::pair(l.i[k], l.j[k]); },
      [&](std::size_t o) {
        if (had_bridges && bridges && pairs.bridge[o] >= 0.0)
          dropped_bridges.push_back({pairs.i[o], pairs.j[o], pairs.bridge[o]});
      });
  std::swap(pairs, new_pairs_);
  build_wall_pairs(p, walls, new_wall_pairs_);
  carry_history(
      wall_pairs, new_wall_pairs_,
      [](const auto& l, std::size_t k) { return std::tuple(l.i[k], l.wall[k], l.element[k]); },
      [](std::size_t) {});
  std::swap(wall_pairs, new_wall_pairs_);
  incidence_valid_ = false;
  x_ref = p.x;
  wall_ref.resize(walls.size());
  wall_ref_turn.resize(walls.size());
  for (std::size_t w = 0; w < walls.size(); ++w) {
    wall_ref[w] = walls[w].point;
    wall_ref_turn[w] = walls[w].orientation;
  }
  ++builds;
}

template <int D>
void NeighborList<D>::update_incidence(std::size_t n) {
  if (incidence_valid_ && wall_begin.size() == n + 1) return;
  wall_begin.assign(n + 1, 0);
  for (std::size_t k = 0; k < wall_pairs.size(); ++k) ++wall_begin[wall_pairs.i[k] + 1];
  for (std::size_t i = 0; i < n; ++i) wall_begin[i + 1] += wall_begin[i];
  incidence_valid_ = true;
}

template double max_displacement2<2>(const std::vector<Space<2>::Vec>&,
                                     const std::vector<Space<2>::Vec>&);
template double max_displacement2<3>(const std::vector<Space<3>::Vec>&,
                                     const std::vector<Space<3>::Vec>&);
template class NeighborList<2>;
template class NeighborList<3>;

}  // namespace sable
