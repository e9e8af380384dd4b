// The DEM force pass's working set: the entries of the neighbour list that can touch soon.
//
// The neighbour list (collision/neighbor_list.hpp) holds every pair within the skin, rebuilt
// from the cells when a grain has moved half a skin. In a dense bed more than half of those
// candidates are apart (bench/ab_dense.sh's bed, 0.5 mm skin, 1.5 mm grains: 103,000
// candidates, 46,500 touching), yet the force pass tests each of them and the accumulation
// visits each twice. The near list is a second, inner level: the indices of the candidates
// whose gap was below a smaller inner skin when it was made, with its own per-grain
// incidence. It is remade from the neighbour list (a filter, no cell search) when some grain
// has moved half an inner skin since, and after every rebuild of the neighbour list. A
// candidate left out had a gap of at least the inner skin, so it cannot touch before the
// next remake: the forces are the same bits as with the whole list, only the apart entries
// are not visited. Entries left out are told to the caller (`drop`), which clears what a
// pass would have cleared for an apart contact.
//
// The inner skin is chosen at each remake from the fastest grain, so that a remake is due
// after about kStepsPerRemake steps, but never below a tenth of the skin (a still bed) nor
// above the skin (a fast flow, where it is the neighbour list itself). Wet runs keep every
// candidate (`keep_all`): a capillary bridge acts across a gap.
//
// Solver scratch, not model state: not saved in snapshots, remade on the first step after a
// resume; the neighbour list and every force are unchanged by it.
#pragma once

#include <cstdint>
#include <vector>

#include "sable/collision/neighbor_list.hpp"
#include "sable/core/grow.hpp"
#include "sable/core/particles.hpp"
#include "sable/world/domain.hpp"

namespace sable {

template <int D>
class NearList {
 public:
  using Vec = typename Space<D>::Vec;
  static constexpr double kStepsPerRemake = 20.0;
  static constexpr double kMinSkinFraction = 0.1;

  // Entries of the neighbour list's pairs, ascending; grain i is the first member of entries
  // index[first_begin[i] .. first_begin[i+1]) and the second member of the entries
  // second_pairs[second_begin[i] .. second_begin[i+1]) (ascending): the fixed order in which
  // the DEM accumulation sums a grain's contacts, whatever the number of threads.
  std::vector<std::uint32_t> index;
  std::vector<std::uint32_t> first_begin, second_begin, second_pairs;
  double skin = 0.0;          // inner skin of the last remake
  std::uint64_t remakes = 0;  // for diagnostics and benchmarks

  // True when the near list no longer holds every pair that can touch: the neighbour list
  // was rebuilt since, the grains changed, or some grain moved half an inner skin.
  // `domain`: the displacement measured over every process's grains (world/domain.hpp).
  bool stale(const ParticleStore<D>& p, const NeighborList<D>& nl, bool keep_all,
             const Domain<D>& domain = Domain<D>{}) const;
  // The same test, given the grains' largest squared displacement since reference() (read
  // only when reference() holds every grain): the DEM step measures it in its drift loop.
  bool stale_after(double max_d2, const ParticleStore<D>& p, const NeighborList<D>& nl,
                   bool keep_all) const;
  // The positions at the last remake.
  const std::vector<Vec>& reference() const { return x_ref_; }

  // Remake from the neighbour list at the current positions; `drop(k)` for every pair entry
  // k left out, in parallel (drop(k) may touch entry k only). `dt` sizes the inner skin from
  // the fastest grain (of every process: `domain`, so that all choose the same skin and
  // remake at the same steps).
  template <class Drop>
  void remake(const ParticleStore<D>& p, const NeighborList<D>& nl, double dt, bool keep_all,
              const Domain<D>& domain, Drop drop) {
    filter(p, nl, dt, keep_all, domain);
    const auto n_pairs = static_cast<std::ptrdiff_t>(nl.pairs.size());
    assign_ahead(kept_, nl.pairs.size(), std::uint8_t{0});  // core/grow.hpp
    for (std::uint32_t k : index) kept_[k] = 1;
#pragma omp parallel for schedule(static) if (n_pairs >= 8192)
    for (std::ptrdiff_t k = 0; k < n_pairs; ++k)
      if (!kept_[static_cast<std::size_t>(k)]) drop(static_cast<std::size_t>(k));
  }

 private:
  void filter(const ParticleStore<D>& p, const NeighborList<D>& nl, double dt, bool keep_all,
              const Domain<D>& domain);
  void make_incidence(const NeighborList<D>& nl, std::size_t n_grains);

  std::vector<Vec> x_ref_;  // positions at the last remake
  std::uint64_t outer_build_ = ~std::uint64_t{0};
  std::size_t outer_size_ = 0;
  bool kept_all_ = false;
  std::vector<std::uint32_t> scratch_;
  std::vector<std::vector<std::uint32_t>> blocks_;  // per-thread blocks of the filter
  std::vector<std::uint8_t> kept_;                  // per pair entry: in the near list
};

}  // namespace sable
