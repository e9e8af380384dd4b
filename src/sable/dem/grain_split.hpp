// How one of the DEM step's parallel loops shares the grains among the threads: one contiguous
// block of grains per thread, sized by how fast each thread has been in that loop. Each loop
// (the opening grain loop, the pair pass, the closing grain loop) has its own split: each
// ends with the threads meeting, and their work differs in kind (the closing loop's wall
// contacts and gathered grains sit in some blocks only), so one cut balancing their sum
// would leave the threads waiting for one another in turn.
//
// Why measured: the threads of a run do not all run at one speed. A VM's vCPUs differ (on the
// project's 2-vCPU VM, by up to 30 % over the same blocks, and which one is the slower changes
// over minutes: bench/ab_dense.sh -s sees it), desktop CPUs with fast and slow cores differ by
// design, and any other job on the machine slows one thread. With an even cut every step
// waits for the slowest thread. Each thread's blocks are timed (a clock read at each end of
// its share of a loop), each step yields the shares that would have equalised those times,
// and every kEvery steps the shares move halfway to the median of those estimates (one step
// hit by a hiccup of the host does not move the cut).
//
// Why it cannot change the results: no grain's or contact's arithmetic depends on the block
// it falls in (the pair pass adds each grain's terms in list order whatever the cut, see
// dem_solver_impl.hpp), so the cut, and the timing behind it, changes the speed only: the same bits
// for any cut, which tests check with deliberately lopsided shares.
//
// Why chunks as well: the cut balances the threads on average, not step by step. Each
// thread's time for the same block wanders by a few % from one step to the next (a host's
// other work, a stolen tick), and every loop ends with the threads meeting: each step waits
// for whichever was slower that time, 6-8 % of a two-thread step in all on the project's VM
// (bench/ab_dense.sh -s). In the loops whose grains are independent (the opening and closing
// grain loops: no grain's operations read what another's write) a thread takes its own block
// in chunks, and then the chunks its partners have not reached yet. Which thread does a grain
// changes the speed only, never the bits. The pair pass shares only the tail of each block
// (share_tail()), and from both ends: its threads add forces to their own grains as they go,
// in list order, which a chunk done by another thread cannot. A block's own thread takes its
// tail from the front (take_chunk()) and goes on adding; a thread done with its own takes
// chunks from the far end (take_chunk_from_back()), whose entries only store their forces;
// those grains, from where the two ends met (first_taken_from_back()), are summed after the
// pass (see DemSolver::dry_pair_forces). So only as many grains are left to that slower sum
// as the step's imbalance asked for.
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace sable {

class GrainSplit {
 public:
  static constexpr std::size_t kEvery = 32;  // steps per look at the threads' times

  // Block b holds grains [bounds()[b], bounds()[b + 1]); its grains from tail(b) on are
  // shared in chunks, the others are its own thread's.
  int blocks() const { return bound_.empty() ? 0 : static_cast<int>(bound_.size()) - 1; }
  const std::uint32_t* bounds() const { return bound_.data(); }
  std::uint32_t tail(int b) const { return tail_[static_cast<std::size_t>(b)]; }

  // From the next cut on: share only the last `fraction` (0, 1] of each block's work, in
  // chunks of `chunk` grains (the default: whole blocks, kChunk). With one block nothing is
  // shared when fraction < 1: its thread does it all, and a tail would only cost its
  // caller's extra work (the pair pass's gather).
  void share_tail(double fraction, std::uint32_t chunk) {
    tail_fraction_ = fraction;
    chunk_ = chunk;
    recut_ = true;
  }
  // Made for n grains in `blocks` blocks, and not asking to be made again.
  bool fits(std::size_t n, int blocks) const {
    return !recut_ && this->blocks() == blocks && bound_.back() == n;
  }

  // Cuts n grains into `blocks` blocks, block b with about share(b) of the work. The work
  // before grain g is begin[g] + g (its list entries, and one per grain) when begin holds
  // n + 1 offsets, else g (no list for these grains yet).
  void cut(std::size_t n, int blocks, std::span<const std::uint32_t> begin);

  // Seconds that block b's work took in one loop, added by the thread that did it; `work`:
  // how much of the block's work (in the cut's units, see cut()) it did in that time, when
  // others took some (chunks).
  void add_busy(int b, double seconds) { busy_[static_cast<std::size_t>(b)].seconds += seconds; }
  void add_busy(int b, double seconds, double work) {
    Busy& busy = busy_[static_cast<std::size_t>(b)];
    busy.seconds += seconds;
    busy.work += work;
    busy.partial = true;
  }

  // Chunks (see the header comment). open_chunks() before the loop, on one thread; then each
  // thread does its own blocks' grains before the tail, takes their tails' chunks with
  // take_chunk() until they are done, then the others' (take_chunk(), or
  // take_chunk_from_back() from the tail's far end). A chunk is [g0, g1); false once block b
  // has none left.
  static constexpr std::uint32_t kChunk = 256;  // grains: a few us of work, one atomic op
  void open_chunks() {
    for (std::size_t b = 0; b < tail_.size(); ++b)
      ends_[b].v.store(pack(tail_[b], bound_[b + 1]), std::memory_order_relaxed);
  }
  // The next chunk from the front of block b's tail.
  bool take_chunk(int b, std::uint32_t& g0, std::uint32_t& g1) {
    std::atomic<std::uint64_t>& ends = ends_[static_cast<std::size_t>(b)].v;
    // Relaxed: the chunks are disjoint whichever order the threads take them in; the loop's
    // closing barrier orders the rest.
    std::uint64_t now = ends.load(std::memory_order_relaxed);
    for (;;) {
      const std::uint32_t front = low(now), back = high(now);
      if (front >= back) return false;  // no write once done
      g0 = front;
      g1 = back - front > chunk_ ? front + chunk_ : back;
      if (ends.compare_exchange_weak(now, pack(g1, back), std::memory_order_relaxed)) return true;
    }
  }
  // The next chunk from the back of block b's tail.
  bool take_chunk_from_back(int b, std::uint32_t& g0, std::uint32_t& g1) {
    std::atomic<std::uint64_t>& ends = ends_[static_cast<std::size_t>(b)].v;
    std::uint64_t now = ends.load(std::memory_order_relaxed);
    for (;;) {
      const std::uint32_t front = low(now), back = high(now);
      if (front >= back) return false;
      g1 = back;
      g0 = back - front > chunk_ ? back - chunk_ : front;
      if (ends.compare_exchange_weak(now, pack(front, g0), std::memory_order_relaxed)) return true;
    }
  }
  // Once the loop is over: the first of block b's grains that take_chunk_from_back() handed
  // out (the block's end when none).
  std::uint32_t first_taken_from_back(int b) const {
    return high(ends_[static_cast<std::size_t>(b)].v.load(std::memory_order_relaxed));
  }
  // At the end of each step: the step's times become an estimate of the shares; every kEvery
  // steps the shares move towards the estimates, and fits() turns false once a cut would move
  // by more than kMinShift of the work since the last cut.
  void end_step();

  // Fixed shares instead of measured ones (one per block, any positive numbers: they are
  // normalised). For tests: any cut gives the same bits.
  void fix_shares(std::vector<double> shares);
  double share(int b) const { return share_[static_cast<std::size_t>(b)]; }

 private:
  static constexpr double kMinShift = 0.005;  // a smaller move is not worth a new cut
  static constexpr double kGain = 0.5;        // how far the shares move towards the estimate
  void reset(int blocks);
  void move_shares();

  std::vector<std::uint32_t> bound_;
  std::vector<std::uint32_t> tail_;  // per block: its first shared grain
  double tail_fraction_ = 1.0;
  std::uint32_t chunk_ = kChunk;
  std::vector<double> share_;      // per block, summing to 1
  std::vector<double> next_;       // scratch of move_shares()
  std::vector<double> cut_share_;  // the shares of the last cut
  std::vector<double> work_;       // per block: its work at the last cut
  std::vector<double> estimate_;   // kEvery rows of `blocks` estimated shares
  struct alignas(64) Busy {        // one cache line per block: its thread alone writes it
    double seconds = 0.0;
    double work = 0.0;     // work done in those seconds, when `partial`
    bool partial = false;  // else: the whole block
  };
  std::vector<Busy> busy_;
  // Per block, its own cache line: the front and the back of what is left of its tail.
  static std::uint64_t pack(std::uint32_t front, std::uint32_t back) {
    return std::uint64_t{front} | std::uint64_t{back} << 32;
  }
  static std::uint32_t low(std::uint64_t e) { return static_cast<std::uint32_t>(e); }
  static std::uint32_t high(std::uint64_t e) { return static_cast<std::uint32_t>(e >> 32); }
  struct alignas(64) Ends {
    std::atomic<std::uint64_t> v{0};
  };
  std::vector<Ends> ends_;
  std::size_t steps_ = 0;  // rows of estimate_ filled
  bool fixed_ = false, recut_ = false;
};

}  // namespace sable
