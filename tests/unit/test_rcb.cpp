// Recursive coordinate bisection (mpi/rcb.hpp), on one process: each point's owner is the part
// whose box holds it, the boxes tile the domain, the counts are even to within the histogram's
// resolution, a lopsided bias moves the cuts, and the distance to a box ignores the domain's
// own faces (a grain that left the domain stays near its side's boxes).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "sable/core/rng.hpp"
#include "sable/mpi/rcb.hpp"

namespace sable {
namespace {

using Vec3 = Space<3>::Vec;

std::vector<Vec3> uniform_points(std::size_t n, const Vec3& lo, const Vec3& hi) {
  Rng rng(5);
  std::vector<Vec3> x(n);
  for (auto& p : x)
    for (int d = 0; d < 3; ++d) p[d] = rng.uniform(lo[d], hi[d]);
  return x;
}

TEST(Rcb, OwnersBoxesAndEvenCounts) {
  const Vec3 lo(0.0, 0.0, 0.0), hi(1.0, 2.0, 4.0);
  const std::vector<Vec3> x = uniform_points(20000, lo, hi);
  for (int parts : {1, 2, 3, 5, 7, 8}) {
    Rcb<3> rcb;
    rcb.cut(lo, hi, parts, x, [](std::vector<std::int64_t>&) {});
    ASSERT_EQ(rcb.parts(), parts);
    std::vector<int> count(static_cast<std::size_t>(parts), 0);
    for (const Vec3& p : x) {
      const int o = rcb.owner(p);
      ASSERT_GE(o, 0);
      ASSERT_LT(o, parts);
      ++count[static_cast<std::size_t>(o)];
      EXPECT_EQ(rcb.distance2(p, o), 0.0);  // inside its own box
      const auto& b = rcb.box(o);
      for (int d = 0; d < 3; ++d) ASSERT_TRUE(b.lo[d] <= p[d] && p[d] <= b.hi[d]);
    }
    // The boxes tile the domain: their volumes add up to its volume (cuts are binary
    // fractions of the extents: exact up to the sum's round-off).
    double volume = 0.0;
    for (int k = 0; k < parts; ++k) volume += (rcb.box(k).hi - rcb.box(k).lo).prod();
    EXPECT_NEAR(volume, 8.0, 1e-12);
    // Even shares: each cut is placed at a bin edge (1,024 bins a box), so a part may hold
    // up to about one bin's grains (20,000 / 1,024 per level, ~20) per level of cuts more or
    // less than its share; allow 3 levels' worth, 60.
    for (int k = 0; k < parts; ++k)
      EXPECT_NEAR(count[static_cast<std::size_t>(k)], 20000.0 / parts, 60.0) << parts << " parts";
  }
}

TEST(Rcb, BiasMakesLopsidedCutsAndOutsidePointsStayNear) {
  const Vec3 lo(0.0, 0.0, 0.0), hi(1.0, 1.0, 1.0);
  const std::vector<Vec3> x = uniform_points(10000, lo, hi);
  Rcb<3> rcb;
  rcb.cut(
      lo, hi, 2, x, [](std::vector<std::int64_t>&) {}, 0.3);
  int below = 0;
  for (const Vec3& p : x) below += rcb.owner(p) == 0 ? 1 : 0;
  EXPECT_NEAR(below, 0.3 * 5000, 30.0);  // 30 % of the lower half's share of 5,000
  // A point past the domain's face (z > 1 or < 0 here, the longest-axis tie going to x) is
  // in no box, yet at distance 0 from the part on its side: the domain's faces do not bound.
  const Vec3 out(0.99, 0.5, 1.7);
  const int o = rcb.owner(out);
  EXPECT_EQ(rcb.distance2(out, o), 0.0);
  EXPECT_GT(rcb.distance2(Vec3(0.99, 0.5, 0.5), 1 - rcb.owner(Vec3(0.99, 0.5, 0.5))), 0.0);
}

// The reduction is what makes many processes agree: points split between two "processes",
// each cutting with the other's histogram added, find the cut one process finds with all (one
// level of cuts, two parts: the other's histogram is that of the same box).
TEST(Rcb, SplitPointsWithAReductionCutAsOne) {
  const Vec3 lo(0.0, 0.0, 0.0), hi(2.0, 1.0, 1.0);
  const std::vector<Vec3> x = uniform_points(8000, lo, hi);
  std::vector<Vec3> first(x.begin(), x.begin() + 3000), second(x.begin() + 3000, x.end());
  Rcb<3> whole, a;
  whole.cut(lo, hi, 2, x, [](std::vector<std::int64_t>&) {});
  // `a` holds the first share; the reduction adds the second share's histogram, which is what
  // an MPI_SUM over two processes gives.
  std::vector<std::vector<std::int64_t>> levels;
  Rcb<3> twin;
  twin.cut(lo, hi, 2, second, [&](std::vector<std::int64_t>& c) { levels.push_back(c); });
  std::size_t level = 0;
  a.cut(lo, hi, 2, first, [&](std::vector<std::int64_t>& c) {
    for (std::size_t k = 0; k < c.size(); ++k) c[k] += levels[level][k];
    ++level;
  });
  ASSERT_EQ(levels.size(), 1u);
  for (int k = 0; k < 2; ++k) {
    EXPECT_EQ(a.box(k).lo, whole.box(k).lo);
    EXPECT_EQ(a.box(k).hi, whole.box(k).hi);
  }
}

}  // namespace
}  // namespace sable
