#include "sable/dem/near_list.hpp"

#include <omp.h>
#include <algorithm>
#include <cmath>
#include <limits>

#include "sable/core/grow.hpp"
#include "sable/core/parallel.hpp"

namespace sable {

template <int D>
bool NearList<D>::stale(const ParticleStore<D>& p, const NeighborList<D>& nl, bool keep_all,
                        const Domain<D>& domain) const {
  const bool measure = !keep_all && x_ref_.size() == p.size();
  double max_d2 = measure ? max_displacement2<D>(p.x, x_ref_) : 0.0;
  domain.max(&max_d2, 1);
  return stale_after(max_d2, p, nl, keep_all);
}

template <int D>
bool NearList<D>::stale_after(double max_d2, const ParticleStore<D>& p, const NeighborList<D>& nl,
                              bool keep_all) const {
  if (outer_build_ != nl.builds || outer_size_ != nl.pairs.size() || x_ref_.size() != p.size() ||
      kept_all_ != keep_all)
    return true;
  if (keep_all) return false;  // every candidate is in: only a rebuild changes that
  // Two grains close in by at most twice the largest displacement.
  return 4.0 * max_d2 >= skin * skin;
}

template <int D>
void NearList<D>::filter(const ParticleStore<D>& p, const NeighborList<D>& nl, double dt,
                         bool keep_all, const Domain<D>& domain) {
  double max_v2 = 0.0;  // a max: thread-independent
  const Vec* const vp = p.v.data();
  const auto n = static_cast<std::ptrdiff_t>(p.size());
#pragma omp parallel for schedule(static) reduction(max : max_v2) if (n >= kMinParallelScan)
  for (std::ptrdiff_t k = 0; k < n; ++k) max_v2 = std::max(max_v2, vp[k].squaredNorm());
  domain.max(&max_v2, 1);
  // Half the inner skin is covered in about kStepsPerRemake steps at the current top speed.
  skin = keep_all ? std::numeric_limits<double>::infinity()
                  : std::clamp(2.0 * kStepsPerRemake * std::sqrt(max_v2) * dt,
                               kMinSkinFraction * nl.skin, nl.skin);
  // In parallel over contiguous blocks of entries, joined in order: the same ascending list
  // whatever the number of threads.
  const auto& pl = nl.pairs;
  const auto n_pairs = static_cast<std::ptrdiff_t>(pl.size());
  const bool parallel = n_pairs >= 8192;
  const int threads = parallel ? omp_get_max_threads() : 1;
  blocks_.resize(static_cast<std::size_t>(threads));
  const std::uint32_t *const pi = pl.i.data(), *const pj = pl.j.data();
  const Vec* const x = p.x.data();
  const double* const radius = p.radius.data();
  const double s = skin;
#pragma omp parallel num_threads(threads) if (parallel)
  {
    // A vector of the thread's own: the threads' vector objects in blocks_ share a cache
    // line, which push_back from both cores would bounce between them (see build_pairs).
    const auto t = static_cast<std::size_t>(omp_get_thread_num());
    std::vector<std::uint32_t> block = std::move(blocks_[t]);
    block.clear();
#pragma omp for schedule(static) nowait
    for (std::ptrdiff_t k = 0; k < n_pairs; ++k) {
      const double reach = radius[pi[k]] + radius[pj[k]] + s;
      if (keep_all || (x[pi[k]] - x[pj[k]]).squaredNorm() < reach * reach)
        block.push_back(static_cast<std::uint32_t>(k));
    }
    blocks_[t] = std::move(block);
  }
  std::size_t total = 0;
  for (const auto& block : blocks_) total += block.size();
  index.clear();
  reserve_ahead(index, total);  // see core/grow.hpp
  for (const auto& block : blocks_) index.insert(index.end(), block.begin(), block.end());
  make_incidence(nl, p.size());
  x_ref_ = p.x;
  outer_build_ = nl.builds;
  outer_size_ = pl.size();
  kept_all_ = keep_all;
  ++remakes;
}

template <int D>
void NearList<D>::make_incidence(const NeighborList<D>& nl, std::size_t n) {
  const auto& pl = nl.pairs;
  first_begin.assign(n + 1, 0);
  second_begin.assign(n + 1, 0);
  for (std::uint32_t k : index) {
    ++first_begin[pl.i[k] + 1];
    ++second_begin[pl.j[k] + 1];
  }
  for (std::size_t i = 0; i < n; ++i) {
    first_begin[i + 1] += first_begin[i];
    second_begin[i + 1] += second_begin[i];
  }
  // Counting sort of the entries by their second member; ascending within each grain.
  reserve_ahead(second_pairs, index.size());
  second_pairs.resize(index.size());
  scratch_.assign(second_begin.begin(), second_begin.end() - 1);
  for (std::uint32_t k : index) second_pairs[scratch_[pl.j[k]]++] = k;
}

template class NearList<2>;
template class NearList<3>;

}  // namespace sable
