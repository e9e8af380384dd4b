// Grain generation: lattice, random insertion, radius distributions and LAMMPS data files.
//
// A scenario with a seed must always produce the same grains, and the pour example must start
// from exactly the bed of the LIGGGHTS benchmark (gen_lattice.py), so positions are checked
// against their exact construction wherever the arithmetic allows it.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "sable/core/error.hpp"
#include "sable/generation/generate.hpp"
#include "sable/scenario/config.hpp"
#include "test_data.hpp"

namespace {

namespace fs = std::filesystem;
using sable::GrainsConfig;
using sable::GrainSeed;
using sable::InputError;
using sable::RadiusConfig;
using sable::RegionConfig;
using sable::Vec3a;

// ---------------------------------------------------------------- helpers

sable::SourceLoc test_loc() {
  return sable::SourceLoc{"scene.toml", 17, 3};
}

GrainsConfig lattice_block(const Vec3a& lo, const Vec3a& hi, double r, double spacing,
                           std::size_t count) {
  GrainsConfig b;
  b.generator = "lattice";
  b.material = "glass";
  b.radius.kind = RadiusConfig::Kind::kMono;
  b.radius.value = r;
  b.region.kind = RegionConfig::Kind::kBox;
  b.region.lo = lo;
  b.region.hi = hi;
  b.spacing = spacing;
  b.count = count;
  b.loc = test_loc();
  return b;
}

GrainsConfig random_box_block(const Vec3a& lo, const Vec3a& hi, std::size_t count) {
  GrainsConfig b;
  b.generator = "random";
  b.material = "glass";
  b.radius.kind = RadiusConfig::Kind::kUniform;
  b.radius.value = 0.03;
  b.radius.spread = 0.2;
  b.region.kind = RegionConfig::Kind::kBox;
  b.region.lo = lo;
  b.region.hi = hi;
  b.count = count;
  b.loc = test_loc();
  return b;
}

double dist(const GrainSeed& a, const GrainSeed& b, int dim) {
  double d2 = 0.0;
  for (int d = 0; d < dim; ++d) d2 += (a.x[d] - b.x[d]) * (a.x[d] - b.x[d]);
  return std::sqrt(d2);
}

// Brute force: number of pairs closer than the sum of their radii (up to a relative 1e-12,
// the rounding of the distance itself).
std::size_t count_overlaps(const std::vector<GrainSeed>& g, int dim) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < g.size(); ++i)
    for (std::size_t j = i + 1; j < g.size(); ++j)
      if (dist(g[i], g[j], dim) < (g[i].radius + g[j].radius) * (1.0 - 1e-12)) ++n;
  return n;
}

bool inside_box(const GrainSeed& g, const Vec3a& lo, const Vec3a& hi, int dim) {
  for (int d = 0; d < dim; ++d)
    if (g.x[d] - g.radius < lo[d] - 1e-12 || g.x[d] + g.radius > hi[d] + 1e-12) return false;
  return true;
}

// Scratch directory per test, removed afterwards.
class GenerationFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("sable_gen_" + std::to_string(::getpid()) + "_" +
                                        info->test_suite_name() + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) const {
    std::string p = (dir_ / name).string();
    std::ofstream(p) << text;
    return p;
  }
  fs::path dir_;
};

// ---------------------------------------------------------------- lattice

// Guards the documented site order (x fastest, then y, then z, first site at lo + s/2) and the
// exact count; 1e-12 absolute covers only the rounding of lo + (i + 1/2) s at O(1) coordinates.
TEST(GenerationLattice, SitesInOrder3D) {
  const Vec3a lo{0.25, -1.5, 2.0};
  const double s = 1.0, r = 0.4;
  const Vec3a hi{lo[0] + 4.0, lo[1] + 3.0, lo[2] + 5.0};  // 4 x 3 x 5 = 60 sites
  const std::size_t count = 50;                           // last layer only partly filled
  const auto g = sable::generate_grains(lattice_block(lo, hi, r, s, count), 3, 7, {});
  ASSERT_EQ(g.size(), count);
  for (std::size_t m = 0; m < g.size(); ++m) {
    const std::size_t layer = m / 12;  // 4 x 3 sites a layer
    const double i = static_cast<double>(m % 4), j = static_cast<double>((m / 4) % 3),
                 k = static_cast<double>(layer);
    EXPECT_NEAR(g[m].x[0], lo[0] + (i + 0.5) * s, 1e-12) << "grain " << m;
    EXPECT_NEAR(g[m].x[1], lo[1] + (j + 0.5) * s, 1e-12) << "grain " << m;
    EXPECT_NEAR(g[m].x[2], lo[2] + (k + 0.5) * s, 1e-12) << "grain " << m;
    EXPECT_EQ(g[m].radius, r);
    EXPECT_TRUE(inside_box(g[m], lo, hi, 3)) << "grain " << m;
  }
}

// Guards the 2D lattice (x fastest, then y; z stays exactly 0) and its exact count; 1e-12 as
// above, the rounding of lo + (i + 1/2) s.
TEST(GenerationLattice, SitesInOrder2D) {
  const Vec3a lo{-1.0, 0.5, 0.0}, hi{2.0, 3.0, 0.0};  // spacing 0.5: 6 x 5 = 30 sites
  const double s = 0.5, r = 0.2;
  const auto g = sable::generate_grains(lattice_block(lo, hi, r, s, 30), 2, 7, {});
  ASSERT_EQ(g.size(), 30u);
  for (std::size_t m = 0; m < g.size(); ++m) {
    const std::size_t row = m / 6;  // 6 sites a row
    const double i = static_cast<double>(m % 6), j = static_cast<double>(row);
    EXPECT_NEAR(g[m].x[0], lo[0] + (i + 0.5) * s, 1e-12) << "grain " << m;
    EXPECT_NEAR(g[m].x[1], lo[1] + (j + 0.5) * s, 1e-12) << "grain " << m;
    EXPECT_EQ(g[m].x[2], 0.0) << "grain " << m;
    EXPECT_TRUE(inside_box(g[m], lo, hi, 2)) << "grain " << m;
  }
}

// Guards the jitter for both generators: every coordinate within +-jitter of its site (1e-12 is
// the site's rounding), the jitter really used (some deviation above jitter/2), and no overlaps
// when the spacing leaves room for it (s >= 2 r_max + 2 jitter).
TEST(GenerationLattice, JitterBoundedAndNoOverlap) {
  for (const char* rng : {"sable", "numpy-pcg64"}) {
    for (int dim : {2, 3}) {
      SCOPED_TRACE(std::string(rng) + " dim " + std::to_string(dim));
      const Vec3a lo{0.0, 0.0, 0.0}, hi{6.0, 5.0, 4.0};
      const double s = 1.0, r = 0.4, jitter = 0.09;  // 2 r + 2 jitter = 0.98 s
      const std::size_t count = dim == 3 ? 120 : 30;
      GrainsConfig b = lattice_block(lo, hi, r, s, count);
      b.jitter = jitter;
      b.jitter_rng = rng;
      const auto g = sable::generate_grains(b, dim, 99, {});
      ASSERT_EQ(g.size(), count);
      double max_dev = 0.0;
      for (std::size_t m = 0; m < g.size(); ++m) {
        const std::size_t ij[3] = {m % 6, dim == 3 ? (m / 6) % 5 : m / 6, m / 30};
        for (int d = 0; d < dim; ++d) {
          const double dev = g[m].x[d] - (lo[d] + (static_cast<double>(ij[d]) + 0.5) * s);
          EXPECT_LE(std::abs(dev), jitter + 1e-12) << "grain " << m << " axis " << d;
          max_dev = std::max(max_dev, std::abs(dev));
        }
        EXPECT_TRUE(inside_box(g[m], lo, hi, dim)) << "grain " << m;
      }
      EXPECT_GT(max_dev, 0.5 * jitter);
      EXPECT_EQ(count_overlaps(g, dim), 0u);
    }
  }
}

// Guards the cylinder region for the lattice: sites of the bounding box outside the cylinder
// are skipped, so every grain lies wholly inside (1e-12: rounding of rho).
TEST(GenerationLattice, CylinderRegionKeepsGrainsInside) {
  GrainsConfig b = lattice_block({0, 0, 0}, {0, 0, 0}, 0.2, 0.5, 30);
  b.region.kind = RegionConfig::Kind::kCylinder;
  b.region.center = {1.0, -1.0, 0.0};
  b.region.radius = 1.5;
  b.region.zlo = 0.0;
  b.region.zhi = 2.0;
  const auto g = sable::generate_grains(b, 3, 1, {});
  ASSERT_EQ(g.size(), 30u);
  for (const auto& s : g) {
    const double rho = std::hypot(s.x[0] - 1.0, s.x[1] + 1.0);
    EXPECT_LE(rho + s.radius, 1.5 + 1e-12);
    EXPECT_GE(s.x[2] - s.radius, -1e-12);
    EXPECT_LE(s.x[2] + s.radius, 2.0 + 1e-12);
  }
}

// Guards the default spacing (2 r_max) on a region exactly n diameters wide: the lattice counts
// n sites per row (its floor has a 1e-9 slack), so all n must be kept, in order: here 10 per
// row for d = 1.5 mm in 15 mm. 1e-12 absolute: the rounding of lo + (i + 1/2) s.
TEST(GenerationLattice, DefaultSpacingFillsAnExactFit) {
  for (int dim : {2, 3}) {
    SCOPED_TRACE(dim);
    GrainsConfig b = lattice_block({0, 0, 0}, {0.015, 0.015, 0.015}, 0.75e-3, 0.0, 0);
    b.spacing.reset();
    b.count = dim == 3 ? 1000 : 100;
    std::vector<GrainSeed> g;
    try {
      g = sable::generate_grains(b, dim, 1, {});
    } catch (const InputError& e) {
      ADD_FAILURE() << e.what();
      continue;
    }
    ASSERT_EQ(g.size(), b.count);
    for (std::size_t m = 0; m < 10; ++m)
      EXPECT_NEAR(g[m].x[0], (static_cast<double>(m) + 0.5) * 1.5e-3, 1e-12) << "grain " << m;
    EXPECT_NEAR(g[10].x[1], 2.25e-3, 1e-12);  // the second row starts after 10 grains
  }
}

// Guards the error for a region too small for `count`: an InputError naming the block's
// location, so the user can find the offending [[grains]] block (no tolerance: a message).
TEST(GenerationLattice, TooSmallRegionNamesTheBlock) {
  const GrainsConfig b = lattice_block({0, 0, 0}, {3.0, 3.0, 3.0}, 0.4, 1.0, 28);  // 27 sites
  for (int dim : {2, 3}) {
    try {
      (void)sable::generate_grains(b, dim, 1, {});
      ADD_FAILURE() << "expected an InputError in " << dim << "D";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(test_loc().str()), std::string::npos) << e.what();
    }
  }
  EXPECT_NO_THROW((void)sable::generate_grains(
      lattice_block({0, 0, 0}, {3.0, 3.0, 3.0}, 0.4, 1.0, 27), 3, 1, {}));
}

// ---------------------------------------------------------------- the pour bed vs gen_lattice.py

// Guards bit-compatibility of the pour example's bed with the LIGGGHTS benchmark generator
// (numpy PCG64 jitter). Relative 1e-9: the data file keeps 10 significant digits (%.9e), so
// it rounds each coordinate by at most 5e-10 relative. Radii compare exactly (1.5e-3 / 2).
TEST_F(GenerationFiles, PourBedMatchesGenLatticePy) {
  const std::string script = SABLE_SOURCE_DIR "/../shared/peers/liggghts/gen_lattice.py";
  SABLE_NEEDS(fs::exists(script), "gen_lattice.py not found at " << script);
  SABLE_NEEDS(fs::exists("/usr/bin/python3"), "/usr/bin/python3 not found");
  const std::string data = (dir_ / "pour.data").string();
  const std::string cmd = "/usr/bin/python3 '" + script + "' '" + data + "' 20000 >/dev/null 2>&1";
  if (std::system(cmd.c_str()) != 0) {
    if (std::system("/usr/bin/python3 -c 'import numpy' >/dev/null 2>&1") != 0)
      SABLE_NEEDS(false, "numpy is not available to /usr/bin/python3");
    FAIL() << "gen_lattice.py failed: " << cmd;
  }

  GrainsConfig b = lattice_block({0.0, 0.0, 0.0}, {0.03, 0.03, 0.11}, 0.75e-3, 0.03 / 18, 20000);
  b.jitter = 0.06e-3;
  b.jitter_rng = "numpy-pcg64";
  b.seed = 12345;
  const auto mine = sable::generate_grains(b, 3, *b.seed, {});
  const auto theirs = sable::read_lammps_data(data, 3);
  ASSERT_EQ(mine.size(), 20000u);
  ASSERT_EQ(theirs.size(), 20000u);
  std::size_t bad = 0;
  for (std::size_t k = 0; k < mine.size(); ++k) {
    EXPECT_EQ(mine[k].radius, 0.75e-3);
    EXPECT_EQ(theirs[k].radius, 0.75e-3);
    for (int d = 0; d < 3; ++d) {
      if (std::abs(mine[k].x[d] - theirs[k].x[d]) > 1e-9 * std::abs(theirs[k].x[d])) {
        if (++bad <= 5)
          ADD_FAILURE() << "grain " << k << " axis " << d << ": sable " << mine[k].x[d]
                        << ", gen_lattice.py " << theirs[k].x[d];
      }
    }
  }
  EXPECT_EQ(bad, 0u);
}

// ---------------------------------------------------------------- random insertion

// Guards random insertion in a 3D box: exact count, no pair overlaps (brute force; 1e-12
// relative is the rounding of the distance), every grain wholly inside (1e-12 absolute).
TEST(GenerationRandom, Box3D) {
  const Vec3a lo{-0.2, 0.1, 0.0}, hi{0.8, 1.1, 1.0};
  const auto g = sable::generate_grains(random_box_block(lo, hi, 500), 3, 42, {});
  ASSERT_EQ(g.size(), 500u);
  EXPECT_EQ(count_overlaps(g, 3), 0u);
  for (const auto& s : g) {
    EXPECT_TRUE(inside_box(s, lo, hi, 3));
    EXPECT_GE(s.radius, 0.03 * 0.8 * (1 - 1e-12));
    EXPECT_LE(s.radius, 0.03 * 1.2 * (1 + 1e-12));
  }
}

// Guards random insertion in a 2D box: exact count, no overlaps, inside, z exactly 0 (same
// tolerances as in 3D).
TEST(GenerationRandom, Box2D) {
  const Vec3a lo{0.0, 0.0, 0.0}, hi{2.5, 2.5, 0.0};  // area fraction ~0.23
  const auto g = sable::generate_grains(random_box_block(lo, hi, 500), 2, 42, {});
  ASSERT_EQ(g.size(), 500u);
  EXPECT_EQ(count_overlaps(g, 2), 0u);
  for (const auto& s : g) {
    EXPECT_TRUE(inside_box(s, lo, hi, 2));
    EXPECT_EQ(s.x[2], 0.0);
  }
}

// Guards random insertion in a cylinder (axis z): count, no overlaps, every grain wholly
// inside the cylinder (1e-12: rounding of rho and of the bounds).
TEST(GenerationRandom, Cylinder3D) {
  GrainsConfig b = random_box_block({0, 0, 0}, {0, 0, 0}, 500);
  b.region.kind = RegionConfig::Kind::kCylinder;
  b.region.center = {0.3, -0.4, 0.0};
  b.region.radius = 0.6;
  b.region.zlo = 0.5;
  b.region.zhi = 1.7;
  const auto g = sable::generate_grains(b, 3, 5, {});
  ASSERT_EQ(g.size(), 500u);
  EXPECT_EQ(count_overlaps(g, 3), 0u);
  for (const auto& s : g) {
    EXPECT_LE(std::hypot(s.x[0] - 0.3, s.x[1] + 0.4) + s.radius, 0.6 + 1e-12);
    EXPECT_GE(s.x[2] - s.radius, 0.5 - 1e-12);
    EXPECT_LE(s.x[2] + s.radius, 1.7 + 1e-12);
  }
}

// Guards that grains of earlier blocks (`existing`) are obstacles: none of the new grains
// overlaps them (1e-12 relative: rounding of the distance).
TEST(GenerationRandom, AvoidsExistingGrains) {
  const Vec3a lo{0, 0, 0}, hi{1, 1, 1};
  const auto first = sable::generate_grains(random_box_block(lo, hi, 200), 3, 1, {});
  const auto second = sable::generate_grains(random_box_block(lo, hi, 200), 3, 2, first);
  ASSERT_EQ(second.size(), 200u);
  std::vector<GrainSeed> all = first;
  all.insert(all.end(), second.begin(), second.end());
  EXPECT_EQ(count_overlaps(all, 3), 0u);
}

// Guards determinism: the same seed gives bit-identical grains (exact), another seed differs.
TEST(GenerationRandom, SeedDeterminism) {
  const GrainsConfig b = random_box_block({0, 0, 0}, {1, 1, 1}, 300);
  const auto a1 = sable::generate_grains(b, 3, 2024, {});
  const auto a2 = sable::generate_grains(b, 3, 2024, {});
  const auto c = sable::generate_grains(b, 3, 2025, {});
  ASSERT_EQ(a1.size(), a2.size());
  ASSERT_EQ(a1.size(), c.size());
  std::size_t same_as_other_seed = 0;
  for (std::size_t k = 0; k < a1.size(); ++k) {
    EXPECT_EQ(a1[k].x, a2[k].x) << "grain " << k;
    EXPECT_EQ(a1[k].radius, a2[k].radius) << "grain " << k;
    if (a1[k].x == c[k].x) ++same_as_other_seed;
  }
  EXPECT_EQ(same_as_other_seed, 0u);
}

// Guards the error for a region too full for `count`: an InputError naming the block's
// location (no tolerance: a message).
TEST(GenerationRandom, TooSmallRegionNamesTheBlock) {
  GrainsConfig b = random_box_block({0, 0, 0}, {0.1, 0.1, 0.1}, 50);  // room for a handful
  b.max_attempts = 200;
  for (int dim : {2, 3}) {
    try {
      (void)sable::generate_grains(b, dim, 3, {});
      ADD_FAILURE() << "expected an InputError in " << dim << "D";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(test_loc().str()), std::string::npos) << e.what();
    }
  }
}

// ---------------------------------------------------------------- radius distributions

GrainsConfig list_block(std::size_t n) {
  GrainsConfig b;
  b.generator = "list";
  b.positions.assign(n, Vec3a{0.0, 0.0, 0.0});
  for (std::size_t k = 0; k < n; ++k) b.positions[k][0] = static_cast<double>(k);
  b.count = n;
  b.loc = test_loc();
  return b;
}

// Guards the mono distribution: every radius is exactly the given value, and list positions
// are kept as given (both exact: nothing is computed).
TEST(GenerationRadius, MonoExact) {
  GrainsConfig b = list_block(10);
  b.radius.kind = RadiusConfig::Kind::kMono;
  b.radius.value = 1.234e-3;
  const auto g = sable::generate_grains(b, 3, 1, {});
  ASSERT_EQ(g.size(), 10u);
  for (std::size_t k = 0; k < g.size(); ++k) {
    EXPECT_EQ(g[k].radius, 1.234e-3);
    EXPECT_EQ(g[k].x, b.positions[k]);
  }
}

// Guards the uniform +-10 % distribution: all radii within [0.9, 1.1] x mean (1e-12 relative:
// rounding of value * (1 + spread * u)), the sample mean within 3 sigma of the mean
// (sigma = spread * mean / sqrt(3) / sqrt(N), the standard error of a uniform sample), the
// sample standard deviation within 10 % of spread * mean / sqrt(3) (its relative standard error
// for N = 4000 is ~1 %), and the range really spanned.
TEST(GenerationRadius, UniformWithinSpreadAndUnbiased) {
  const std::size_t n = 4000;
  const double mean = 2.0e-3, spread = 0.1;
  GrainsConfig b = list_block(n);
  b.radius.kind = RadiusConfig::Kind::kUniform;
  b.radius.value = mean;
  b.radius.spread = spread;
  const auto g = sable::generate_grains(b, 3, 77, {});
  ASSERT_EQ(g.size(), n);
  double sum = 0.0, lo = 1e300, hi = 0.0;
  for (const auto& s : g) {
    EXPECT_GE(s.radius, 0.9 * mean * (1 - 1e-12));
    EXPECT_LE(s.radius, 1.1 * mean * (1 + 1e-12));
    sum += s.radius;
    lo = std::min(lo, s.radius);
    hi = std::max(hi, s.radius);
  }
  const double nd = static_cast<double>(n);
  const double sample_mean = sum / nd;
  const double sd = spread * mean / std::sqrt(3.0);
  EXPECT_NEAR(sample_mean, mean, 3.0 * sd / std::sqrt(nd));
  double var = 0.0;
  for (const auto& s : g) var += (s.radius - sample_mean) * (s.radius - sample_mean);
  EXPECT_NEAR(std::sqrt(var / (nd - 1.0)), sd, 0.1 * sd);
  EXPECT_LT(lo, 0.905 * mean);
  EXPECT_GT(hi, 1.095 * mean);
}

// Guards the list distribution: radii are the values in turn, cycled (exact), for the list
// generator and for the lattice alike.
TEST(GenerationRadius, ListCycles) {
  const std::vector<double> values{1e-3, 2e-3, 3e-3};
  GrainsConfig b = list_block(7);
  b.radius.kind = RadiusConfig::Kind::kList;
  b.radius.values = values;
  const auto g = sable::generate_grains(b, 3, 1, {});
  ASSERT_EQ(g.size(), 7u);
  for (std::size_t k = 0; k < g.size(); ++k) EXPECT_EQ(g[k].radius, values[k % 3]) << k;

  GrainsConfig l = lattice_block({0, 0, 0}, {0.1, 0.1, 0.1}, 0.0, 0.01, 8);
  l.radius.kind = RadiusConfig::Kind::kList;
  l.radius.values = values;
  const auto gl = sable::generate_grains(l, 3, 1, {});
  ASSERT_EQ(gl.size(), 8u);
  for (std::size_t k = 0; k < gl.size(); ++k) EXPECT_EQ(gl[k].radius, values[k % 3]) << k;
}

// ---------------------------------------------------------------- LAMMPS data files

const char* kHeader =
    "test bed\n"
    "\n"
    "3 atoms\n"
    "1 atom types\n"
    "\n"
    "0 1 xlo xhi\n"
    "0 1 ylo yhi\n"
    "0 1 zlo zhi\n"
    "\n"
    "Atoms # granular\n"
    "\n";  // the Atoms lines start at line 12

// Guards reading an Atoms section: ids out of order are sorted, radius = diameter / 2, a
// following section ends the atoms, 2D drops z. Exact: decimal literals parse identically.
TEST_F(GenerationFiles, LammpsSortsById) {
  const std::string p = write("bed.data", std::string(kHeader) +
                                              "3 1 0.6 2500 0.7 0.8 0.9\n"
                                              "1 1 0.2 2500 0.1 0.2 0.3\n"
                                              "2 1 0.4 2500 0.4 0.5 0.6  # comment\n"
                                              "\n"
                                              "Velocities\n"
                                              "\n"
                                              "1 0 0 0 0 0 0\n");
  const auto g = sable::read_lammps_data(p, 3);
  ASSERT_EQ(g.size(), 3u);
  EXPECT_EQ(g[0].x, (Vec3a{0.1, 0.2, 0.3}));
  EXPECT_EQ(g[1].x, (Vec3a{0.4, 0.5, 0.6}));
  EXPECT_EQ(g[2].x, (Vec3a{0.7, 0.8, 0.9}));
  EXPECT_EQ(g[0].radius, 0.5 * 0.2);
  EXPECT_EQ(g[1].radius, 0.5 * 0.4);
  EXPECT_EQ(g[2].radius, 0.5 * 0.6);
  const auto g2 = sable::read_lammps_data(p, 2);
  ASSERT_EQ(g2.size(), 3u);
  EXPECT_EQ(g2[1].x, (Vec3a{0.4, 0.5, 0.0}));
}

// Guards the message for a malformed Atoms line: an InputError naming `file:line` so the user
// finds it (no tolerance: a message).
TEST_F(GenerationFiles, LammpsMalformedLineNamesFileAndLine) {
  const std::string p = write("bad.data", std::string(kHeader) +
                                              "1 1 0.2 2500 0.1 0.2 0.3\n"
                                              "2 1 0.4 2500 0.4 oops 0.6\n"
                                              "3 1 0.6 2500 0.7 0.8 0.9\n");
  try {
    (void)sable::read_lammps_data(p, 3);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(p + ":13"), std::string::npos) << e.what();
  }
  const std::string q = write("short.data", std::string(kHeader) +
                                                "1 1 0.2 2500 0.1 0.2 0.3\n"
                                                "2 1 0.4 2500 0.4 0.5 0.6\n"
                                                "3 1 0.6 2500 0.7 0.8\n");
  try {
    (void)sable::read_lammps_data(q, 3);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(q + ":14"), std::string::npos) << e.what();
  }
}

// Guards the count check: fewer atoms than the header announces, or a missing file, is an
// InputError naming the file (no tolerance: a message).
TEST_F(GenerationFiles, LammpsCountMismatchAndMissingFile) {
  const std::string p = write("few.data", std::string(kHeader) +
                                              "1 1 0.2 2500 0.1 0.2 0.3\n"
                                              "2 1 0.4 2500 0.4 0.5 0.6\n");
  try {
    (void)sable::read_lammps_data(p, 3);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what();
  }
  const std::string missing = (dir_ / "nope.data").string();
  EXPECT_THROW((void)sable::read_lammps_data(missing, 3), InputError);
}

// Guards the LAMMPS rule that the first line is a free-text title, always skipped: a title
// mentioning "atoms" must neither be parsed as the atom count nor escape as a bare
// std::invalid_argument (exact: decimal literals parse identically).
TEST_F(GenerationFiles, LammpsTitleLineIsFreeText) {
  std::string text = kHeader;
  text.replace(0, text.find('\n'), "granular atoms of the test bed");
  const std::string p = write("title.data", text +
                                                "1 1 0.2 2500 0.1 0.2 0.3\n"
                                                "2 1 0.4 2500 0.4 0.5 0.6\n"
                                                "3 1 0.6 2500 0.7 0.8 0.9\n");
  std::vector<GrainSeed> g;
  ASSERT_NO_THROW(g = sable::read_lammps_data(p, 3));
  ASSERT_EQ(g.size(), 3u);
  EXPECT_EQ(g[2].x, (Vec3a{0.7, 0.8, 0.9}));
}

// Guards the error contract (every input error names where it is): an Atoms line whose id does
// not fit a long is an InputError naming `file:line`, not a bare std::out_of_range.
TEST_F(GenerationFiles, LammpsOversizedIdNamesFileAndLine) {
  const std::string p = write("bigid.data", std::string(kHeader) +
                                                "1 1 0.2 2500 0.1 0.2 0.3\n"
                                                "99999999999999999999 1 0.4 2500 0.4 0.5 0.6\n"
                                                "3 1 0.6 2500 0.7 0.8 0.9\n");
  try {
    (void)sable::read_lammps_data(p, 3);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(p + ":13"), std::string::npos) << e.what();
  } catch (const std::exception& e) {
    FAIL() << "expected an InputError naming " << p << ":13, got " << e.what();
  }
}

}  // namespace
