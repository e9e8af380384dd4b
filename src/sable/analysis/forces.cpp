#include "sable/analysis/forces.hpp"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "sable/core/error.hpp"

namespace sable {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kPi = std::numbers::pi;
constexpr double kDeg = 180.0 / kPi;

void check_bins(int bins, const char* what) {
  if (bins <= 0)
    throw InputError(fmt::format("{}: the number of bins must be > 0, got {}", what, bins));
}

double mean_of(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return v.empty() ? kNaN : s / static_cast<double>(v.size());
}

// Bin of x in [0, width * bins); values at or past the upper end go to the last bin.
std::size_t bin_of(double x, double width, int bins) {
  const double b = std::floor(x / width);
  if (!(b > 0.0)) return 0;  // also catches NaN
  return std::min(static_cast<std::size_t>(b), static_cast<std::size_t>(bins - 1));
}

// An angle folded to [0, pi): a direction and its opposite are the same axis.
double fold_pi(double a) {
  a = std::fmod(a, kPi);
  if (a < 0.0) a += kPi;
  return a >= kPi ? 0.0 : a;
}

// Exponential tail over x > 1 (Richefeu et al. 2009 eq. 9, P ~ exp(-beta f/<f>)).
//
// Maximum likelihood: for the tail, x - 1 is exponential with rate beta (an exponential
// conditioned on x > 1 stays one), so beta = n / sum(x - 1), standard error beta / sqrt(n).
// For comparison, the least-squares slope of log(pdf) against the bin centre over the bins
// lying wholly above x = 1 with at least one count; each bin is weighted by its count, since the
// variance of the log of a Poisson count n is about 1 / n (sparse far bins would bias an
// unweighted fit). R^2 is the weighted coefficient of determination.
TailFit tail_fit(const std::vector<double>& x, const ForceDistribution& d) {
  TailFit t;
  double s = 0.0;
  for (double v : x)
    if (v > 1.0) {
      ++t.n_tail;
      s += v - 1.0;
    }
  t.beta = s > 0.0 ? static_cast<double>(t.n_tail) / s : kNaN;
  t.beta_stderr = t.n_tail > 0 ? t.beta / std::sqrt(static_cast<double>(t.n_tail)) : kNaN;
  double w = 0.0, sx = 0.0, sy = 0.0;
  std::vector<double> bx, by, bw;
  for (std::size_t b = 0; b < d.counts.size(); ++b) {
    if (static_cast<double>(b) * d.bin_width < 1.0 || d.counts[b] <= 0.0) continue;
    bx.push_back((static_cast<double>(b) + 0.5) * d.bin_width);
    by.push_back(std::log(d.pdf[b]));
    bw.push_back(d.counts[b]);
    w += bw.back();
    sx += bw.back() * bx.back();
    sy += bw.back() * by.back();
  }
  t.lsq_bins = bx.size();
  t.beta_lsq = t.r2_lsq = kNaN;
  if (bx.size() < 2) return t;
  const double xm = sx / w, ym = sy / w;
  double sxx = 0.0, sxy = 0.0, syy = 0.0;
  for (std::size_t k = 0; k < bx.size(); ++k) {
    sxx += bw[k] * (bx[k] - xm) * (bx[k] - xm);
    sxy += bw[k] * (bx[k] - xm) * (by[k] - ym);
    syy += bw[k] * (by[k] - ym) * (by[k] - ym);
  }
  const double slope = sxy / sxx;
  t.beta_lsq = -slope;
  t.r2_lsq = syy > 0.0 ? (slope * sxy) / syy : kNaN;  // 1 - SS_res / SS_tot
  return t;
}

// The distribution of the magnitudes `f` (one side), in x = f / f_norm.
ForceDistribution distribution(std::string side, std::string variable, const std::vector<double>& f,
                               double f_norm, std::size_t total, const ForceStatsOptions& opt) {
  ForceDistribution d;
  d.side = std::move(side);
  d.variable = std::move(variable);
  d.count = f.size();
  d.fraction = total > 0 ? static_cast<double>(d.count) / static_cast<double>(total) : kNaN;
  d.counts.assign(static_cast<std::size_t>(opt.bins), 0.0);
  if (f.empty()) {  // e.g. the tensile side of a dry sample: no statistic, an empty histogram
    d.mean_force = d.fraction_below_mean = d.alpha = d.p0 = kNaN;
    d.tail.beta = d.tail.beta_stderr = d.tail.beta_lsq = d.tail.r2_lsq = kNaN;
    d.bin_width = 1.0 / opt.bins;
    d.pdf.assign(d.counts.size(), kNaN);
    return d;
  }
  const double n = static_cast<double>(d.count);
  d.mean_force = mean_of(f);
  std::vector<double> x(f.size());
  double below = 0.0, near0 = 0.0, x_max = 0.0;
  for (std::size_t k = 0; k < f.size(); ++k) {
    x[k] = f[k] / f_norm;
    below += f[k] < d.mean_force ? 1.0 : 0.0;
    near0 += x[k] < opt.p0_window ? 1.0 : 0.0;
    x_max = std::max(x_max, x[k]);
  }
  d.fraction_below_mean = below / n;
  const double x_mean = mean_of(x);
  d.alpha = x_mean > 0.0 ? 1.0 / x_mean : kNaN;  // MLE of P ~ exp(-alpha x), Richefeu eq. 10
  // P(0): the density over the window [0, p0_window) next to zero, a fixed width in x so the
  // estimate does not depend on the number of histogram bins.
  d.p0 = near0 / (n * opt.p0_window);
  d.bin_width = (x_max > 0.0 ? x_max : 1.0) / opt.bins;
  for (double v : x) d.counts[bin_of(v, d.bin_width, opt.bins)] += 1.0;
  for (double cnt : d.counts) d.pdf.push_back(cnt / (n * d.bin_width));  // integral = 1
  d.tail = tail_fit(x, d);
  return d;
}

void check_force_options(const ForceStatsOptions& opt) {
  check_bins(opt.bins, "force statistics");
  if (!(opt.reference_force >= 0.0) || !std::isfinite(opt.reference_force))
    throw InputError(fmt::format(
        "force statistics: the reference force must be finite and >= 0 (0: the mean), got {}",
        opt.reference_force));
  if (!(opt.p0_window > 0.0) || !std::isfinite(opt.p0_window))
    throw InputError(
        fmt::format("force statistics: the P(0) window must be > 0, got {}", opt.p0_window));
}

Summary tail_summary(const TailFit& t) {
  Summary s;
  s.add("n_tail", t.n_tail).add("beta_mle", t.beta).add("beta_mle_stderr", t.beta_stderr);
  s.add("beta_lsq", t.beta_lsq).add("r2_lsq", t.r2_lsq).add("lsq_bins", t.lsq_bins);
  return s;
}

template <int D>
std::vector<bool> mask_if(const ContactSet<D>& c, auto pred) {
  std::vector<bool> m(c.size());
  for (std::size_t k = 0; k < c.size(); ++k) m[k] = pred(k);
  return m;
}

}  // namespace

// ---------------------------------------------------------------- selections

template <int D>
std::vector<bool> select_bulk(const ContactSet<D>& c) {
  return mask_if(c, [&](std::size_t k) { return !c.is_wall(k); });
}

template <int D>
std::vector<bool> select_walls(const ContactSet<D>& c) {
  return mask_if(c, [&](std::size_t k) { return c.is_wall(k); });
}

template <int D>
std::vector<bool> select_wall(const ContactSet<D>& c, std::uint32_t wall) {
  return mask_if(c, [&](std::size_t k) { return c.is_wall(k) && c.j[k] == wall; });
}

template <int D>
std::vector<bool> select_region(const ContactSet<D>& c,
                                const std::vector<typename Space<D>::Vec>& x,
                                const Region<D>& region, bool include_walls) {
  for (std::size_t k = 0; k < c.size(); ++k)
    if (c.i[k] >= x.size())
      throw InputError(fmt::format("contact {} names grain {}, the sample holds {} grains", k,
                                   c.i[k], x.size()));
  return mask_if(c, [&](std::size_t k) {
    return (include_walls || !c.is_wall(k)) && region.contains(c.point(k, x));
  });
}

// ---------------------------------------------------------------- force statistics

template <int D>
ForceStats force_statistics(const ContactSet<D>& c, const ForceStatsOptions& opt) {
  check_force_options(opt);
  ForceStats st;
  st.component = opt.component;
  st.include_walls = opt.include_walls;
  st.dim = D;
  st.p0_window = opt.p0_window;
  st.reference = opt.reference_force > 0.0;
  std::vector<double> comp, tens, tang;
  for (std::size_t k = 0; k < c.size(); ++k) {
    if (c.is_wall(k) && !opt.include_walls) continue;
    ++st.contacts;
    if (opt.component == ForceComponent::tangential) {
      tang.push_back(c.ft[k].norm());
    } else if (c.fn[k] > 0.0) {
      comp.push_back(c.fn[k]);
    } else if (c.fn[k] < 0.0) {
      tens.push_back(-c.fn[k]);
    } else {
      ++st.zero_count;
    }
  }
  const char* which = opt.include_walls ? "contacts" : "grain-grain contacts";
  const std::string suffix = st.reference ? "_over_f0" : "_over_mean";
  if (opt.component == ForceComponent::normal) {
    if (comp.empty())
      throw InputError(
          fmt::format("no compressive contacts to build a force PDF from ({} selected {})",
                      st.contacts, which));
    // Both sides are normalised by the compressive mean (Richefeu et al. 2009 Fig. 3), or f0.
    st.f_norm = st.reference ? opt.reference_force : mean_of(comp);
    st.sides.push_back(
        distribution("compressive", "f" + suffix, comp, st.f_norm, st.contacts, opt));
    st.sides.push_back(
        distribution("tensile", "abs_f" + suffix, tens, st.f_norm, st.contacts, opt));
  } else {
    if (tang.empty())
      throw InputError(fmt::format("no {} to build a tangential force PDF from", which));
    st.f_norm = st.reference ? opt.reference_force : mean_of(tang);
    if (!(st.f_norm > 0.0))
      throw InputError(fmt::format(
          "all {} tangential forces are zero: no mean to normalise them by", tang.size()));
    st.sides.push_back(
        distribution("tangential", "ft" + suffix, tang, st.f_norm, st.contacts, opt));
  }
  return st;
}

Summary summary(const ForceStats& s) {
  Summary out;
  const bool normal = s.component == ForceComponent::normal;
  out.add("component", normal ? "normal" : "tangential");
  out.add("include_walls", s.include_walls).add("contacts", s.contacts);
  out.add("force_unit", s.dim == 2 ? "N/m" : "N");
  out.add("normalisation",
          s.reference ? "reference" : (normal ? "mean_compressive" : "mean_tangential"));
  out.add("f_norm", s.f_norm);
  if (normal) out.add("zero_count", s.zero_count);
  out.add("p0_window", s.p0_window);
  Summary sides;
  for (const auto& d : s.sides) {
    Summary e;
    e.add("variable", d.variable).add("count", d.count).add("fraction", d.fraction);
    e.add("mean_force", d.mean_force).add("fraction_below_mean", d.fraction_below_mean);
    e.add("alpha", d.alpha).add("p0", d.p0);
    e.add("bins", d.counts.size()).add("bin_width", d.bin_width);
    e.add("tail", tail_summary(d.tail));
    sides.add(d.side, e);
  }
  out.add("sides", sides);
  return out;
}

namespace {

// The lower edge, upper edge and centre columns of `n` bins of `width` from 0, named
// NAME_lo, NAME_hi and NAME (NAME may carry a unit suffix after them, e.g. "_deg").
void add_bins(Table& t, const std::string& name, const std::string& unit, std::size_t n,
              double width) {
  std::vector<double> lo, hi, mid;
  for (std::size_t b = 0; b < n; ++b) {
    lo.push_back(static_cast<double>(b) * width);
    hi.push_back(static_cast<double>(b + 1) * width);
    mid.push_back((static_cast<double>(b) + 0.5) * width);
  }
  t.add(name + "_lo" + unit, lo);
  t.add(name + "_hi" + unit, hi);
  t.add(name + unit, mid);
}

}  // namespace

Table table(const ForceDistribution& d) {
  Table t;
  add_bins(t, d.variable, "", d.counts.size(), d.bin_width);
  t.add("count", d.counts);
  t.add("pdf", d.pdf);
  return t;
}

// ---------------------------------------------------------------- coordination

namespace {

// Marks rattlers: fewer than `threshold` force-carrying contacts (wall contacts count). When
// iterating, contacts with grains already marked no longer count, until nothing changes.
template <int D>
void mark_rattlers(const Sample<D>& s, Coordination& r, bool iterate) {
  const auto& c = s.contacts;
  const auto thr = static_cast<std::uint32_t>(r.rattler_threshold);
  for (std::size_t g = 0; g < s.size(); ++g) r.rattler[g] = r.per_grain[g] < thr ? 1 : 0;
  for (bool changed = iterate; changed;) {
    std::vector<std::uint32_t> live(s.size(), 0);
    for (std::size_t k = 0; k < c.size(); ++k) {
      if (c.is_wall(k)) {
        ++live[c.i[k]];
      } else if (!r.rattler[c.i[k]] && !r.rattler[c.j[k]]) {
        ++live[c.i[k]];
        ++live[c.j[k]];
      }
    }
    changed = false;
    for (std::size_t g = 0; g < s.size(); ++g)
      if (!r.rattler[g] && live[g] < thr) r.rattler[g] = changed = true;
  }
}

}  // namespace

template <int D>
Coordination coordination(const Sample<D>& s, const CoordinationOptions& opt) {
  if (s.size() == 0)
    throw InputError(fmt::format("{}: the sample holds no grains to count contacts of", s.source));
  check_contact_indices(s);
  const auto& c = s.contacts;
  Coordination r;
  r.dim = D;
  r.grains = s.size();
  for (std::size_t g = 0; g < s.fixed.size(); ++g) r.fixed_grains += s.fixed[g] ? 1 : 0;
  r.per_grain.assign(s.size(), 0);
  for (std::size_t k = 0; k < c.size(); ++k) {
    ++r.per_grain[c.i[k]];
    if (c.is_wall(k)) {
      ++r.wall_contacts;
      continue;
    }
    ++r.per_grain[c.j[k]];
    ++r.contacts;
    r.compressive += c.fn[k] > 0.0 ? 1 : 0;
    r.tensile += c.fn[k] < 0.0 ? 1 : 0;
  }
  const double n = static_cast<double>(r.grains);
  r.z = 2.0 * static_cast<double>(r.contacts) / n;
  r.z_compressive = 2.0 * static_cast<double>(r.compressive) / n;
  r.z_tensile = 2.0 * static_cast<double>(r.tensile) / n;
  r.wall_per_grain = static_cast<double>(r.wall_contacts) / n;
  // Rattler: fewer than D force-carrying contacts (2 in 2D, 3 in 3D), the rule used for
  // frictional packings; frictionless (isostatic) counting would ask D + 1. Fixed grains are
  // counted like free ones: the analysis sees contacts, not boundary conditions.
  r.rattler_threshold = D == 2 ? 2 : 3;
  r.rattler.assign(s.size(), 0);
  mark_rattlers(s, r, opt.iterate_rattlers);
  for (std::uint8_t v : r.rattler) r.rattlers += v;
  r.rattler_fraction = static_cast<double>(r.rattlers) / n;
  for (std::size_t k = 0; k < c.size(); ++k)
    if (!c.is_wall(k) && !r.rattler[c.i[k]] && !r.rattler[c.j[k]]) ++r.non_rattler_contacts;
  const std::size_t kept = r.grains - r.rattlers;
  r.z_without_rattlers =
      kept > 0 ? 2.0 * static_cast<double>(r.non_rattler_contacts) / static_cast<double>(kept)
               : kNaN;
  return r;
}

Summary summary(const Coordination& c) {
  Summary s;
  s.add("grains", c.grains).add("fixed_grains", c.fixed_grains);
  s.add("contacts", c.contacts).add("compressive", c.compressive).add("tensile", c.tensile);
  s.add("wall_contacts", c.wall_contacts);
  s.add("z", c.z).add("z_compressive", c.z_compressive).add("z_tensile", c.z_tensile);
  s.add("wall_contacts_per_grain", c.wall_per_grain);
  s.add("rattler_threshold", c.rattler_threshold);
  s.add("rattlers", c.rattlers).add("rattler_fraction", c.rattler_fraction);
  s.add("non_rattler_contacts", c.non_rattler_contacts);
  s.add("z_without_rattlers", c.z_without_rattlers);
  return s;
}

Table table(const Coordination& c) {
  std::uint32_t top = 0;
  for (auto v : c.per_grain) top = std::max(top, v);
  std::vector<double> k(top + 1), grains(top + 1, 0.0), frac(top + 1);
  for (auto v : c.per_grain) grains[v] += 1.0;
  for (std::size_t b = 0; b <= top; ++b) {
    k[b] = static_cast<double>(b);
    frac[b] = grains[b] / static_cast<double>(c.grains);
  }
  Table t;
  t.add("contacts", k);
  t.add("grains", grains);
  t.add("fraction", frac);
  return t;
}

// ---------------------------------------------------------------- fabric

namespace {

// 2D: the angle of n in [0, pi), density per radian (isotropic: 1 / pi).
// 3D: the polar angle of n from z folded to [0, pi/2] (n ~ -n); bins of equal angle hold
// unequal solid angles, 2 pi (cos a - cos b) each on the half sphere, so the density is per
// steradian (isotropic: 1 / (2 pi)) and over_isotropic = fraction / (cos a - cos b).
template <int D>
void orientation_histogram(const std::vector<typename Space<D>::Vec>& n, int bins, Fabric& f) {
  const double span = D == 2 ? kPi : 0.5 * kPi;
  const double w = span / bins, total = static_cast<double>(n.size());
  f.counts.assign(static_cast<std::size_t>(bins), 0.0);
  for (const auto& v : n) {
    const double a = D == 2 ? fold_pi(std::atan2(v[1], v[0]))
                            : std::acos(std::min(1.0, std::abs(v[D - 1]) / v.norm()));
    f.counts[bin_of(a, w, bins)] += 1.0;
  }
  for (std::size_t b = 0; b < f.counts.size(); ++b) {
    const double lo = static_cast<double>(b) * w, hi = lo + w, frac = f.counts[b] / total;
    f.angle_lo_deg.push_back(lo * kDeg);
    f.angle_hi_deg.push_back(hi * kDeg);
    if (D == 2) {
      f.density.push_back(frac / w);
      f.over_isotropic.push_back(frac / w * kPi);
    } else {
      const double cap = std::cos(lo) - std::cos(hi);
      f.density.push_back(frac / (2.0 * kPi * cap));
      f.over_isotropic.push_back(frac / cap);
    }
  }
}

// 3D: the azimuth of n's projection on the xy plane folded to [0, pi) (density per radian).
void azimuth_histogram(const std::vector<Eigen::Vector3d>& n, int bins, Fabric& f) {
  const double w = kPi / bins;
  f.azimuth_counts.assign(static_cast<std::size_t>(bins), 0.0);
  double used = 0.0;
  for (const auto& v : n) {
    if (std::hypot(v.x(), v.y()) < 1e-12 * v.norm()) {  // along z: no azimuth
      ++f.azimuth_skipped;
      continue;
    }
    f.azimuth_counts[bin_of(fold_pi(std::atan2(v.y(), v.x())), w, bins)] += 1.0;
    used += 1.0;
  }
  for (double cnt : f.azimuth_counts)
    f.azimuth_density.push_back(used > 0 ? cnt / (used * w) : kNaN);
}

void azimuth_histogram(const std::vector<Eigen::Vector2d>&, int, Fabric&) {}

}  // namespace

template <int D>
Fabric fabric(const ContactSet<D>& c, const FabricOptions& opt) {
  check_bins(opt.bins, "fabric orientation histogram");
  check_bins(opt.azimuth_bins, "fabric azimuth histogram");
  using Mat = Eigen::Matrix<double, D, D>;
  std::vector<typename Space<D>::Vec> n;
  Mat phi = Mat::Zero();
  for (std::size_t k = 0; k < c.size(); ++k) {
    if ((c.is_wall(k) && !opt.include_walls) || (opt.compressive_only && !(c.fn[k] > 0.0)))
      continue;
    n.push_back(c.n[k]);
    phi += c.n[k] * c.n[k].transpose();
  }
  if (n.empty())
    throw InputError(fmt::format("no {}{} to build a fabric tensor from",
                                 opt.compressive_only ? "compressive " : "",
                                 opt.include_walls ? "contacts" : "grain-grain contacts"));
  Fabric f;
  f.dim = D;
  f.contacts = n.size();
  phi /= static_cast<double>(n.size());
  f.tensor = phi;
  const Eigen::SelfAdjointEigenSolver<Mat> es(phi);  // ascending eigenvalues
  f.eigenvalues = es.eigenvalues().reverse();
  f.eigenvectors = es.eigenvectors().rowwise().reverse();
  for (int col = 0; col < D; ++col) {  // a deterministic sign: largest component positive
    Eigen::Index at = 0;
    f.eigenvectors.col(col).cwiseAbs().maxCoeff(&at);
    if (f.eigenvectors(at, col) < 0.0) f.eigenvectors.col(col) *= -1.0;
  }
  // Anisotropy of the contact orientations (Rothenburg & Bathurst 1989 in 2D, P(theta) =
  // (1 + a cos 2(theta - theta_c)) / pi gives phi1 - phi2 = a / 2; in 3D the analogous
  // second-order expansion gives a = 5/2 (phi1 - phi3), e.g. Radjai, Granular Materials 2011).
  f.anisotropy = D == 2 ? 2.0 * (f.eigenvalues[0] - f.eigenvalues[1])
                        : 2.5 * (f.eigenvalues[0] - f.eigenvalues[D - 1]);
  f.major_angle_deg =
      D == 2 ? fold_pi(std::atan2(f.eigenvectors(1, 0), f.eigenvectors(0, 0))) * kDeg : kNaN;
  orientation_histogram<D>(n, opt.bins, f);
  azimuth_histogram(n, opt.azimuth_bins, f);
  return f;
}

Summary summary(const Fabric& f) {
  Summary s;
  s.add("contacts", f.contacts);
  std::vector<double> t(f.tensor.data(), f.tensor.data() + f.tensor.size());  // symmetric
  s.add("tensor", t);
  s.add("eigenvalues",
        std::vector<double>(f.eigenvalues.data(), f.eigenvalues.data() + f.eigenvalues.size()));
  Summary vecs;
  for (Eigen::Index col = 0; col < f.eigenvectors.cols(); ++col) {
    const Eigen::VectorXd v = f.eigenvectors.col(col);
    vecs.add(fmt::format("{}", col + 1), std::vector<double>(v.data(), v.data() + v.size()));
  }
  s.add("eigenvectors", vecs);
  s.add("anisotropy", f.anisotropy);
  if (f.dim == 2) s.add("major_angle_deg", f.major_angle_deg);
  if (f.dim == 3) s.add("azimuth_skipped", f.azimuth_skipped);
  return s;
}

Table table(const Fabric& f) {
  std::vector<double> mid;
  for (std::size_t b = 0; b < f.counts.size(); ++b)
    mid.push_back(0.5 * (f.angle_lo_deg[b] + f.angle_hi_deg[b]));
  Table t;
  const std::string a = f.dim == 2 ? "angle" : "polar_angle";
  t.add(a + "_lo_deg", f.angle_lo_deg);
  t.add(a + "_hi_deg", f.angle_hi_deg);
  t.add(a + "_deg", mid);
  t.add("count", f.counts);
  t.add(f.dim == 2 ? "pdf_per_rad" : "pdf_per_sr", f.density);
  t.add("over_isotropic", f.over_isotropic);
  return t;
}

Table azimuth_table(const Fabric& f) {
  Table t;
  if (f.azimuth_counts.empty()) return t;
  add_bins(t, "azimuth", "_deg", f.azimuth_counts.size(),
           180.0 / static_cast<double>(f.azimuth_counts.size()));
  t.add("count", f.azimuth_counts);
  t.add("pdf_per_rad", f.azimuth_density);
  return t;
}

// ---------------------------------------------------------------- polarization

template <int D>
Polarization polarization(const ContactSet<D>& c, const std::vector<bool>& mask,
                          const PolarizationOptions& opt) {
  check_bins(opt.bins, "polarization histogram");
  if (!(opt.eps >= 0.0 && opt.eps < 1.0))
    throw InputError(fmt::format("polarization: eps must lie in [0, 1), got {}", opt.eps));
  if (mask.size() != c.size())
    throw InputError(fmt::format("polarization: the selection has {} entries for {} contacts",
                                 mask.size(), c.size()));
  Polarization p;
  p.label = opt.label;
  p.eps = opt.eps;
  p.counts.assign(static_cast<std::size_t>(opt.bins), 0.0);
  double sum = 0.0;
  for (std::size_t k = 0; k < c.size(); ++k) {
    if (!mask[k]) continue;
    ++p.selected;
    if (!(c.fn[k] > 0.0)) {
      ++p.excluded_non_compressive;
      continue;
    }
    if (!(c.friction[k] > 0.0)) {
      ++p.excluded_frictionless;
      continue;
    }
    // Mobilisation of friction: m = 1 on the Coulomb cone |ft| = mu fn.
    const double m = c.ft[k].norm() / (c.friction[k] * c.fn[k]);
    ++p.count;
    sum += m;
    p.max_m = std::max(p.max_m, m);
    p.sliding += m >= 1.0 - opt.eps ? 1 : 0;
    p.above_one += m > 1.0 ? 1 : 0;
    p.counts[bin_of(m, 1.0 / opt.bins, opt.bins)] += 1.0;  // m > 1 (round-off) in the last bin
  }
  if (p.selected == 0)
    throw InputError(fmt::format("polarization: no contacts selected ({})", opt.label));
  if (p.count == 0)
    throw InputError(fmt::format(
        "polarization: none of the {} selected contacts ({}) is compressive with friction > 0",
        p.selected, opt.label));
  const double n = static_cast<double>(p.count);
  p.mean_m = sum / n;
  p.fraction_sliding = static_cast<double>(p.sliding) / n;
  for (double cnt : p.counts) p.pdf.push_back(cnt / n * opt.bins);
  return p;
}

Summary summary(const Polarization& p) {
  Summary s;
  s.add("selection", p.label).add("eps", p.eps).add("selected", p.selected);
  s.add("excluded_non_compressive", p.excluded_non_compressive);
  s.add("excluded_frictionless", p.excluded_frictionless);
  s.add("count", p.count).add("sliding", p.sliding).add("fraction_sliding", p.fraction_sliding);
  s.add("mean_m", p.mean_m).add("max_m", p.max_m).add("above_one", p.above_one);
  return s;
}

Table table(const Polarization& p) {
  Table t;
  add_bins(t, "m", "", p.counts.size(), 1.0 / static_cast<double>(p.counts.size()));
  t.add("count", p.counts);
  t.add("pdf", p.pdf);
  return t;
}

// ---------------------------------------------------------------- instantiations

#define SABLE_FORCES_INSTANTIATE(D)                                                        \
  template std::vector<bool> select_bulk<D>(const ContactSet<D>&);                         \
  template std::vector<bool> select_walls<D>(const ContactSet<D>&);                        \
  template std::vector<bool> select_wall<D>(const ContactSet<D>&, std::uint32_t);          \
  template std::vector<bool> select_region<D>(                                             \
      const ContactSet<D>&, const std::vector<Space<D>::Vec>&, const Region<D>&, bool);    \
  template ForceStats force_statistics<D>(const ContactSet<D>&, const ForceStatsOptions&); \
  template Coordination coordination<D>(const Sample<D>&, const CoordinationOptions&);     \
  template Fabric fabric<D>(const ContactSet<D>&, const FabricOptions&);                   \
  template Polarization polarization<D>(const ContactSet<D>&, const std::vector<bool>&,    \
                                        const PolarizationOptions&);
SABLE_FORCES_INSTANTIATE(2)
SABLE_FORCES_INSTANTIATE(3)
#undef SABLE_FORCES_INSTANTIATE

}  // namespace sable
