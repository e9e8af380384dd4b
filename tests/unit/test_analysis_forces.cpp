// Force-network analyses (forces.hpp, percolation.hpp) on hand-built contact sets and samples.
//
// Every expected value is worked out by hand from the constructed data; tolerances are
// round-off unless a comment says the check is statistical.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "sable/analysis/forces.hpp"
#include "sable/analysis/percolation.hpp"
#include "sable/core/error.hpp"

namespace {

using sable::ContactSet;
using sable::InputError;
using sable::Sample;
template <int D>
using Vec = typename sable::Space<D>::Vec;

constexpr double kPi = std::numbers::pi;

// Unit vector along axis `a`, times `s`.
template <int D>
Vec<D> axis(int a, double s = 1.0) {
  Vec<D> v = Vec<D>::Zero();
  v[a] = s;
  return v;
}

// A contact with normal n, normal force fn (> 0 compressive) and tangential force ft (ft . n = 0):
// the force on i is -fn n + ft, so ContactSet::push recovers fn and ft.
template <int D>
void add(ContactSet<D>& c, std::uint32_t i, std::uint32_t j, const Vec<D>& n, double fn,
         const Vec<D>& ft = Vec<D>::Zero(), double mu = 0.5, bool wall = false) {
  c.push(i, j, wall, n, Vec<D>(-fn * n + ft), Vec<D>::Zero(), Vec<D>::Zero(), n, 0.0, mu);
}

// Grains at the given centres, all of radius r, mass 1, free.
template <int D>
Sample<D> grains(const std::vector<Vec<D>>& x, double r) {
  Sample<D> s;
  s.x = x;
  s.v.assign(x.size(), Vec<D>::Zero());
  s.a = s.v;
  s.radius.assign(x.size(), r);
  s.mass.assign(x.size(), 1.0);
  s.volume.assign(x.size(), 1.0);
  s.inertia.assign(x.size(), 1.0);
  s.fixed.assign(x.size(), 0);
  s.source = "test";
  return s;
}

// The message of the InputError `f` throws (fails the test if it throws none).
std::string input_error(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError thrown";
  return "";
}

// Uniform in [0, 1) from the top 53 bits of mt19937_64 (portable: the engine's output is
// specified by the standard, std::uniform_real_distribution is not).
double uniform(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

// ---------------------------------------------------------------- force PDF

// Compressive fn = {1, 1, 2, 4, 12} (<f> = 4, x = {0.25, 0.25, 0.5, 1, 3}), tensile fn = {-2, -6}
// (x = |f| / 4 = {0.5, 1.5}), one contact with fn = 0 and one wall contact (fn = 100).
template <int D>
ContactSet<D> pdf_set() {
  ContactSet<D> c;
  for (double f : {1.0, 1.0, 2.0, 4.0, 12.0, -2.0, -6.0}) add<D>(c, 0, 1, axis<D>(0), f);
  add<D>(c, 0, 1, axis<D>(0), 0.0, axis<D>(1));  // tangential only: fn = 0
  add<D>(c, 0, 0, axis<D>(1), 100.0, Vec<D>::Zero(), 0.5, true);
  return c;
}

template <int D>
void check_pdf() {
  sable::ForceStatsOptions opt;
  opt.bins = 4;
  opt.p0_window = 0.3;
  const auto st = sable::force_statistics(pdf_set<D>(), opt);
  // All hand-computed values below are exact up to round-off of a few operations: 1e-12.
  EXPECT_EQ(st.contacts, 8u);  // the wall contact is excluded by default
  EXPECT_EQ(st.zero_count, 1u);
  EXPECT_NEAR(st.f_norm, 4.0, 1e-12);  // mean compressive force
  ASSERT_EQ(st.sides.size(), 2u);
  const auto& cp = st.sides[0];
  EXPECT_EQ(cp.side, "compressive");
  EXPECT_EQ(cp.variable, "f_over_mean");
  EXPECT_EQ(cp.count, 5u);
  EXPECT_NEAR(cp.fraction, 5.0 / 8.0, 1e-12);
  EXPECT_NEAR(cp.fraction_below_mean, 0.6, 1e-12);  // 1, 1, 2 below 4
  EXPECT_NEAR(cp.alpha, 1.0, 1e-12);                // mean of f/<f> is 1
  EXPECT_NEAR(cp.p0, 2.0 / (5.0 * 0.3), 1e-12);     // two x = 0.25 < 0.3
  // Bins of width 3/4 over [0, 3]: x/w = 1/3, 1/3, 2/3, 4/3, 4 (-> last bin).
  EXPECT_NEAR(cp.bin_width, 0.75, 1e-12);
  const std::vector<double> counts{3, 1, 0, 1};
  EXPECT_EQ(cp.counts, counts);
  double integral = 0.0;
  for (std::size_t b = 0; b < 4; ++b) {
    EXPECT_NEAR(cp.pdf[b], counts[b] / (5.0 * 0.75), 1e-12);  // count / (n width)
    integral += cp.pdf[b] * cp.bin_width;
  }
  EXPECT_NEAR(integral, 1.0, 1e-12);      // a PDF over the side's own samples
  EXPECT_EQ(cp.tail.n_tail, 1u);          // only x = 3 lies above 1
  EXPECT_NEAR(cp.tail.beta, 0.5, 1e-12);  // 1 / (3 - 1)
  EXPECT_NEAR(cp.tail.beta_stderr, 0.5, 1e-12);
  EXPECT_EQ(cp.tail.lsq_bins, 1u);  // one populated bin above x = 1: no line through it
  EXPECT_TRUE(std::isnan(cp.tail.beta_lsq));

  const auto& tn = st.sides[1];
  EXPECT_EQ(tn.variable, "abs_f_over_mean");
  EXPECT_EQ(tn.count, 2u);
  EXPECT_NEAR(tn.fraction, 2.0 / 8.0, 1e-12);
  EXPECT_NEAR(tn.mean_force, 4.0, 1e-12);
  EXPECT_NEAR(tn.alpha, 1.0, 1e-12);  // x = {0.5, 1.5}, mean 1
  // Bins of width 1.5/4: x/w = 4/3 and 4 -> bins 1 and 3; pdf = 1 / (2 * 0.375).
  EXPECT_EQ(tn.counts, (std::vector<double>{0, 1, 0, 1}));
  EXPECT_NEAR(tn.pdf[1], 1.0 / 0.75, 1e-12);
  EXPECT_NEAR(tn.tail.beta, 2.0, 1e-12);  // 1 / (1.5 - 1)

  const auto t = sable::table(cp);
  EXPECT_EQ(t.names, (std::vector<std::string>{"f_over_mean_lo", "f_over_mean_hi", "f_over_mean",
                                               "count", "pdf"}));
  EXPECT_EQ(t.rows(), 4u);

  opt.include_walls = true;  // the wall contact's 100 joins the compressive side
  const auto withw = sable::force_statistics(pdf_set<D>(), opt);
  EXPECT_EQ(withw.contacts, 9u);
  EXPECT_NEAR(withw.f_norm, 120.0 / 6.0, 1e-12);
}

TEST(AnalysisForces, PdfOfHandBuiltForces2D) {
  check_pdf<2>();
}
TEST(AnalysisForces, PdfOfHandBuiltForces3D) {
  check_pdf<3>();
}

TEST(AnalysisForces, TangentialAndReferenceForce) {
  ContactSet<2> c;
  add<2>(c, 0, 1, axis<2>(0), 1.0, axis<2>(1, 1.0));
  add<2>(c, 0, 1, axis<2>(0), -1.0, axis<2>(1, -3.0));
  sable::ForceStatsOptions opt;
  opt.component = sable::ForceComponent::tangential;
  opt.bins = 2;
  const auto st = sable::force_statistics(c, opt);
  ASSERT_EQ(st.sides.size(), 1u);
  EXPECT_EQ(st.sides[0].variable, "ft_over_mean");
  EXPECT_NEAR(st.f_norm, 2.0, 1e-12);  // mean of |ft| = {1, 3}: both signs of fn count
  EXPECT_EQ(st.sides[0].counts, (std::vector<double>{1, 1}));  // x = 0.5, 1.5 over [0, 1.5]

  // Reference force f0 = 2 (Richefeu eq. 10): alpha = 1 / mean(|f| / f0) on each side.
  opt = {};
  opt.reference_force = 2.0;
  const auto ref = sable::force_statistics(c, opt);
  EXPECT_TRUE(ref.reference);
  EXPECT_EQ(ref.sides[0].variable, "f_over_f0");
  EXPECT_NEAR(ref.sides[0].alpha, 2.0, 1e-12);  // |f| / f0 = 0.5
  EXPECT_NEAR(ref.sides[1].alpha, 2.0, 1e-12);  // tensile |f| / f0 = 0.5
  const std::string json = sable::summary(ref).json();
  EXPECT_NE(json.find("\"normalisation\": \"reference\""), std::string::npos);
  EXPECT_NE(json.find("\"force_unit\": \"N/m\""), std::string::npos);  // 2D: per thickness
}

// A body of forces below the mean plus an exponential tail f = 1 + E / beta, E ~ Exp(1): the
// body (all at one value b < 1) is chosen so that the mean force is exactly 1, so x = f and the
// tail above x = 1 is the truncated exponential the estimator assumes.
TEST(AnalysisForces, TailBetaMaximumLikelihood) {
  constexpr double beta = 1.4;
  constexpr int n_tail = 10000, n_body = 10000;
  std::mt19937_64 rng(20090101);
  std::vector<double> tail;
  double sum = 0.0;
  for (int k = 0; k < n_tail; ++k) {
    const double e = -std::log(1.0 - uniform(rng));  // inverse CDF of Exp(1)
    tail.push_back(1.0 + e / beta);
    sum += tail.back();
  }
  const double body = (n_tail + n_body - sum) / n_body;
  ASSERT_GT(body, 0.0);
  ASSERT_LT(body, 1.0);
  ContactSet<3> c;
  for (double f : tail) add<3>(c, 0, 1, axis<3>(2), f);
  for (int k = 0; k < n_body; ++k) add<3>(c, 0, 1, axis<3>(2), body);
  const auto st = sable::force_statistics(c);
  EXPECT_NEAR(st.f_norm, 1.0, 1e-12);  // by construction of the body
  const auto& t = st.sides[0].tail;
  EXPECT_EQ(t.n_tail, static_cast<std::size_t>(n_tail));  // every tail sample is > 1
  // Statistical: the MLE is within 3 standard errors of the true beta (99.7 %; fixed seed).
  EXPECT_NEAR(t.beta, beta, 3.0 * t.beta_stderr);
  // The binned least-squares fit is coarser: within 10 % (Poisson noise of the sparse far bins).
  EXPECT_NEAR(t.beta_lsq, beta, 0.1 * beta);
  EXPECT_GT(t.r2_lsq, 0.9);  // the log-PDF is a line above the mean (weighted fit)
  EXPECT_NEAR(st.sides[0].fraction_below_mean, 0.5, 1e-12);  // the body exactly
}

// ---------------------------------------------------------------- coordination

// Grains 0-3 on a square with bonds 0-1, 1-2, 2-3 (tensile), 3-0; grain 4 hangs on grain 0;
// grain 1 touches wall 0. Contacts per grain: 3, 3, 2, 2, 1.
template <int D>
Sample<D> square() {
  std::vector<Vec<D>> x{axis<D>(0, 0.0), axis<D>(0, 1.0), Vec<D>(axis<D>(0) + axis<D>(1)),
                        axis<D>(1, 1.0), axis<D>(0, -1.0)};
  auto s = grains<D>(x, 0.5);
  add<D>(s.contacts, 0, 1, axis<D>(0), 1.0);
  add<D>(s.contacts, 1, 2, axis<D>(1), 1.0);
  add<D>(s.contacts, 3, 2, axis<D>(0), -0.5);
  add<D>(s.contacts, 0, 3, axis<D>(1), 1.0);
  add<D>(s.contacts, 0, 4, axis<D>(0, -1.0), 2.0);
  add<D>(s.contacts, 1, 0, axis<D>(1, -1.0), 1.0, Vec<D>::Zero(), 0.5, true);
  s.fixed[4] = 1;
  return s;
}

TEST(AnalysisCoordination, SquareWithRattler2D) {
  const auto c = sable::coordination(square<2>());
  // Integer counts are exact; ratios of small integers: 1e-12.
  EXPECT_EQ(c.grains, 5u);
  EXPECT_EQ(c.fixed_grains, 1u);  // counted, and as a grain like any other
  EXPECT_EQ(c.contacts, 5u);
  EXPECT_EQ(c.compressive, 4u);
  EXPECT_EQ(c.tensile, 1u);
  EXPECT_EQ(c.wall_contacts, 1u);
  EXPECT_NEAR(c.z, 2.0, 1e-12);  // 2 * 5 / 5
  EXPECT_NEAR(c.z_compressive, 1.6, 1e-12);
  EXPECT_NEAR(c.z_tensile, 0.4, 1e-12);
  EXPECT_EQ(c.per_grain, (std::vector<std::uint32_t>{3, 3, 2, 2, 1}));
  EXPECT_EQ(c.rattler_threshold, 2);
  EXPECT_EQ(c.rattlers, 1u);  // grain 4, with one contact
  EXPECT_EQ(c.rattler[4], 1);
  EXPECT_NEAR(c.rattler_fraction, 0.2, 1e-12);
  EXPECT_EQ(c.non_rattler_contacts, 4u);
  EXPECT_NEAR(c.z_without_rattlers, 2.0, 1e-12);  // 2 * 4 / 4
  const auto t = sable::table(c);
  EXPECT_EQ(t.columns[1], (std::vector<double>{0, 1, 2, 2}));  // grains with 0..3 contacts
}

TEST(AnalysisCoordination, RattlersIterated3D) {
  const auto s = square<3>();
  const auto c = sable::coordination(s);
  EXPECT_EQ(c.rattler_threshold, 3);
  EXPECT_EQ(c.rattlers, 3u);                      // grains 2, 3 (two contacts) and 4 (one)
  EXPECT_EQ(c.non_rattler_contacts, 1u);          // 0-1 only
  EXPECT_NEAR(c.z_without_rattlers, 1.0, 1e-12);  // 2 * 1 / 2
  // Iterated: without 2, 3, 4, grain 0 keeps 1 contact and grain 1 two (one a wall): all go.
  sable::CoordinationOptions opt;
  opt.iterate_rattlers = true;
  const auto it = sable::coordination(s, opt);
  EXPECT_EQ(it.rattlers, 5u);
  EXPECT_TRUE(std::isnan(it.z_without_rattlers));  // no grain left to average over
}

// ---------------------------------------------------------------- fabric

TEST(AnalysisFabric, IsotropicAndAligned2D) {
  ContactSet<2> c;
  for (int a = 0; a < 2; ++a)
    for (double s : {1.0, -1.0}) add<2>(c, 0, 1, axis<2>(a, s), 1.0);
  add<2>(c, 0, 0, axis<2>(0), 1.0, Vec<2>::Zero(), 0.5, true);  // wall: not in the fabric
  sable::FabricOptions opt;
  opt.bins = 3;
  const auto f = sable::fabric(c, opt);
  // Sums of products of 0 and +-1: exact up to round-off, 1e-12.
  EXPECT_EQ(f.contacts, 4u);
  EXPECT_TRUE(f.tensor.isApprox(0.5 * Eigen::Matrix2d::Identity(), 1e-12));
  EXPECT_NEAR(f.anisotropy, 0.0, 1e-12);
  // 60-degree bins: +-x fold to 0 (bin 0), +-y to 90 (bin 1).
  EXPECT_EQ(f.counts, (std::vector<double>{2, 2, 0}));
  EXPECT_NEAR(f.density[0], 0.5 / (kPi / 3.0), 1e-12);  // fraction / bin width (rad)
  EXPECT_NEAR(f.over_isotropic[0], 1.5, 1e-12);

  ContactSet<2> x;
  for (double s : {1.0, -1.0}) add<2>(x, 0, 1, axis<2>(0, s), 1.0);
  const auto fx = sable::fabric(x);
  EXPECT_NEAR(fx.anisotropy, 2.0, 1e-12);  // phi = diag(1, 0)
  EXPECT_NEAR(fx.eigenvalues[0], 1.0, 1e-12);
  EXPECT_NEAR(fx.eigenvectors(0, 0), 1.0, 1e-12);  // sign fixed: largest component positive

  ContactSet<2> d;  // all at 30 degrees: a = 2, major direction 30 degrees
  add<2>(d, 0, 1, Vec<2>(std::cos(kPi / 6), std::sin(kPi / 6)), 1.0);
  add<2>(d, 0, 1, Vec<2>(-std::cos(kPi / 6), -std::sin(kPi / 6)), 1.0);
  const auto fd = sable::fabric(d);
  EXPECT_NEAR(fd.anisotropy, 2.0, 1e-12);
  EXPECT_NEAR(fd.major_angle_deg, 30.0, 1e-9);  // degrees from atan2 of an eigenvector
}

TEST(AnalysisFabric, SixAxisDirections3D) {
  ContactSet<3> c;
  for (int a = 0; a < 3; ++a)
    for (double s : {1.0, -1.0}) add<3>(c, 0, 1, axis<3>(a, s), 1.0);
  sable::FabricOptions opt;
  opt.bins = 3;
  opt.azimuth_bins = 3;
  const auto f = sable::fabric(c, opt);
  EXPECT_TRUE(f.tensor.isApprox(Eigen::Matrix3d::Identity() / 3.0, 1e-12));  // round-off
  EXPECT_NEAR(f.anisotropy, 0.0, 1e-12);
  // Polar angle in 30-degree bins: +-z at 0 (bin 0), the four others at 90 (last bin).
  EXPECT_EQ(f.counts, (std::vector<double>{2, 0, 4}));
  const double cap0 = 1.0 - std::cos(kPi / 6);  // solid angle of bin 0 over 2 pi
  EXPECT_NEAR(f.density[0], (2.0 / 6.0) / (2 * kPi * cap0), 1e-12);
  EXPECT_NEAR(f.over_isotropic[0], (2.0 / 6.0) / cap0, 1e-12);
  // Azimuth: +-z skipped, +-x at 0 (bin 0), +-y at 90 degrees (bin 1 of 60-degree bins).
  EXPECT_EQ(f.azimuth_skipped, 2u);
  EXPECT_EQ(f.azimuth_counts, (std::vector<double>{2, 2, 0}));
  EXPECT_NEAR(f.azimuth_density[1], 0.5 / (kPi / 3), 1e-12);
  EXPECT_EQ(sable::azimuth_table(f).rows(), 3u);

  ContactSet<3> z;
  add<3>(z, 0, 1, axis<3>(2), 1.0);
  const auto fz = sable::fabric(z);
  EXPECT_NEAR(fz.anisotropy, 2.5, 1e-12);  // 5/2 (1 - 0)
  EXPECT_NEAR(fz.eigenvectors(2, 0), 1.0, 1e-12);
}

// The polar-angle density is normalised by solid angle: isotropic directions give a flat
// over_isotropic = 1 in every bin.
TEST(AnalysisFabric, IsotropicDirectionsAreFlat3D) {
  constexpr int n = 100000, bins = 9;
  std::mt19937_64 rng(7);
  ContactSet<3> c;
  for (int k = 0; k < n; ++k) {
    const double z = 2.0 * uniform(rng) - 1.0, ph = 2.0 * kPi * uniform(rng);
    const double r = std::sqrt(1.0 - z * z);
    add<3>(c, 0, 1, Vec<3>(r * std::cos(ph), r * std::sin(ph), z), 1.0);
  }
  sable::FabricOptions opt;
  opt.bins = bins;
  const auto f = sable::fabric(c, opt);
  for (int b = 0; b < bins; ++b) {
    const double p = std::cos(b * kPi / 18) - std::cos((b + 1) * kPi / 18);  // bin probability
    const double sd = std::sqrt((1.0 - p) / (p * n));  // binomial sd of fraction / p
    // Statistical: each bin within 5 standard deviations of 1 (fixed seed).
    EXPECT_NEAR(f.over_isotropic[static_cast<std::size_t>(b)], 1.0, 5.0 * sd) << "bin " << b;
  }
  EXPECT_NEAR(f.anisotropy, 0.0, 0.05);  // statistical: ~ 1/sqrt(n) fluctuations of phi
}

// ---------------------------------------------------------------- polarization

// mu fn = 0.5 * 2 = 1, so m = |ft| exactly: {0.25, 0.55, 0.985, 0.995, 1.0, 1.2}; plus a
// tensile, a frictionless and a wall contact.
template <int D>
ContactSet<D> polar_set() {
  ContactSet<D> c;
  for (double t : {0.25, 0.55, 0.985, 0.995, 1.0, 1.2})
    add<D>(c, 0, 1, axis<D>(D - 1), 2.0, axis<D>(0, t));
  add<D>(c, 0, 1, axis<D>(D - 1), -1.0, axis<D>(0, 0.1));
  add<D>(c, 0, 1, axis<D>(D - 1), 1.0, axis<D>(0, 0.1), 0.0);
  add<D>(c, 0, 2, axis<D>(D - 1), 2.0, axis<D>(0, 1.0), 0.5, true);  // wall 2, m = 1
  return c;
}

template <int D>
void check_polarization() {
  const auto c = polar_set<D>();
  sable::PolarizationOptions opt;
  opt.bins = 10;
  const auto p = sable::polarization(c, sable::select_bulk(c), opt);
  EXPECT_EQ(p.selected, 8u);
  EXPECT_EQ(p.excluded_non_compressive, 1u);
  EXPECT_EQ(p.excluded_frictionless, 1u);
  EXPECT_EQ(p.count, 6u);
  EXPECT_EQ(p.sliding, 3u);                     // m >= 0.99: 0.995, 1.0, 1.2
  EXPECT_NEAR(p.fraction_sliding, 0.5, 1e-15);  // 3 / 6
  EXPECT_NEAR(p.mean_m, (0.25 + 0.55 + 0.985 + 0.995 + 1.0 + 1.2) / 6.0, 1e-15);  // summation
  EXPECT_NEAR(p.max_m, 1.2, 1e-15);
  EXPECT_EQ(p.above_one, 1u);
  EXPECT_EQ(p.counts, (std::vector<double>{0, 0, 1, 0, 0, 1, 0, 0, 0, 4}));  // 1.2 in the last
  EXPECT_NEAR(p.pdf[9], 4.0 / 6.0 * 10.0, 1e-12);

  opt.eps = 0.02;  // m >= 0.98 now takes 0.985 too
  EXPECT_EQ(sable::polarization(c, sable::select_bulk(c), opt).sliding, 4u);

  const auto w = sable::polarization(c, sable::select_wall(c, 2), opt);
  EXPECT_EQ(w.count, 1u);
  EXPECT_NEAR(w.fraction_sliding, 1.0, 1e-15);
  EXPECT_EQ(sable::select_walls(c), sable::select_wall(c, 2));
  const std::vector<Vec<D>> x(3, Vec<D>::Zero());
  sable::Region<D> r;
  r.hi = Vec<D>::Constant(1.0);
  r.lo = Vec<D>::Constant(-1.0);
  EXPECT_EQ(sable::select_region(c, x, r), sable::select_bulk(c));  // every point at 0
  r.lo = Vec<D>::Constant(0.5);
  EXPECT_EQ(sable::select_region(c, x, r, true), std::vector<bool>(c.size(), false));
}

TEST(AnalysisPolarization, FractionOnTheCone2D) {
  check_polarization<2>();
}
TEST(AnalysisPolarization, FractionOnTheCone3D) {
  check_polarization<3>();
}

// ---------------------------------------------------------------- percolation

// A 5 x 5 square grid of unit spacing, radius 0.5, slot = 5 iy + ix, contacts between
// horizontal and vertical neighbours; the box is [-0.5, 4.5]^2.
Sample<2> grid() {
  std::vector<Vec<2>> x;
  for (int iy = 0; iy < 5; ++iy)
    for (int ix = 0; ix < 5; ++ix) x.emplace_back(ix, iy);
  auto s = grains<2>(x, 0.5);
  for (std::uint32_t g = 0; g < 25; ++g) {
    if (g % 5 < 4) add<2>(s.contacts, g, g + 1, axis<2>(0), 1.0);
    if (g < 20) add<2>(s.contacts, g, g + 5, axis<2>(1), 1.0);
  }
  return s;
}

TEST(AnalysisPercolation, ColumnSpansYNotX2D) {
  const auto s = grid();
  std::vector<double> v(25, -1.0);
  for (std::size_t iy = 0; iy < 5; ++iy) v[5 * iy + 2] = 2.0;
  const auto p = sable::percolation(s, v);
  // Default slab = the largest diameter, 1: columns 0-1 touch the low x face, 3-4 the high.
  EXPECT_DOUBLE_EQ(p.slab, 1.0);  // 2 * 0.5, exact
  ASSERT_EQ(p.positive.clusters.size(), 1u);
  EXPECT_EQ(p.positive.clusters[0].label, 2u);  // smallest slot of the column
  EXPECT_EQ(p.positive.clusters[0].size, 5u);
  EXPECT_FALSE(p.positive.percolates[0]);
  EXPECT_TRUE(p.positive.percolates[1]);
  // The column cuts the negative phase in two: columns 0-1 (label 0) and 3-4 (label 3).
  ASSERT_EQ(p.negative.clusters.size(), 2u);
  EXPECT_EQ(p.negative.clusters[0].label, 0u);
  EXPECT_EQ(p.negative.clusters[1].label, 3u);
  EXPECT_EQ(p.negative.clusters[0].size, 10u);
  EXPECT_EQ(p.negative.largest, 10u);
  EXPECT_FALSE(p.negative.percolates[0]);
  EXPECT_TRUE(p.negative.percolates[1]);
  EXPECT_EQ(p.label[24], 3);
  EXPECT_EQ(p.label[22], 2);
  EXPECT_EQ(p.phase[22], 1);
  const auto t = sable::cluster_table(p);
  EXPECT_EQ(t.names, (std::vector<std::string>{"phase", "label", "size", "spans_x", "spans_y"}));
  EXPECT_EQ(t.rows(), 3u);
}

TEST(AnalysisPercolation, EnclosedClusterDoesNotSpan2D) {
  const auto s = grid();
  std::vector<double> v(25, -1.0);
  for (std::size_t g : {11u, 12u, 13u}) v[g] = 1.0;  // the middle of row 2
  v[0] = 0.0;                                        // a grain in neither phase
  sable::PercolationOptions opt;
  opt.slab = 0.25;  // only the outer ring touches the faces
  const auto p = sable::percolation(s, v, opt);
  ASSERT_EQ(p.positive.clusters.size(), 1u);
  EXPECT_EQ(p.positive.clusters[0].label, 11u);
  EXPECT_EQ(p.positive.largest, 3u);
  EXPECT_FALSE(p.positive.percolates[0]);
  EXPECT_FALSE(p.positive.percolates[1]);
  ASSERT_EQ(p.negative.clusters.size(), 1u);    // a ring around the row: one cluster
  EXPECT_EQ(p.negative.clusters[0].label, 1u);  // slot 0 is in no phase
  EXPECT_EQ(p.negative.clusters[0].size, 21u);
  EXPECT_TRUE(p.negative.largest_spans[0]);
  EXPECT_TRUE(p.negative.largest_spans[1]);
  EXPECT_EQ(p.label[0], -1);
  EXPECT_EQ(p.phase[0], 0);
}

TEST(AnalysisPercolation, ExtraEdgesAndWallContacts3D) {
  // Four grains on the z axis, bonds 0-1, 1-2, 2-3; values +, +, -, +; grain 3 touches wall 0.
  std::vector<Vec<3>> x;
  for (int k = 0; k < 4; ++k) x.push_back(axis<3>(2, k));
  auto s = grains<3>(x, 0.5);
  for (std::uint32_t g = 0; g < 3; ++g) add<3>(s.contacts, g, g + 1, axis<3>(2), 1.0);
  add<3>(s.contacts, 3, 0, axis<3>(2), 1.0, Vec<3>::Zero(), 0.5, true);  // wall 0, not grain 0
  const std::vector<double> v{1.0, 1.0, -1.0, 1.0};
  const auto p = sable::percolation(s, v);
  // Box z in [-0.5, 3.5], slab 1: grains 0-1 touch the bottom, 2-3 the top.
  ASSERT_EQ(p.positive.clusters.size(), 2u);  // {0, 1} and {3}: the wall joins nothing
  EXPECT_EQ(p.positive.clusters[1].label, 3u);
  EXPECT_FALSE(p.positive.percolates[2]);
  EXPECT_TRUE(p.positive.percolates[0]);  // every grain fills the x extent
  sable::PercolationOptions opt;
  opt.extra_edges = {{1, 3}};  // e.g. a liquid bridge between two positive grains
  const auto q = sable::percolation(s, v, opt);
  ASSERT_EQ(q.positive.clusters.size(), 1u);
  EXPECT_EQ(q.positive.clusters[0].size, 3u);
  EXPECT_TRUE(q.positive.percolates[2]);
  EXPECT_EQ(q.label[3], 0);
  const std::string json = sable::summary(q).json();
  EXPECT_NE(json.find("\"z\": true"), std::string::npos);
}

// ---------------------------------------------------------------- bad input

TEST(AnalysisForces, BadInputIsAnInputError) {
  const ContactSet<3> empty;
  EXPECT_NE(input_error([&] {
              sable::force_statistics(empty);
            }).find("no compressive contacts to build a force PDF from"),
            std::string::npos);
  sable::ForceStatsOptions fo;
  fo.component = sable::ForceComponent::tangential;
  EXPECT_NE(input_error([&] { sable::force_statistics(empty, fo); }).find("tangential"),
            std::string::npos);
  EXPECT_NE(input_error([&] { sable::fabric(empty); }).find("fabric tensor"), std::string::npos);
  EXPECT_NE(input_error([&] { sable::polarization(empty, {}); }).find("no contacts selected"),
            std::string::npos);
  const auto c = polar_set<3>();
  fo = {};
  fo.bins = 0;
  EXPECT_NE(input_error([&] { sable::force_statistics(c, fo); }).find("bins"), std::string::npos);
  sable::FabricOptions fab;
  fab.bins = -1;
  EXPECT_NE(input_error([&] { sable::fabric(c, fab); }).find("bins"), std::string::npos);
  sable::PolarizationOptions po;
  po.bins = 0;
  EXPECT_NE(input_error([&] { sable::polarization(c, sable::select_bulk(c), po); }).find("bins"),
            std::string::npos);
  for (double eps : {1.0, -0.1, std::nan("")}) {
    po = {};
    po.eps = eps;
    EXPECT_NE(input_error([&] { sable::polarization(c, sable::select_bulk(c), po); }).find("eps"),
              std::string::npos);
  }
  fo = {};
  fo.reference_force = -1.0;
  EXPECT_NE(input_error([&] { sable::force_statistics(c, fo); }).find("reference force"),
            std::string::npos);
  const auto s = grid();
  EXPECT_NE(input_error([&] {
              sable::percolation(s, std::vector<double>(3, 1.0));
            }).find("3 values for 25 grains"),
            std::string::npos);
  EXPECT_NE(input_error([&] { sable::coordination(Sample<2>{}); }).find("no grains"),
            std::string::npos);
}

}  // namespace
