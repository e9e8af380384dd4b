#include "sable/analysis/wall_stress.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "sable/core/error.hpp"

namespace sable {

namespace {

template <int D>
int up_axis(const Sample<D>& s) {
  if (s.gravity.squaredNorm() == 0.0) return D - 1;
  int best = 0;
  for (int d = 1; d < D; ++d)
    if (std::abs(s.gravity[d]) > std::abs(s.gravity[best])) best = d;
  return best;
}

template <int D>
std::size_t find_wall(const Sample<D>& s, const std::string& name) {
  std::string names;
  for (std::size_t w = 0; w < s.walls.size(); ++w) {
    if (s.walls[w].name == name) return w;
    if (names.size() <= kQuoteLimit) names += (w ? ", " : "") + clip(s.walls[w].name);
  }
  if (names.size() > kQuoteLimit) names += fmt::format(", ... ({} in all)", s.walls.size());
  throw InputError(fmt::format("{}: no wall named '{}' (walls: {})", s.source, clip(name),
                               names.empty() ? "none" : names));
}

// The wall's width for a bin's area: thickness in 2D, 2 pi R for a cylinder, otherwise the
// grains' extent along the plane's horizontal direction.
template <int D>
double wall_width(const Sample<D>& s, const SampleWall& wall, int axis) {
  if constexpr (D == 2) {
    (void)wall;
    (void)axis;
    return s.thickness;
  } else {
    if (!wall.plane) {
      // The wall's stored normal is unused for cylinders; its radius is the contacts' reach.
      double r = 0.0;
      for (std::size_t k = 0; k < s.contacts.size(); ++k) {
        if (!s.contacts.is_wall(k) || s.walls[s.contacts.j[k]].name != wall.name) continue;
        const Eigen::Vector3d p = s.contacts.point(k, s.x) - Eigen::Vector3d(wall.point.data());
        r = std::max(r, std::hypot(p.x(), p.y()));
      }
      return 2.0 * 3.14159265358979323846 * r;
    }
    Eigen::Vector3d up = Eigen::Vector3d::Zero();
    up[axis] = 1.0;
    const Eigen::Vector3d h = Eigen::Vector3d(wall.normal.data()).cross(up);
    if (h.norm() < 1e-12)
      throw InputError(fmt::format("{}: wall '{}' is perpendicular to the profile axis", s.source,
                                   clip(wall.name)));
    const Eigen::Vector3d e = h.normalized();
    double lo = std::numeric_limits<double>::max(), hi = -lo;
    for (std::size_t g = 0; g < s.size(); ++g) {
      lo = std::min(lo, s.x[g].dot(e) - s.radius[g]);
      hi = std::max(hi, s.x[g].dot(e) + s.radius[g]);
    }
    return hi - lo;
  }
}

}  // namespace

template <int D>
bool is_side_wall(const Sample<D>& s, std::size_t wall, int axis) {
  const SampleWall& w = s.walls[wall];
  if (w.mesh()) return false;
  if (!w.plane) return true;
  const int a = axis >= 0 ? axis : up_axis(s);
  return std::abs(w.normal[static_cast<std::size_t>(a)]) < 1.0 - 1e-9;
}

template <int D>
WallProfile wall_profile(const Sample<D>& s, const std::string& name,
                         const WallProfileOptions& opt) {
  if (s.size() == 0) throw InputError(fmt::format("{}: the sample holds no grains", s.source));
  const std::size_t w = find_wall(s, name);
  if (s.walls[w].mesh())
    throw InputError(
        fmt::format("{}: wall '{}' is a mesh: height profiles are for planes and "
                    "cylinders",
                    s.source, clip(name)));
  WallProfile p;
  p.wall = name;
  p.axis = opt.axis >= 0 ? opt.axis : up_axis(s);
  if (p.axis >= D)
    throw InputError(fmt::format("profile axis {} does not exist in {}D", p.axis, D));
  double mean_d = 0.0, bottom = std::numeric_limits<double>::max();
  p.top = -bottom;
  for (std::size_t g = 0; g < s.size(); ++g) {
    // A polyhedron's size is its volume-equivalent sphere's; its bounding sphere (`radius`)
    // still bounds the profile, which must hold the whole grain.
    const double d =
        s.polyhedra ? std::cbrt(6.0 * s.volume[g] / 3.14159265358979323846) : 2.0 * s.radius[g];
    mean_d += d / static_cast<double>(s.size());
    p.top = std::max(p.top, s.x[g][p.axis] + s.radius[g]);
    bottom = std::min(bottom, s.x[g][p.axis] - s.radius[g]);
  }
  p.bin = opt.bin > 0.0 ? opt.bin : 2.0 * mean_d;
  p.width = opt.width > 0.0 ? opt.width : wall_width(s, s.walls[w], p.axis);
  auto bins = static_cast<std::size_t>(std::ceil((p.top - bottom) / p.bin));
  if (opt.count > 0) {
    bottom = opt.bottom;
    p.top = opt.top;
    bins = opt.count;
  }
  std::vector<double> fn(bins, 0.0), ft(bins, 0.0), abs_ft(bins, 0.0), mu_fn(bins, 0.0);
  p.contacts.assign(bins, 0);
  const auto& c = s.contacts;
  for (std::size_t k = 0; k < c.size(); ++k) {
    if (!c.is_wall(k) || c.j[k] != w) continue;
    const double h = c.point(k, s.x)[p.axis];
    const auto b = static_cast<std::size_t>(
        std::clamp(std::floor((h - bottom) / p.bin), 0.0, static_cast<double>(bins - 1)));
    fn[b] += c.fn[k];
    ft[b] += c.ft[k][p.axis];
    abs_ft[b] += c.ft[k].norm();
    mu_fn[b] += c.friction[k] * c.fn[k];
    ++p.contacts[b];
    p.total_normal += c.fn[k];
    p.total_shear += c.ft[k][p.axis];
  }
  const double area = p.bin * p.width;
  for (std::size_t b = 0; b < bins; ++b) {
    const double h = bottom + (static_cast<double>(b) + 0.5) * p.bin;
    p.height.push_back(h);
    p.depth.push_back(p.top - h);
    p.sigma_n.push_back(fn[b] / area);
    p.tau.push_back(ft[b] / area);
    p.abs_tau.push_back(abs_ft[b] / area);
    p.mobilisation.push_back(mu_fn[b] > 0.0 ? abs_ft[b] / mu_fn[b]
                                            : std::numeric_limits<double>::quiet_NaN());
  }
  return p;
}

void accumulate(WallProfile& sum, const WallProfile& add) {
  if (sum.height.size() != add.height.size())
    throw SimulationError("wall profiles with different bins cannot be averaged");
  for (std::size_t b = 0; b < sum.height.size(); ++b) {
    sum.sigma_n[b] += add.sigma_n[b];
    sum.tau[b] += add.tau[b];
    sum.abs_tau[b] += add.abs_tau[b];
    sum.mobilisation[b] += add.mobilisation[b];
    sum.contacts[b] += add.contacts[b];
  }
  sum.total_normal += add.total_normal;
  sum.total_shear += add.total_shear;
}

void scale(WallProfile& p, double factor) {
  for (std::size_t b = 0; b < p.height.size(); ++b) {
    p.sigma_n[b] *= factor;
    p.tau[b] *= factor;
    p.abs_tau[b] *= factor;
    p.mobilisation[b] *= factor;
  }
  p.total_normal *= factor;
  p.total_shear *= factor;
}

Table wall_profile_table(const WallProfile& p) {
  Table t;
  t.add("height_m", p.height);
  t.add("depth_m", p.depth);
  std::vector<double> n(p.contacts.begin(), p.contacts.end());
  t.add("contacts", n);
  t.add("normal_stress_Pa", p.sigma_n);
  t.add("shear_stress_Pa", p.tau);
  t.add("abs_tangential_stress_Pa", p.abs_tau);
  t.add("mobilisation", p.mobilisation);
  return t;
}

Summary wall_profile_summary(const WallProfile& p) {
  Summary s;
  s.add("wall", p.wall);
  s.add("axis", p.axis);
  s.add("bin_m", p.bin);
  s.add("width_m", p.width);
  s.add("top_m", p.top);
  std::size_t n = 0;
  for (auto c : p.contacts) n += c;
  s.add("contacts", n);
  s.add("total_normal_force_N", p.total_normal);
  s.add("total_shear_force_N", p.total_shear);
  s.add("shear_over_normal", p.total_normal > 0.0 ? p.total_shear / p.total_normal
                                                  : std::numeric_limits<double>::quiet_NaN());
  return s;
}

template bool is_side_wall(const Sample<2>&, std::size_t, int);
template bool is_side_wall(const Sample<3>&, std::size_t, int);
template WallProfile wall_profile(const Sample<2>&, const std::string&, const WallProfileOptions&);
template WallProfile wall_profile(const Sample<3>&, const std::string&, const WallProfileOptions&);

}  // namespace sable
