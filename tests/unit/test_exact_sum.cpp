// ExactSum (core/exact_sum.hpp): the exact sum of doubles, correctly rounded, whatever the
// order of the terms and however they are split into partial sums (MPI ranks' totals).
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <vector>

#include "sable/core/exact_sum.hpp"
#include "sable/core/rng.hpp"

namespace sable {
namespace {

__extension__ using Int128 = __int128;  // the exact reference below

double exact(const std::vector<double>& xs) {
  ExactSum s;
  for (double x : xs) s.add(x);
  return s.value();
}

// Terms a naive sum gets wrong: cancellation of large terms and ties in the last bit.
TEST(ExactSum, CancellationAndRoundingAreExact) {
  EXPECT_EQ(exact({1e100, 1.0, -1e100}), 1.0);  // naive: 0
  EXPECT_EQ(exact({1.0, 1e-30, -1.0}), 1e-30);
  // 1 + 2^-53 is a tie between 1 and 1 + 2^-52: to even, 1.
  EXPECT_EQ(exact({1.0, std::ldexp(1.0, -53)}), 1.0);
  // Anything beyond the tie, however small, rounds up.
  EXPECT_EQ(exact({1.0, std::ldexp(1.0, -53), std::ldexp(1.0, -300)}), 1.0 + std::ldexp(1.0, -52));
  // The same just below: 1 - 2^-54 is a tie between 1 - 2^-53 and 1, to even: 1.
  EXPECT_EQ(exact({1.0, -std::ldexp(1.0, -54)}), 1.0);
  EXPECT_EQ(exact({-1.5, -2.25}), -3.75);
  // 0.1 + 0.2 - 0.3 in doubles is exactly 2^-55 (the naive sum gives 2^-54).
  EXPECT_EQ(exact({0.1, 0.2, -0.3}), std::ldexp(1.0, -55));
  EXPECT_EQ(exact({}), 0.0);
  EXPECT_EQ(exact({0.0, -0.0}), 0.0);
}

// The extremes of the format: no intermediate overflow, subnormals summed exactly.
TEST(ExactSum, ExtremesOfTheFormat) {
  const double big = std::numeric_limits<double>::max();
  EXPECT_EQ(exact({big, big, -big}), big);
  EXPECT_EQ(exact({big, big}), std::numeric_limits<double>::infinity());  // rounds past max
  const double tiny = std::numeric_limits<double>::denorm_min();
  EXPECT_EQ(exact({tiny, tiny, tiny}), 3 * tiny);
  EXPECT_EQ(exact({std::numeric_limits<double>::min(), -tiny}),
            std::numeric_limits<double>::min() - tiny);
  EXPECT_TRUE(std::isnan(exact({1.0, std::nan("")})));
  EXPECT_EQ(exact({1.0, std::numeric_limits<double>::infinity()}),
            std::numeric_limits<double>::infinity());
  EXPECT_TRUE(std::isnan(
      exact({std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()})));
}

// Against an exact reference: multiples of 2^-40 below 2^40 in magnitude, whose sum of
// 10,000 is an exact 128-bit integer (times 2^-40); converting that integer to double rounds
// correctly (IEEE conversion), so the two must agree to the bit.
TEST(ExactSum, EqualsTheCorrectlyRoundedIntegerSum) {
  Rng rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    ExactSum s;
    Int128 reference = 0;
    for (int k = 0; k < 10000; ++k) {
      const int bits = 1 + static_cast<int>(rng.uniform() * 79);  // 2^-40 .. 2^39 scale
      const double mag = std::floor(rng.uniform() * std::ldexp(1.0, std::min(bits, 53)));
      const double unit = std::ldexp(1.0, bits - std::min(bits, 53) - 40);
      const double x = (rng.uniform() < 0.5 ? -1.0 : 1.0) * mag * unit;
      s.add(x);
      reference += static_cast<Int128>(std::ldexp(x, 40));
    }
    EXPECT_EQ(s.value(), std::ldexp(static_cast<double>(reference), -40)) << "trial " << trial;
  }
}

// The point of it: any order, any split into partial sums merged in any order, the same
// limbs and the same bits.
TEST(ExactSum, IndependentOfOrderAndOfPartialSums) {
  Rng rng(11);
  std::vector<double> xs(5000);
  for (double& x : xs)
    x = (rng.uniform() - 0.5) * std::ldexp(1.0, static_cast<int>(rng.uniform() * 120) - 60);
  ExactSum whole;
  for (double x : xs) whole.add(x);
  const double expect = whole.value();
  for (int trial = 0; trial < 20; ++trial) {
    for (std::size_t k = xs.size() - 1; k > 0; --k)
      std::swap(xs[k], xs[static_cast<std::size_t>(rng.uniform() * static_cast<double>(k + 1))]);
    const int parts = 1 + trial % 7;  // "ranks"
    std::vector<ExactSum> partial(static_cast<std::size_t>(parts));
    for (std::size_t k = 0; k < xs.size(); ++k) partial[k % partial.size()].add(xs[k]);
    ExactSum total;
    for (auto it = partial.rbegin(); it != partial.rend(); ++it) total.merge(*it);
    EXPECT_EQ(std::bit_cast<std::uint64_t>(total.value()), std::bit_cast<std::uint64_t>(expect));
    EXPECT_EQ(total.carried_limbs(), whole.carried_limbs());
  }
  // A naive sum of the same terms does depend on their order (else this test would prove
  // nothing about the accumulator): over 20 orders, more than one result.
  std::vector<double> naive;
  for (int trial = 0; trial < 20; ++trial) {
    std::reverse(xs.begin() + trial, xs.end());
    double s = 0.0;
    for (double x : xs) s += x;
    naive.push_back(s);
  }
  std::sort(naive.begin(), naive.end());
  EXPECT_GT(std::unique(naive.begin(), naive.end()) - naive.begin(), 1);
}

// ExactRun, the fast front: the same exact sum as ExactSum::add() term by term, whether the
// terms fit its window (near the first term), fall outside it (2^40 larger or smaller), are
// subnormal or zero, and over more terms than one window holds (8,192) before it flushes.
TEST(ExactSum, ExactRunAddsExactlyTheSame) {
  Rng rng(3);
  for (int trial = 0; trial < 10; ++trial) {
    ExactSum direct, through_run;
    {
      ExactRun run(through_run);
      for (int k = 0; k < 30000; ++k) {
        const double u = rng.uniform();
        const int exponent = u < 0.9 ? static_cast<int>(rng.uniform() * 20) - 10  // in the window
                                     : static_cast<int>(rng.uniform() * 200) - 100;  // mostly out
        double x = (rng.uniform() - 0.5) * std::ldexp(1.0, exponent);
        if (k % 997 == 0) x = std::numeric_limits<double>::denorm_min() * (k % 5);
        direct.add(x);
        run.add(x);
      }
    }
    EXPECT_EQ(through_run.carried_limbs(), direct.carried_limbs()) << "trial " << trial;
    EXPECT_EQ(std::bit_cast<std::uint64_t>(through_run.value()),
              std::bit_cast<std::uint64_t>(direct.value()));
  }
  // A run whose first term is tiny (below the window's range) sends everything to the sum.
  ExactSum a, b;
  {
    ExactRun run(a);
    for (double x : {std::numeric_limits<double>::denorm_min(), 1.0, -2.5, 1e300}) {
      run.add(x);
      b.add(x);
    }
  }
  EXPECT_EQ(a.carried_limbs(), b.carried_limbs());
}

}  // namespace
}  // namespace sable
