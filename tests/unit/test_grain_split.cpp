// GrainSplit (dem/grain_split.hpp): the cut of the grains into one block per thread, and the
// shares that follow the threads' measured speeds. The times here are made up: block b's
// seconds in a step are its work over a chosen speed, so the shares that equalise the
// threads' times are known exactly (proportional to the speeds).
#include <gtest/gtest.h>

#include <omp.h>

#include <atomic>
#include <cstdint>
#include <numeric>
#include <vector>

#include "sable/dem/grain_split.hpp"

namespace {

using sable::GrainSplit;

// Offsets of a list where grain g has (g % 7) entries: uneven work per grain.
std::vector<std::uint32_t> uneven_offsets(std::size_t n) {
  std::vector<std::uint32_t> begin(n + 1, 0);
  for (std::size_t g = 0; g < n; ++g) begin[g + 1] = begin[g] + static_cast<std::uint32_t>(g % 7);
  return begin;
}

double work_before(const std::vector<std::uint32_t>& begin, std::size_t g) {
  return double(begin[g]) + double(g);
}

// One step's timed loops: block b's seconds = its work / speeds[b] (any unit).
void time_step(GrainSplit& split, const std::vector<std::uint32_t>& begin,
               const std::vector<double>& speeds) {
  for (int b = 0; b < split.blocks(); ++b) {
    const double work =
        work_before(begin, split.bounds()[b + 1]) - work_before(begin, split.bounds()[b]);
    split.add_busy(b, work / speeds[static_cast<std::size_t>(b)]);
  }
  split.end_step();
}

// Runs `steps` steps, cutting again whenever the split asks (as DemSolver::update_pair_split does).
void run(GrainSplit& split, const std::vector<std::uint32_t>& begin, int blocks,
         const std::vector<double>& speeds, int steps) {
  const std::size_t n = begin.size() - 1;
  for (int s = 0; s < steps; ++s) {
    if (!split.fits(n, blocks)) split.cut(n, blocks, begin);
    time_step(split, begin, speeds);
  }
}

// Even shares: each cut is the last grain whose work before it is at most b/blocks of the
// total (exact: the binary search's definition), the bounds cover every grain once.
TEST(GrainSplit, CutsAtTheShareOfTheWork) {
  const std::size_t n = 10007;
  const auto begin = uneven_offsets(n);
  GrainSplit split;
  for (int blocks : {1, 2, 3, 8}) {
    split.cut(n, blocks, begin);
    ASSERT_EQ(split.blocks(), blocks);
    EXPECT_EQ(split.bounds()[0], 0u);
    EXPECT_EQ(split.bounds()[blocks], n);
    const double total = work_before(begin, n);
    for (int b = 1; b < blocks; ++b) {
      const std::size_t g = split.bounds()[b];
      const double target = total * b / blocks;
      EXPECT_LE(work_before(begin, g), target + 1e-9) << blocks << " blocks, cut " << b;
      EXPECT_GT(work_before(begin, g + 1), target - 1e-9) << blocks << " blocks, cut " << b;
    }
    EXPECT_TRUE(split.fits(n, blocks));
    EXPECT_FALSE(split.fits(n + 1, blocks));
  }
}

// Grains the list does not hold yet (offsets for fewer grains): cut by count, evenly.
TEST(GrainSplit, CutsByCountWithoutAList) {
  GrainSplit split;
  const std::vector<std::uint32_t> stale{0, 3, 5};  // two grains' offsets, for 1000 grains
  split.cut(1000, 4, stale);
  for (int b = 0; b <= 4; ++b) EXPECT_EQ(split.bounds()[b], 250u * static_cast<unsigned>(b));
}

// Two threads, one at 0.6 of the other's speed: the shares go to 1/1.6 and 0.6/1.6, where
// both threads' times are equal. The gap halves every kEvery steps (gain 0.5): from 0.125
// it is under 1e-4 after 12 looks (tolerance 1e-3). The cut moves only once the shares have
// moved by more than 0.005 of the work since the last cut, and lies within one grain's work
// (at most 7 + 1 of ~40,000) of its shares: tolerance 0.005 + 1e-3 on the cut's share.
TEST(GrainSplit, SharesFollowTheThreadsSpeeds) {
  const std::size_t n = 10000;
  const auto begin = uneven_offsets(n);
  GrainSplit split;
  run(split, begin, 2, {1.0, 0.6}, 12 * static_cast<int>(GrainSplit::kEvery));
  EXPECT_NEAR(split.share(0), 1.0 / 1.6, 1e-3);
  EXPECT_NEAR(split.share(1), 0.6 / 1.6, 1e-3);
  if (!split.fits(n, 2)) split.cut(n, 2, begin);
  const double total = work_before(begin, n);
  EXPECT_NEAR(work_before(begin, split.bounds()[1]) / total, 1.0 / 1.6, 6e-3);
  // Four threads, speeds 1 : 2 : 3 : 4: shares 0.1, 0.2, 0.3, 0.4.
  GrainSplit four;
  run(four, begin, 4, {1.0, 2.0, 3.0, 4.0}, 16 * static_cast<int>(GrainSplit::kEvery));
  for (int b = 0; b < 4; ++b) EXPECT_NEAR(four.share(b), 0.1 * (b + 1), 1e-3) << "block " << b;
}

// Equal speeds, but in one step of every kEvery a block takes 100 times longer (a host that
// takes the vCPU away for a while): the median ignores it, the shares stay even to the last
// bit and the cut is not made again.
TEST(GrainSplit, OneSlowStepDoesNotMoveTheCut) {
  const std::size_t n = 5000;
  const auto begin = uneven_offsets(n);
  GrainSplit split;
  split.cut(n, 2, begin);
  for (int look = 0; look < 4; ++look)
    for (std::size_t s = 0; s < GrainSplit::kEvery; ++s)
      time_step(split, begin, s == 5 ? std::vector<double>{0.01, 1.0} : std::vector{1.0, 1.0});
  EXPECT_EQ(split.share(0), 0.5);
  EXPECT_EQ(split.share(1), 0.5);
  EXPECT_TRUE(split.fits(n, 2));
}

// A thread that barely runs keeps a fifth of the even share (floor a quarter before the
// shares are normalised), so that it is still measured; the other gets the rest.
TEST(GrainSplit, AStalledThreadKeepsSomeWork) {
  const std::size_t n = 5000;
  const auto begin = uneven_offsets(n);
  GrainSplit split;
  run(split, begin, 2, {1.0, 1e-4}, 20 * static_cast<int>(GrainSplit::kEvery));
  EXPECT_GE(split.share(1), 0.2 / 2);
  EXPECT_LT(split.share(1), 0.25 / 2 + 1e-12);
  EXPECT_NEAR(split.share(0) + split.share(1), 1.0, 1e-12);
}

// Fixed shares (normalised) set the cut and ignore the times.
TEST(GrainSplit, FixedSharesIgnoreTheTimes) {
  const std::size_t n = 8000;
  const auto begin = uneven_offsets(n);
  GrainSplit split;
  split.fix_shares({1.0, 3.0});
  EXPECT_FALSE(split.fits(n, 2));
  run(split, begin, 2, {1.0, 0.1}, 4 * static_cast<int>(GrainSplit::kEvery));
  EXPECT_EQ(split.share(0), 0.25);
  const double total = work_before(begin, n);
  EXPECT_NEAR(work_before(begin, split.bounds()[1]) / total, 0.25, 1e-3);
}

}  // namespace

namespace {

// Takes every chunk of `split` on `threads` threads, each its own block first and then the
// others' (as the grain loops and the pair pass do); counts how often each grain was handed
// out. `chunk`: the most grains a chunk may hold.
std::vector<int> take_all_chunks(GrainSplit& split, std::size_t n, int threads,
                                 std::uint32_t chunk = GrainSplit::kChunk) {
  std::vector<std::atomic<int>> taken(n);
  split.open_chunks();
#pragma omp parallel num_threads(threads)
  {
    const int thread = omp_get_thread_num(), blocks = split.blocks();
    std::uint32_t g0 = 0, g1 = 0;
    for (int k = 0; k < blocks; ++k) {
      const int b = (thread + k) % blocks;
      while (split.take_chunk(b, g0, g1)) {
        // A chunk lies inside its block's tail and is at most `chunk` grains.
        EXPECT_GE(g0, split.tail(b));
        EXPECT_LE(g1, split.bounds()[b + 1]);
        EXPECT_LT(g0, g1);
        EXPECT_LE(g1 - g0, chunk);
        for (std::uint32_t g = g0; g < g1; ++g) taken[g].fetch_add(1);
      }
    }
  }
  std::vector<int> counts(n);
  for (std::size_t g = 0; g < n; ++g) counts[g] = taken[g].load();
  return counts;
}

}  // namespace

// The chunks of the grain loops (dem/grain_split.hpp): whatever thread takes which, every
// grain is handed out exactly once per loop (exact: a grain done twice or never would change
// the step's results), also when the threads race for the same blocks and when a loop runs
// again after open_chunks().
TEST(GrainSplit, ChunksHandOutEveryGrainOnce) {
  const std::size_t n = 10007;  // not a multiple of the chunk
  GrainSplit split;
  for (int blocks : {1, 2, 3}) {
    split.cut(n, blocks, {});
    for (int threads : {1, 2, 4}) {
      for (int round = 0; round < 2; ++round) {
        const auto counts = take_all_chunks(split, n, threads);
        for (std::size_t g = 0; g < n; ++g)
          ASSERT_EQ(counts[g], 1) << "grain " << g << ", " << blocks << " blocks, " << threads
                                  << " threads, round " << round;
      }
    }
  }
}

// Shared tails (the pair pass's, share_tail()): block b's tail starts at the first grain
// whose work to the block's end is at most the fraction of the block's work (exact: the
// binary search's definition); the chunks hand out every tail grain exactly once and no
// other grain (those are the block's own thread's, in order), in chunks of at most the
// chosen size. One block has no tail: its thread does it all.
TEST(GrainSplit, TailsHoldTheirShareOfTheWorkAndNothingElseIsShared) {
  const std::size_t n = 10007;
  const auto begin = uneven_offsets(n);
  GrainSplit split;
  split.share_tail(0.15, 64);
  EXPECT_FALSE(split.fits(n, 2));  // a new tail asks for a new cut
  for (int blocks : {1, 2, 3}) {
    split.cut(n, blocks, begin);
    if (blocks == 1) {
      EXPECT_EQ(split.tail(0), n);
    }
    for (int b = 0; blocks > 1 && b < blocks; ++b) {
      const std::uint32_t g0 = split.bounds()[b], g1 = split.bounds()[b + 1], z = split.tail(b);
      ASSERT_GT(z, g0);
      ASSERT_LT(z, g1);
      const double work = work_before(begin, g1) - work_before(begin, g0);
      EXPECT_LE(work_before(begin, g1) - work_before(begin, z), 0.15 * work + 1e-9);
      EXPECT_GT(work_before(begin, g1) - work_before(begin, z - 1), 0.15 * work - 1e-9);
    }
    for (int threads : {1, 2, 4}) {
      const auto counts = take_all_chunks(split, n, threads, 64);
      for (int b = 0; b < blocks; ++b)
        for (std::uint32_t g = split.bounds()[b]; g < split.bounds()[b + 1]; ++g)
          ASSERT_EQ(counts[g], g >= split.tail(b) ? 1 : 0)
              << "grain " << g << ", " << blocks << " blocks, " << threads << " threads";
    }
  }
}

// The pair pass's two-ended tails (take_chunk() from the front, take_chunk_from_back() from
// the far end): block 0's tail of 500 grains, chunks of 64, taken in a fixed interleaving
// (two from the front for each one from the back) until none is left. Every tail grain is
// handed out exactly once, the front's chunks are consecutive from the tail's start, the
// back's from the block's end down, they meet without overlap, and first_taken_from_back() is
// where the back's chunks begin (exact: a grain handed out twice or never would change the
// step's results; one taken from the back and not known as such would not be gathered).
TEST(GrainSplit, TwoEndedTailsMeetWithoutOverlap) {
  const std::size_t n = 2000;
  GrainSplit split;
  split.share_tail(0.5, 64);
  split.cut(n, 2, {});
  const std::uint32_t tail = split.tail(0), end = split.bounds()[1];
  ASSERT_EQ(end - tail, 500u);  // half of block 0's 1,000 grains (cut by count)
  split.open_chunks();
  EXPECT_EQ(split.first_taken_from_back(0), end);  // nothing taken yet
  std::vector<int> counts(n, 0);
  std::uint32_t front = tail, back = end, g0 = 0, g1 = 0;
  for (int round = 0;; ++round) {
    bool any = false;
    for (int k = 0; k < 2 && split.take_chunk(0, g0, g1); ++k, any = true) {
      EXPECT_EQ(g0, front);
      EXPECT_LE(g1 - g0, 64u);
      front = g1;
      for (std::uint32_t g = g0; g < g1; ++g) ++counts[g];
    }
    if (split.take_chunk_from_back(0, g0, g1)) {
      any = true;
      EXPECT_EQ(g1, back);
      EXPECT_LE(g1 - g0, 64u);
      back = g0;
      for (std::uint32_t g = g0; g < g1; ++g) ++counts[g];
    }
    if (!any) break;
    ASSERT_LT(round, 100);
  }
  EXPECT_EQ(front, back);
  EXPECT_EQ(split.first_taken_from_back(0), back);
  EXPECT_LT(back, end);  // the back did take some
  for (std::size_t g = 0; g < n; ++g)
    ASSERT_EQ(counts[g], g >= tail && g < end ? 1 : 0) << "grain " << g;
  // Block 1, not touched from the back: all from the front, first_taken_from_back() its end.
  while (split.take_chunk(1, g0, g1)) {
  }
  EXPECT_EQ(split.first_taken_from_back(1), n);
}

// The same on threads racing for both ends: each thread takes its own block's tail from the
// front and the others' from the back, as the pair pass does. Every tail grain once, and the
// grains taken from the back are exactly [first_taken_from_back(b), end of block b).
TEST(GrainSplit, RacingEndsHandOutEveryTailGrainOnce) {
  const std::size_t n = 10007;
  const auto begin = uneven_offsets(n);
  GrainSplit split;
  split.share_tail(0.3, 16);
  for (int blocks : {2, 3}) {
    split.cut(n, blocks, begin);
    for (int round = 0; round < 4; ++round) {
      std::vector<std::atomic<int>> front(n), back(n);
      split.open_chunks();
#pragma omp parallel num_threads(blocks)
      {
        const int thread = omp_get_thread_num();
        std::uint32_t g0 = 0, g1 = 0;
        while (split.take_chunk(thread, g0, g1))
          for (std::uint32_t g = g0; g < g1; ++g) front[g].fetch_add(1);
        for (int k = 1; k < blocks; ++k)
          while (split.take_chunk_from_back((thread + k) % blocks, g0, g1))
            for (std::uint32_t g = g0; g < g1; ++g) back[g].fetch_add(1);
      }
      for (int b = 0; b < blocks; ++b) {
        const std::uint32_t from = split.first_taken_from_back(b);
        ASSERT_GE(from, split.tail(b));
        for (std::uint32_t g = split.bounds()[b]; g < split.bounds()[b + 1]; ++g) {
          const bool in_tail = g >= split.tail(b);
          ASSERT_EQ(front[g].load() + back[g].load(), in_tail ? 1 : 0) << "grain " << g;
          ASSERT_EQ(back[g].load(), g >= from ? 1 : 0) << "grain " << g << ", block " << b;
        }
      }
    }
  }
}

// A block shared in chunks is timed by its own thread for the grains that thread did: the
// estimate is its speed in grains per second. Block 0's thread did 600 grains in 1 s, block
// 1's thread 400 of its 5,000 in 1 s (its partner took the rest): speeds 600 and 400, so the
// shares move halfway from 0.5 towards 0.6 and 0.4 after kEvery steps (exact up to the
// divisions' rounding: 1e-12).
TEST(GrainSplit, ChunkedBlocksAreTimedByTheGrainsTheirThreadDid) {
  GrainSplit split;
  split.cut(10000, 2, {});
  for (std::size_t s = 0; s < GrainSplit::kEvery; ++s) {
    split.add_busy(0, 1.0, 600);
    split.add_busy(1, 1.0, 400);
    split.end_step();
  }
  EXPECT_NEAR(split.share(0), 0.55, 1e-12);
  EXPECT_NEAR(split.share(1), 0.45, 1e-12);
  EXPECT_FALSE(split.fits(10000, 2));  // a move of 5 % of the work asks for a new cut
}
