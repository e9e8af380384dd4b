#include "sable/analysis/janssen.hpp"

#include <fmt/format.h>

#include <cmath>

#include "sable/core/error.hpp"

namespace sable {

double janssen_wall_stress(const JanssenInput& in, double k, double depth) {
  const double lambda = in.area_over_perimeter / (k * in.mu_w);
  return k * in.rho_b * in.g * lambda * (1.0 - std::exp(-std::max(depth, 0.0) / lambda));
}

namespace {

double residual(const JanssenFit& f, const JanssenInput& in, double k) {
  double ss = 0.0;
  for (std::size_t p = 0; p < f.depth.size(); ++p) {
    const double r = f.measured[p] - janssen_wall_stress(in, k, f.depth[p]);
    ss += r * r;
  }
  return ss;
}

// Golden-section search of the residual over log K in [log 0.01, log 100]: the residual is
// smooth and, for data of Janssen's shape, unimodal in K.
double best_k(const JanssenFit& f, const JanssenInput& in) {
  const double phi = 0.5 * (std::sqrt(5.0) - 1.0);
  double a = std::log(0.01), b = std::log(100.0);
  double c = b - phi * (b - a), d = a + phi * (b - a);
  double fc = residual(f, in, std::exp(c)), fd = residual(f, in, std::exp(d));
  for (int it = 0; it < 200 && b - a > 1e-12; ++it) {
    if (fc < fd) {
      b = d;
      d = c;
      fd = fc;
      c = b - phi * (b - a);
      fc = residual(f, in, std::exp(c));
    } else {
      a = c;
      c = d;
      fc = fd;
      d = a + phi * (b - a);
      fd = residual(f, in, std::exp(d));
    }
  }
  return std::exp(0.5 * (a + b));
}

}  // namespace

JanssenFit janssen_fit(const JanssenInput& in) {
  if (!(in.rho_b > 0.0 && in.g > 0.0 && in.area_over_perimeter > 0.0 && in.mu_w > 0.0))
    throw InputError(fmt::format(
        "Janssen fit: bulk density ({}), gravity ({}), A/P ({}) and wall friction ({}) must be "
        "positive",
        in.rho_b, in.g, in.area_over_perimeter, in.mu_w));
  JanssenFit f;
  for (std::size_t p = 0; p < in.depth.size(); ++p)
    if (std::isfinite(in.sigma_xx[p]) && in.sigma_xx[p] != 0.0 && in.depth[p] > 0.0) {
      f.depth.push_back(in.depth[p]);
      f.measured.push_back(in.sigma_xx[p]);
    }
  f.points = f.depth.size();
  if (f.points < 3)
    throw InputError(fmt::format(
        "Janssen fit: {} wall-stress bins carry contacts, at least 3 needed", f.points));
  f.k = best_k(f, in);
  // Standard error from the curvature of SS(K): var(K) = 2 s^2 / SS''(K), s^2 = SS / (n - 1).
  const double ss = residual(f, in, f.k), h = 1e-3 * f.k;
  const double curv = (residual(f, in, f.k + h) - 2.0 * ss + residual(f, in, f.k - h)) / (h * h);
  const double s2 = ss / static_cast<double>(f.points - 1);
  f.k_stderr = curv > 0.0 ? std::sqrt(2.0 * s2 / curv) : std::numeric_limits<double>::infinity();
  double mean = 0.0;
  for (double m : f.measured) mean += m / static_cast<double>(f.points);
  double tot = 0.0;
  for (double m : f.measured) tot += (m - mean) * (m - mean);
  f.r2 = tot > 0.0 ? 1.0 - ss / tot : 0.0;
  for (double z : f.depth) f.fitted.push_back(janssen_wall_stress(in, f.k, z));
  f.lambda = in.area_over_perimeter / (f.k * in.mu_w);
  f.saturation = in.rho_b * in.g * in.area_over_perimeter / in.mu_w;
  f.sigma_zz_bottom = in.rho_b * in.g * f.lambda * (1.0 - std::exp(-in.height / f.lambda));
  f.hydrostatic_bottom = in.rho_b * in.g * in.height;
  return f;
}

Summary janssen_summary(const JanssenFit& f) {
  Summary s;
  s.add("K", f.k);
  s.add("K_stderr", f.k_stderr);
  s.add("lambda_m", f.lambda);
  s.add("r2", f.r2);
  s.add("bins", f.points);
  s.add("saturation_wall_stress_Pa", f.saturation);
  s.add("janssen_sigma_zz_bottom_Pa", f.sigma_zz_bottom);
  s.add("hydrostatic_bottom_Pa", f.hydrostatic_bottom);
  return s;
}

Table janssen_table(const JanssenFit& f) {
  Table t;
  t.add("depth_m", f.depth);
  t.add("wall_normal_stress_Pa", f.measured);
  t.add("janssen_Pa", f.fitted);
  return t;
}

}  // namespace sable
