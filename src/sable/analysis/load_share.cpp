#include "sable/analysis/load_share.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "sable/core/error.hpp"

namespace sable {

double LoadShare::walls() const {
  double s = 0.0;
  for (double f : wall_support) s += f;
  return s;
}

double LoadShare::residual() const {
  return weight - cut - walls() - fixed + momentum_rate;
}

template <int D>
LoadShare load_share(const Sample<D>& s, double level) {
  using Vec = typename Space<D>::Vec;
  const double g = s.gravity.norm();
  if (!(g > 0.0))
    throw InputError(
        fmt::format("{}: load-share needs gravity (the vertical is the direction "
                    "of -g), and this sample has none",
                    s.source));
  check_contact_indices(s);
  const Vec up = -s.gravity / g;
  LoadShare r;
  r.time = s.time;
  r.level = level;
  std::vector<std::uint8_t> above(s.size(), 0);
  for (std::size_t k = 0; k < s.size(); ++k) {
    if (s.fixed[k] || !(s.x[k].dot(up) > level)) continue;
    above[k] = 1;
    ++r.grains_above;
    r.weight += s.mass[k] * g;
    r.momentum_rate += s.mass[k] * s.a[k].dot(up);
  }
  for (const auto& w : s.walls) r.wall_names.push_back(w.name);
  r.wall_support.assign(s.walls.size(), 0.0);
  const auto& c = s.contacts;
  for (std::size_t k = 0; k < c.size(); ++k) {
    const std::uint32_t i = c.i[k], j = c.j[k];
    const double f_up = c.force[k].dot(up);  // on grain i; grain j feels -f_up
    if (c.is_wall(k)) {
      if (above[i]) r.wall_support.at(j) += f_up;
      continue;
    }
    if (above[i] == above[j]) continue;  // inside A: cancels in pairs; outside: not on A
    const bool fixed_partner = s.fixed[i] || s.fixed[j];
    const double on_a = above[i] ? f_up : -f_up;
    if (fixed_partner) {
      r.fixed += on_a;
    } else {
      r.cut += on_a;
      ++r.cut_contacts;
    }
  }
  return r;
}

Table load_share_table(const std::vector<LoadShare>& rows) {
  Table t;
  auto column = [&](const std::string& name, const auto& value) {
    std::vector<double> col;
    for (const LoadShare& r : rows) col.push_back(value(r));
    t.add(name, col);
  };
  column("time_s", [](const LoadShare& r) { return r.time; });
  column("grains_above", [](const LoadShare& r) { return static_cast<double>(r.grains_above); });
  column("weight_N", [](const LoadShare& r) { return r.weight; });
  column("cut_N", [](const LoadShare& r) { return r.cut; });
  const std::vector<std::string>& names = rows.front().wall_names;
  for (std::size_t w = 0; w < names.size(); ++w)
    column(fmt::format("wall_{}_N", names[w]), [&](const LoadShare& r) {
      return w < r.wall_support.size() ? r.wall_support[w] : std::nan("");
    });
  column("fixed_grains_N", [](const LoadShare& r) { return r.fixed; });
  column("momentum_rate_N", [](const LoadShare& r) { return r.momentum_rate; });
  column("residual_N", [](const LoadShare& r) { return r.residual(); });
  return t;
}

namespace {

// A support's force and its share of the weight: means and standard deviations.
template <class F>
Summary support(const std::vector<LoadShare>& rows, const F& value) {
  const auto [m, sd] = mean_sd(rows, value);
  const auto [share, share_sd] =
      mean_sd(rows, [&](const LoadShare& r) { return r.weight > 0.0 ? value(r) / r.weight : 0.0; });
  Summary s;
  s.add("force_N", m);
  s.add("force_sd_N", sd);
  s.add("share", share);
  s.add("share_sd", share_sd);
  return s;
}

}  // namespace

Summary load_share_summary(const std::vector<LoadShare>& rows) {
  Summary s;
  s.add("level_m", rows.front().level);
  s.add("snapshots", rows.size());
  const auto [n, n_sd] =
      mean_sd(rows, [](const LoadShare& r) { return static_cast<double>(r.grains_above); });
  s.add("grains_above", n);
  const auto [w, w_sd] = mean_sd(rows, [](const LoadShare& r) { return r.weight; });
  s.add("weight_N", w);
  s.add("weight_sd_N", w_sd);
  s.add("cut", support(rows, [](const LoadShare& r) { return r.cut; }));
  Summary walls;
  const std::vector<std::string>& names = rows.front().wall_names;
  for (std::size_t k = 0; k < names.size(); ++k)
    walls.add(names[k], support(rows, [&](const LoadShare& r) {
                return k < r.wall_support.size() ? r.wall_support[k] : 0.0;
              }));
  s.add("walls", walls);
  s.add("all_walls", support(rows, [](const LoadShare& r) { return r.walls(); }));
  s.add("fixed_grains", support(rows, [](const LoadShare& r) { return r.fixed; }));
  s.add("momentum_rate", support(rows, [](const LoadShare& r) { return r.momentum_rate; }));
  double worst = 0.0;
  for (const LoadShare& r : rows)
    if (r.weight > 0.0) worst = std::max(worst, std::abs(r.residual()) / r.weight);
  s.add("max_abs_residual_over_weight", worst);
  return s;
}

template LoadShare load_share(const Sample<2>&, double);
template LoadShare load_share(const Sample<3>&, double);

}  // namespace sable
