// The coarse-graining weights: kernel names, the exact sphere-kernel fractions (segment in a
// ball, lens of two balls), the Gaussian and Lucy normalisations, and the contact line
// integral. See coarse_grain.hpp for the formulas and their sources.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "sable/analysis/coarse_grain.hpp"
#include "sable/core/error.hpp"

namespace sable {

const char* cg_kernel_name(CgKernel k) {
  switch (k) {
    case CgKernel::Sphere:
      return "sphere";
    case CgKernel::Gaussian:
      return "gaussian";
    case CgKernel::Lucy:
      return "lucy";
  }
  return "?";
}

CgKernel parse_cg_kernel(const std::string& name, const std::string& key) {
  for (CgKernel k : {CgKernel::Sphere, CgKernel::Gaussian, CgKernel::Lucy})
    if (name == cg_kernel_name(k)) return k;
  throw InputError(fmt::format(
      "{}: unknown coarse-graining kernel \"{}\" (expected one of \"sphere\", \"gaussian\", "
      "\"lucy\")",
      key, name));
}

namespace cg {

namespace {

constexpr double kPi = std::numbers::pi;

// 8-point Gauss-Legendre rule on [-1, 1] (abscissae +-x_k, weights w_k): exact for
// polynomials of degree 15 on each panel of a branch.
constexpr std::array<double, 4> kGlX = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267,
                                        0.9602898564975363};
constexpr std::array<double, 4> kGlW = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745,
                                        0.1012285362903763};

// Panels of the line integral: one per kernel width of branch, so that the 8 points of a
// panel always sample the kernel's profile finely (at most w / 8 apart); capped for absurd
// inputs (a branch thousands of widths long spans few nodes anyway).
constexpr double kMaxPanels = 256.0;

}  // namespace

template <int D>
double segment_fraction_in_ball(const typename Space<D>::Vec& p, const typename Space<D>::Vec& l,
                                const typename Space<D>::Vec& c, double radius) {
  // |q + s l|^2 = R^2 with q = p - c: a s^2 + 2 b s + k = 0; the chord is [s1, s2].
  const typename Space<D>::Vec q = p - c;
  const double a = l.squaredNorm();
  const double k = q.squaredNorm() - radius * radius;
  if (a == 0.0) return k < 0.0 ? 1.0 : 0.0;
  const double b = q.dot(l);
  const double disc = b * b - a * k;
  if (disc <= 0.0) return 0.0;  // misses the ball, or touches it at one point
  const double root = std::sqrt(disc);
  const double s1 = (-b - root) / a, s2 = (-b + root) / a;
  return std::max(std::min(s2, 1.0) - std::max(s1, 0.0), 0.0);
}

template <>
double ball_intersection<3>(double r1, double r2, double d) {
  if (d >= r1 + r2) return 0.0;
  const double rmin = std::min(r1, r2);
  if (d <= std::abs(r1 - r2)) return 4.0 / 3.0 * kPi * rmin * rmin * rmin;
  // The lens of two spheres: pi (r1 + r2 - d)^2 (d^2 + 2 d (r1 + r2) - 3 (r1 - r2)^2) / (12 d)
  // (the two spherical caps cut by the radical plane, summed).
  const double t = r1 + r2 - d;
  return kPi * t * t * (d * d + 2.0 * d * (r1 + r2) - 3.0 * (r1 - r2) * (r1 - r2)) / (12.0 * d);
}

template <>
double ball_intersection<2>(double r1, double r2, double d) {
  if (d >= r1 + r2) return 0.0;
  const double rmin = std::min(r1, r2);
  if (d <= std::abs(r1 - r2)) return kPi * rmin * rmin;
  // Two circular segments: r1^2 acos(c1) + r2^2 acos(c2) - (1/2) sqrt(K), with K = 16 times
  // the squared area of the triangle of sides d, r1, r2 (Heron).
  const double c1 = std::clamp((d * d + r1 * r1 - r2 * r2) / (2.0 * d * r1), -1.0, 1.0);
  const double c2 = std::clamp((d * d + r2 * r2 - r1 * r1) / (2.0 * d * r2), -1.0, 1.0);
  const double k = (-d + r1 + r2) * (d + r1 - r2) * (d - r1 + r2) * (d + r1 + r2);
  return r1 * r1 * std::acos(c1) + r2 * r2 * std::acos(c2) - 0.5 * std::sqrt(std::max(k, 0.0));
}

template <>
double ball_measure<3>(double r) {
  return 4.0 / 3.0 * kPi * r * r * r;
}

template <>
double ball_measure<2>(double r) {
  return kPi * r * r;
}

template <>
double gaussian_norm<2>(double w) {
  // int_0^{3w} exp(-r^2 / 2w^2) 2 pi r dr = 2 pi w^2 (1 - e^{-9/2}).
  return 2.0 * kPi * w * w * (1.0 - std::exp(-4.5));
}

template <>
double gaussian_norm<3>(double w) {
  // int_0^{3w} exp(-r^2 / 2w^2) 4 pi r^2 dr = 4 pi w^3 int_0^3 u^2 e^{-u^2/2} du, and by parts
  // int_0^a u^2 e^{-u^2/2} du = sqrt(pi/2) erf(a / sqrt 2) - a e^{-a^2/2}.
  return 4.0 * kPi * w * w * w *
         (std::sqrt(kPi / 2.0) * std::erf(3.0 / std::numbers::sqrt2) - 3.0 * std::exp(-4.5));
}

template <int D>
Kernel<D>::Kernel(CgKernel k, double w, double thick) : kind(k), width(w), thickness(thick) {
  const double depth = D == 2 ? thick : 1.0;  // 2D: weights per unit area / thickness
  switch (k) {
    case CgKernel::Sphere:
      reach_ = w;
      norm_ = 1.0 / (ball_measure<D>(w) * depth);
      break;
    case CgKernel::Gaussian:
      reach_ = 3.0 * w;
      norm_ = 1.0 / (gaussian_norm<D>(w) * depth);
      break;
    case CgKernel::Lucy:
      reach_ = w;
      // Lucy (1977): int_0^c (1 + 3q)(1 - q)^3 4 pi r^2 dr = 16 pi c^3 / 105 (q = r/c), and
      // 2 pi r dr gives pi c^2 / 5 in 2D.
      norm_ = (D == 3 ? 105.0 / (16.0 * kPi * w * w * w) : 5.0 / (kPi * w * w)) / depth;
      break;
  }
}

template <int D>
double Kernel<D>::point(double r2) const {
  if (r2 >= reach_ * reach_) return 0.0;
  switch (kind) {
    case CgKernel::Sphere:
      return norm_;
    case CgKernel::Gaussian:
      return norm_ * std::exp(-r2 / (2.0 * width * width));
    case CgKernel::Lucy: {
      const double q = std::sqrt(r2) / width;
      const double u = 1.0 - q;
      return norm_ * (1.0 + 3.0 * q) * u * u * u;
    }
  }
  return 0.0;
}

template <int D>
double Kernel<D>::grain_reach(double radius) const {
  return kind == CgKernel::Sphere ? reach_ + radius : reach_;
}

template <int D>
double Kernel<D>::grain(const Vec& d, double radius) const {
  if (kind != CgKernel::Sphere) return point(d.squaredNorm());
  // Guillard et al. (2015) eq. (4): the fraction of the grain's volume inside the ball.
  const double inside = ball_intersection<D>(reach_, radius, d.norm());
  return inside == 0.0 ? 0.0 : norm_ * inside / ball_measure<D>(radius);
}

template <int D>
double Kernel<D>::segment(const Vec& node, const Vec& p, const Vec& l) const {
  // Nothing to do if the segment stays farther than the reach from the node.
  const double ll = l.squaredNorm();
  const double s_near = ll > 0.0 ? std::clamp((node - p).dot(l) / ll, 0.0, 1.0) : 0.0;
  if ((p + s_near * l - node).squaredNorm() >= reach_ * reach_) return 0.0;
  // Guillard et al. (2015) eq. (3): the fraction of the branch inside the ball.
  if (kind == CgKernel::Sphere) return norm_ * segment_fraction_in_ball<D>(p, l, node, reach_);
  const double panels = std::min(std::max(std::ceil(std::sqrt(ll) / width), 1.0), kMaxPanels);
  const int np = static_cast<int>(panels);
  const double half = 0.5 / panels;  // half a panel, in s
  double sum = 0.0;
  for (int k = 0; k < np; ++k) {
    const double mid = (2.0 * k + 1.0) * half;
    for (std::size_t q = 0; q < kGlX.size(); ++q) {
      const double sa = mid - half * kGlX[q], sb = mid + half * kGlX[q];
      sum += kGlW[q] *
             (point((p + sa * l - node).squaredNorm()) + point((p + sb * l - node).squaredNorm()));
    }
  }
  return sum * half;
}

template double segment_fraction_in_ball<2>(const Space<2>::Vec&, const Space<2>::Vec&,
                                            const Space<2>::Vec&, double);
template double segment_fraction_in_ball<3>(const Space<3>::Vec&, const Space<3>::Vec&,
                                            const Space<3>::Vec&, double);
template struct Kernel<2>;
template struct Kernel<3>;

}  // namespace cg

}  // namespace sable
