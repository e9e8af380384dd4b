#include "sable/dem/grain_split.hpp"

#include <algorithm>
#include <cmath>

namespace sable {

void GrainSplit::reset(int blocks) {
  const auto nb = static_cast<std::size_t>(blocks);
  share_.assign(nb, 1.0 / blocks);
  next_.assign(nb, 0.0);
  cut_share_ = share_;
  work_.assign(nb, 0.0);
  estimate_.assign(nb * kEvery, 0.0);
  busy_.assign(nb, Busy{});
  ends_ = std::vector<Ends>(nb);  // atomics: made, not copied
  steps_ = 0;
  fixed_ = false;
}

void GrainSplit::fix_shares(std::vector<double> shares) {
  double total = 0.0;
  for (double s : shares) total += s;
  reset(static_cast<int>(shares.size()));
  for (std::size_t b = 0; b < shares.size(); ++b) share_[b] = shares[b] / total;
  fixed_ = true;
  recut_ = true;
}

void GrainSplit::cut(std::size_t n, int blocks, std::span<const std::uint32_t> begin) {
  if (share_.size() != static_cast<std::size_t>(blocks)) reset(blocks);
  const auto nb = static_cast<std::size_t>(blocks);
  const bool listed = begin.size() == n + 1;
  auto work_before = [&](std::size_t g) { return (listed ? double(begin[g]) : 0.0) + double(g); };
  const double total = work_before(n);
  bound_.assign(nb + 1, 0);
  bound_[nb] = static_cast<std::uint32_t>(n);
  double cumulative = 0.0;
  for (std::size_t b = 1; b < nb; ++b) {
    cumulative += share_[b - 1];
    const double target = total * cumulative;
    // The last grain g whose work before it is at most the target (binary search: the work
    // before g never decreases with g).
    std::size_t lo = bound_[b - 1], hi = n;
    while (hi - lo > 1) {
      const std::size_t mid = lo + (hi - lo) / 2;
      (work_before(mid) <= target ? lo : hi) = mid;
    }
    bound_[b] = static_cast<std::uint32_t>(lo);
  }
  for (std::size_t b = 0; b < nb; ++b)
    work_[b] = work_before(bound_[b + 1]) - work_before(bound_[b]);
  // Each block's tail: from the first grain whose work to the block's end is at most the
  // tail's fraction of the block's work.
  tail_.assign(nb, 0);
  for (std::size_t b = 0; b < nb; ++b) {
    if (tail_fraction_ >= 1.0) {
      tail_[b] = bound_[b];
      continue;
    }
    if (nb == 1) {
      tail_[b] = bound_[b + 1];
      continue;
    }
    const double from = work_before(bound_[b + 1]) - tail_fraction_ * work_[b];
    std::size_t lo = bound_[b], hi = bound_[b + 1];  // work_before(hi) >= from
    while (lo < hi) {
      const std::size_t mid = lo + (hi - lo) / 2;
      if (work_before(mid) >= from)
        hi = mid;
      else
        lo = mid + 1;
    }
    tail_[b] = static_cast<std::uint32_t>(lo);
  }
  cut_share_ = share_;  // same size: no allocation
  recut_ = false;
}

void GrainSplit::end_step() {
  const std::size_t nb = busy_.size();
  if (nb < 2 || work_.size() != nb) return;
  // The step's estimate: were block b's work done at the speed it had in this step (work over
  // seconds), the shares that equalise the times are proportional to those speeds. A block
  // shared in chunks counts the work its own thread did. A block not timed (a loop run on one
  // thread) makes no estimate.
  double total = 0.0;
  bool timed = true;
  double* const row = estimate_.data() + steps_ * nb;
  for (std::size_t b = 0; b < nb; ++b) {
    const double work = busy_[b].partial ? busy_[b].work : work_[b];
    timed = timed && busy_[b].seconds > 0.0 && work > 0.0;
    row[b] = timed ? work / busy_[b].seconds : 0.0;
    total += row[b];
    busy_[b] = Busy{};
  }
  if (!timed || fixed_) return;
  for (std::size_t b = 0; b < nb; ++b) row[b] /= total;
  if (++steps_ == kEvery) move_shares();
}

// The shares move halfway to each block's median estimate over the last kEvery steps; none
// falls below a fifth of the even share (a quarter before they are normalised: their sum is
// then at most 1.25), so a thread stalled for a while still gets work, and a fresh measure
// of its speed.
void GrainSplit::move_shares() {
  const std::size_t nb = share_.size();
  std::array<double, kEvery> column{};
  double total = 0.0;
  for (std::size_t b = 0; b < nb; ++b) {
    for (std::size_t s = 0; s < kEvery; ++s) column[s] = estimate_[s * nb + b];
    std::nth_element(column.begin(), column.begin() + kEvery / 2, column.end());
    const double median = column[kEvery / 2];
    next_[b] = std::max(share_[b] + kGain * (median - share_[b]), 0.25 / double(nb));
    total += next_[b];
  }
  double before = 0.0, after = 0.0, shift = 0.0;  // the largest move of a cut, in work
  for (std::size_t b = 0; b < nb; ++b) {
    share_[b] = next_[b] / total;
    before += cut_share_[b];
    after += share_[b];
    shift = std::max(shift, std::abs(after - before));
  }
  steps_ = 0;
  if (shift > kMinShift) recut_ = true;
}

}  // namespace sable
