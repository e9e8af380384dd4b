#include "sable/analysis/dissipation.hpp"

#include <fmt/format.h>

#include <cmath>
#include <utility>

namespace sable {

double PowerBudget::walls() const {
  double s = 0.0;
  for (double p : wall_power) s += p;
  return s;
}

template <int D>
PowerBudget power_budget(const Sample<D>& s) {
  using S = Space<D>;
  using Vec = typename S::Vec;
  check_contact_indices(s);
  refuse_polyhedra(s, "dissipation", kDissipationPolyhedra);
  PowerBudget r;
  r.time = s.time;
  r.rigid = s.geometry == ForceGeometry::kContactDynamics;
  for (std::size_t g = 0; g < s.size(); ++g) {
    if (s.fixed[g]) continue;
    r.kinetic += 0.5 * (s.mass[g] * s.v[g].squaredNorm() + s.inertia[g] * S::rot_norm2(s.omega[g]));
    r.potential -= s.mass[g] * s.gravity.dot(s.x[g]);
  }
  for (const auto& w : s.walls) r.wall_names.push_back(w.name);
  r.wall_power.assign(s.walls.size(), 0.0);
  const auto& c = s.contacts;
  r.contacts = c.size();
  for (std::size_t k = 0; k < c.size(); ++k) {
    const Vec& f = c.force[k];
    const Vec& vrel = c.vrel[k];
    r.contact -= f.dot(vrel);
    if (c.is_wall(k)) {
      const std::uint32_t i = c.i[k];
      const Vec v_wall = s.v[i] + S::spin_velocity(s.omega[i], c.arm_i[k]) - vrel;
      r.wall_power.at(c.j[k]) += f.dot(v_wall);
    }
    const double vn = vrel.dot(c.n[k]);
    r.damping_normal += c.damping_n[k] * vn * vn;
    const Vec vt = vrel - vn * c.n[k];
    // The kernel's own test: the spring alone at the Coulomb cap (a sticking contact's force
    // -k_t xi - gamma_t v_t may exceed the cap while the spring loads; its work then partly
    // goes into the spring, not into heat). Contact dynamics has no spring: |f_t| at the cap.
    const double cap = c.friction[k] * c.fn[k];
    const double tangential = r.rigid ? c.ft[k].norm() : c.spring[k];
    if (cap > 0.0 && tangential >= (1.0 - 1e-9) * cap) {
      ++r.sliding;
      r.sliding_power -= c.ft[k].dot(vt);
    } else {
      r.damping_tangential += c.damping_t[k] * vt.squaredNorm();
    }
  }
  return r;
}

Table power_budget_table(const std::vector<PowerBudget>& rows) {
  Table t;
  auto column = [&](const std::string& name, const auto& value) {
    std::vector<double> col;
    for (const PowerBudget& r : rows) col.push_back(value(r));
    t.add(name, col);
  };
  column("time_s", [](const PowerBudget& r) { return r.time; });
  column("contacts", [](const PowerBudget& r) { return static_cast<double>(r.contacts); });
  column("sliding", [](const PowerBudget& r) { return static_cast<double>(r.sliding); });
  const std::vector<std::string>& names = rows.front().wall_names;
  for (std::size_t w = 0; w < names.size(); ++w)
    column(fmt::format("wall_{}_power_W", names[w]), [&](const PowerBudget& r) {
      return w < r.wall_power.size() ? r.wall_power[w] : std::nan("");
    });
  column("input_power_W", [](const PowerBudget& r) { return r.walls(); });
  column("contact_power_W", [](const PowerBudget& r) { return r.contact; });
  column("dissipation_W", [](const PowerBudget& r) { return r.dissipation(); });
  column("damping_normal_W", [](const PowerBudget& r) { return r.damping_normal; });
  column("damping_tangential_W", [](const PowerBudget& r) { return r.damping_tangential; });
  column("sliding_W", [](const PowerBudget& r) { return r.sliding_power; });
  column("kinetic_J", [](const PowerBudget& r) { return r.kinetic; });
  column("potential_J", [](const PowerBudget& r) { return r.potential; });
  return t;
}

namespace {

// Mean, standard deviation (n - 1) and standard error of the mean of value(row).
template <class F>
Summary stats(const std::vector<PowerBudget>& rows, const F& value) {
  const auto [m, sd] = mean_sd(rows, value);
  Summary s;
  s.add("mean_W", m);
  s.add("sd_W", sd);
  s.add("sem_W", sd / std::sqrt(static_cast<double>(rows.size())));
  return s;
}

}  // namespace

Summary power_budget_summary(const std::vector<PowerBudget>& rows) {
  Summary s;
  s.add("snapshots", rows.size());
  Summary walls;
  const std::vector<std::string>& names = rows.front().wall_names;
  for (std::size_t k = 0; k < names.size(); ++k)
    walls.add(names[k], stats(rows, [&](const PowerBudget& r) {
                return k < r.wall_power.size() ? r.wall_power[k] : 0.0;
              }));
  s.add("walls", walls);
  s.add("input_power", stats(rows, [](const PowerBudget& r) { return r.walls(); }));
  s.add("contact_power", stats(rows, [](const PowerBudget& r) { return r.contact; }));
  s.add("dissipation", stats(rows, [](const PowerBudget& r) { return r.dissipation(); }));
  s.add("damping_normal", stats(rows, [](const PowerBudget& r) { return r.damping_normal; }));
  s.add("damping_tangential",
        stats(rows, [](const PowerBudget& r) { return r.damping_tangential; }));
  s.add("sliding", stats(rows, [](const PowerBudget& r) { return r.sliding_power; }));
  const double in = mean_sd(rows, [](const PowerBudget& r) { return r.walls(); }).first;
  const double out = mean_sd(rows, [](const PowerBudget& r) { return r.dissipation(); }).first;
  s.add("input_over_dissipation", out != 0.0 ? in / out : std::nan(""));
  const PowerBudget &a = rows.front(), &b = rows.back();
  const double span = b.time - a.time;
  s.add("energy_rate_W",
        span > 0.0 ? (b.kinetic + b.potential - a.kinetic - a.potential) / span : std::nan(""));
  return s;
}

template PowerBudget power_budget(const Sample<2>&);
template PowerBudget power_budget(const Sample<3>&);

}  // namespace sable
