// The writing half of AnalysisParts (analyze_parts.hpp): one finish_* per group of outputs.
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>

#include "sable/analysis/analyze_parts.hpp"
#include "sable/analysis/forces.hpp"
#include "sable/analysis/janssen.hpp"
#include "sable/analysis/percolation.hpp"
#include "sable/core/error.hpp"

namespace sable {

namespace {

std::string file_safe(const std::string& name) {
  std::string out = name;
  for (char& c : out)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_')) c = '_';
  return out;
}

// One row per force-carrying contact: the network a figure draws (centre to centre, or centre
// to the contact point for walls), the contact point, the normal force and the mobilisation
// |ft| / (mu fn).
template <int D>
Table contact_table(const Sample<D>& s) {
  static constexpr const char* axes = "xyz";
  const auto& c = s.contacts;
  const std::size_t n = c.size();
  std::vector<double> col(n);
  Table t;
  auto add = [&](const std::string& name, const auto& value) {
    for (std::size_t k = 0; k < n; ++k) col[k] = value(k);
    t.add(name, col);
  };
  add("i", [&](std::size_t k) { return static_cast<double>(c.i[k]); });
  add("partner", [&](std::size_t k) { return static_cast<double>(c.j[k]); });
  add("wall", [&](std::size_t k) { return static_cast<double>(c.wall[k]); });
  for (int d = 0; d < D; ++d)
    add(fmt::format("{}_i_m", axes[d]), [&](std::size_t k) { return s.x[c.i[k]][d]; });
  for (int d = 0; d < D; ++d)
    add(fmt::format("{}_end_m", axes[d]), [&](std::size_t k) {
      return c.is_wall(k) ? s.x[c.i[k]][d] + c.arm_i[k][d] : s.x[c.j[k]][d];
    });
  // The contact point (grain i's centre plus its arm): where a polyhedral pair touches, off
  // the line of centres; a bulk region selects contacts by it.
  for (int d = 0; d < D; ++d)
    add(fmt::format("{}_c_m", axes[d]),
        [&](std::size_t k) { return s.x[c.i[k]][d] + c.arm_i[k][d]; });
  add("fn_N", [&](std::size_t k) { return c.fn[k]; });
  add("ft_N", [&](std::size_t k) { return c.ft[k].norm(); });
  add("mobilisation", [&](std::size_t k) {
    const double cap = c.friction[k] * c.fn[k];
    return cap > 0.0 ? c.ft[k].norm() / cap : std::numeric_limits<double>::quiet_NaN();
  });
  return t;
}

}  // namespace

// An analysis the data cannot support (no tensile contacts, no tangential force, no grain
// with a pressure...) is skipped with its reason in the summary, and the others still run.
template <int D>
void AnalysisParts<D>::attempt(Summary& into, const std::string& name,
                               const std::function<void()>& body) {
  try {
    body();
  } catch (const InputError& e) {
    Summary skipped;
    skipped.add("skipped", std::string(e.what()));
    into.add(name, skipped);
    if (opt_.log) *opt_.log << fmt::format("  {}: skipped: {}\n", name, e.what());
  }
}

template <int D>
void AnalysisParts<D>::finish_forces() {
  if (wants("forces")) {
    ForceStatsOptions o;
    o.bins = opt_.bins;
    o.reference_force = opt_.reference_force;
    Summary both;
    for (ForceComponent comp : {ForceComponent::normal, ForceComponent::tangential}) {
      o.component = comp;
      const char* name = comp == ForceComponent::normal ? "normal" : "tangential";
      attempt(both, name, [&] {
        // With --region: the grain-grain contacts whose point lies in it (away from walls);
        // without: every contact, walls included.
        const ForceStats st = force_statistics(region_ ? bulk_ : all_, o);
        both.add(name, summary(st));
        for (const auto& side : st.sides)
          if (side.count > 0) out_.write(fmt::format("force_pdf_{}.csv", side.side), table(side));
      });
    }
    summary_.add("forces", both);
  }
  if (wants("fabric")) {
    attempt(summary_, "fabric", [&] {
      const Fabric f = fabric(bulk_, FabricOptions{});
      summary_.add("fabric", summary(f));
      out_.write("fabric.csv", table(f));
      if (D == 3) out_.write("fabric_azimuth.csv", azimuth_table(f));
    });
  }
  if (wants("polarization")) {
    PolarizationOptions o;
    o.bins = opt_.bins;
    o.eps = opt_.eps;
    Summary pol;
    auto one = [&](const std::string& label, const ContactSet<D>& set) {
      o.label = label;
      attempt(pol, label, [&] {
        const Polarization p = polarization(set, std::vector<bool>(set.size(), true), o);
        pol.add(label, summary(p));
        out_.write(fmt::format("polarization_{}.csv", file_safe(label)), table(p));
      });
    };
    one(region_ ? "region" : "bulk", bulk_);
    one("walls", walls_);
    for (const auto& [name, set] : by_wall_) one("wall_" + name, set);
    summary_.add("polarization", pol);
  }
}

template <int D>
void AnalysisParts<D>::finish_stress() {
  if (!wants("stress")) return;
  const double n = static_cast<double>(samples_);
  MeanStress<D> m = mean_sum_;
  m.contact /= n;
  m.gravity /= n;
  m.inertia /= n;
  m.volume /= n;
  m.grains = static_cast<std::size_t>(std::llround(static_cast<double>(m.grains) / n));
  Summary s = mean_stress_summary(m, Tensor<D>(love_weber_sum_ / n));
  s.add("averaged_over", samples_);
  summary_.add("stress", s);
}

template <int D>
void AnalysisParts<D>::finish_walls() {
  if (!wants("walls")) return;
  Summary all;
  for (auto& [name, p] : profiles_) {
    scale(p, 1.0 / static_cast<double>(samples_));
    all.add(name, wall_profile_summary(p));
    out_.write(fmt::format("wall_profile_{}.csv", file_safe(name)), wall_profile_table(p));
  }
  summary_.add("walls", all);
}

// Each selected wall's mean force and torque over the snapshots (2D: the force in the plane,
// the torque about z as a number), the pivot the torque is about (the last snapshot's).
template <int D>
void AnalysisParts<D>::finish_wall_loads() {
  if (!wants("walls")) return;
  Summary all;
  const double n = static_cast<double>(samples_);
  for (const auto& name : wall_names_) {
    const auto it = loads_.find(name);
    if (it == loads_.end()) continue;
    const WallLoad& load = it->second;
    std::vector<double> force, pivot;
    for (std::size_t d = 0; d < static_cast<std::size_t>(D); ++d) {
      force.push_back(load.force[d] / n);
      pivot.push_back(load.pivot[d]);
    }
    Summary w;
    w.add("type", load.type);
    w.add("force_N", force);
    if constexpr (D == 3)
      w.add("torque_Nm",
            std::vector<double>{load.torque[0] / n, load.torque[1] / n, load.torque[2] / n});
    else
      w.add("torque_Nm", load.torque[2] / n);
    w.add("pivot_m", pivot);
    all.add(name, w);
  }
  summary_.add("wall_loads", all);
}

namespace {

// A / P of the silo the side walls make: 2D, two facing planes (A / P = W / 2); 3D, a
// cylinder (R / 2) or two pairs of facing planes (W1 W2 / (2 (W1 + W2))). Also A (the
// cross-section, times the thickness in 2D).
template <int D>
std::pair<double, double> silo_section(const Sample<D>& s, const std::vector<std::size_t>& side) {
  std::vector<double> widths;
  for (std::size_t a = 0; a < side.size(); ++a) {
    const SampleWall& wa = s.walls[side[a]];
    if (!wa.plane) {
      constexpr double pi = 3.14159265358979323846;
      return {wa.radius / 2.0, pi * wa.radius * wa.radius};
    }
    for (std::size_t b = a + 1; b < side.size(); ++b) {
      const SampleWall& wb = s.walls[side[b]];
      double dot = 0.0, gap = 0.0;
      for (std::size_t d = 0; d < 3; ++d) {
        dot += wa.normal[d] * wb.normal[d];
        gap += (wb.point[d] - wa.point[d]) * wa.normal[d];
      }
      if (dot < -1.0 + 1e-9) widths.push_back(gap);
    }
  }
  if (D == 2 && widths.size() == 1) return {widths[0] / 2.0, widths[0] * s.thickness};
  if (D == 3 && widths.size() == 2)
    return {widths[0] * widths[1] / (2.0 * (widths[0] + widths[1])), widths[0] * widths[1]};
  throw InputError(
      fmt::format("{}: the side walls do not make a silo (2D: two facing planes; "
                  "3D: a cylinder or two pairs of facing planes)",
                  s.source));
}

}  // namespace

template <int D>
void AnalysisParts<D>::finish_janssen() {
  if (!wants("janssen") || !last_) return;
  attempt(summary_, "janssen", [&] {
    const Sample<D>& s = *last_;
    std::vector<std::size_t> side;
    for (std::size_t w = 0; w < s.walls.size(); ++w)
      if (profiles_.count(s.walls[w].name) && is_side_wall(s, w)) side.push_back(w);
    const auto [a_over_p, section] = silo_section(s, side);
    JanssenInput in;
    const WallProfile& first = profiles_.at(s.walls[side.front()].name);
    in.depth = first.depth;
    in.sigma_xx.assign(first.depth.size(), 0.0);
    double mu = 0.0;
    std::size_t n_mu = 0;
    for (std::size_t k = 0; k < s.contacts.size(); ++k)
      if (s.contacts.is_wall(k) &&
          std::find(side.begin(), side.end(), s.contacts.j[k]) != side.end()) {
        mu += s.contacts.friction[k];
        ++n_mu;
      }
    for (std::size_t w : side) {
      const WallProfile& p = profiles_.at(s.walls[w].name);
      for (std::size_t b = 0; b < p.sigma_n.size(); ++b)
        in.sigma_xx[b] += p.sigma_n[b] / static_cast<double>(side.size());
    }
    in.height = first.top - (first.height.front() - 0.5 * first.bin);
    in.rho_b = s.total_mass() / (section * in.height);
    in.g = s.gravity.norm();
    in.area_over_perimeter = a_over_p;
    in.mu_w = n_mu ? mu / static_cast<double>(n_mu) : 0.0;
    const JanssenFit fit = janssen_fit(in);
    Summary j = janssen_summary(fit);
    // The same fit with the friction the walls actually mobilised (sum ft / sum fn), which is
    // what the global balance sees when some wall contacts stick or roll.
    double normal = 0.0, shear = 0.0;
    for (std::size_t w : side) {
      normal += profiles_.at(s.walls[w].name).total_normal;
      shear += profiles_.at(s.walls[w].name).total_shear;
    }
    if (normal > 0.0 && shear > 0.0) {
      JanssenInput mob = in;
      mob.mu_w = shear / normal;
      const JanssenFit m = janssen_fit(mob);
      Summary ms = janssen_summary(m);
      ms.add("wall_friction", mob.mu_w);
      j.add("with_mobilised_friction", ms);
    }
    j.add("bulk_density_kg_m3", in.rho_b);
    j.add("height_m", in.height);
    j.add("area_over_perimeter_m", a_over_p);
    j.add("wall_friction", in.mu_w);
    j.add("weight_N", weight_sum_ / static_cast<double>(samples_));
    j.add("floor_support_N", floor_sum_ / static_cast<double>(samples_));
    j.add("wall_friction_support_N", friction_sum_ / static_cast<double>(samples_));
    j.add("support_over_weight", (floor_sum_ + friction_sum_) / weight_sum_);
    // Newton for the grains together: support - weight = sum m a (upwards); exact at any instant.
    j.add("grain_momentum_rate_N", momentum_sum_ / static_cast<double>(samples_));
    j.add("support_minus_momentum_rate_over_weight",
          (floor_sum_ + friction_sum_ - momentum_sum_) / weight_sum_);
    j.add("floor_stress_Pa", floor_sum_ / static_cast<double>(samples_) / section);
    summary_.add("janssen", j);
    out_.write("janssen.csv", janssen_table(fit));
  });
}

template <int D>
void AnalysisParts<D>::finish_fields() {
  if (!fields_) return;
  average(*fields_);
  summary_.add("fields", field_summary(*fields_));
  if (fields_->spec.layout == FieldLayout::Grid) {
    const std::string path = out_.path("fields.vti");
    out_.write("fields.csv", field_table(*fields_));
    write_fields_vti(*fields_, path, parse_vtk_encoding(opt_.vtk_format, "option --vtk-format"));
  } else {
    out_.write("fields_line.csv", field_table(*fields_));
  }
}

template <int D>
void AnalysisParts<D>::finish_per_grain() {
  if (!last_) return;
  const Sample<D>& s = *last_;
  if (wants("polarization")) out_.write("contacts.csv", contact_table(s));
  if (wants("coordination")) {
    const Coordination c = coordination(s);
    summary_.add("coordination", summary(c));
    out_.write("coordination.csv", table(c));
  }
  if (!wants("particle-stress") && !wants("percolation")) return;
  const double nu = nu_sum_ / static_cast<double>(samples_);
  const ParticleStresses<D> ps = particle_stresses(s, nu);
  if (wants("particle-stress"))
    attempt(summary_, "particle_stress", [&] {
      out_.write("particle_stress.csv", particle_stress_table(s, ps));
      double p_ref = 0.0;
      out_.write("pressure_pdf.csv", pressure_pdf(pressures_, opt_.bins, p_ref));
      Summary p;
      p.add("solid_fraction", nu);
      p.add("mean_abs_pressure_Pa", p_ref);
      std::size_t positive = 0, negative = 0;
      for (double v : pressures_) (v > 0.0 ? positive : negative) += v != 0.0 ? 1 : 0;
      p.add("positive_fraction",
            static_cast<double>(positive) / static_cast<double>(pressures_.size()));
      p.add("negative_fraction",
            static_cast<double>(negative) / static_cast<double>(pressures_.size()));
      summary_.add("particle_stress", p);
    });
  if (wants("percolation"))
    attempt(summary_, "percolation", [&] {
      const Percolation perc = percolation(s, ps.pressure);
      summary_.add("percolation", summary(perc));
      out_.write("percolation.csv", table(perc));
    });
}

template <int D>
void AnalysisParts<D>::finish_drag() {
  if (!drag_) return;
  const auto& [opt, result] = *drag_;
  out_.write("drag.csv", drag_table(result, opt));
  summary_.add("drag", drag_summary(result, opt));
}

template <int D>
void AnalysisParts<D>::finish_load_share() {
  if (load_shares_.empty()) return;
  out_.write("load_share.csv", load_share_table(load_shares_));
  summary_.add("load_share", load_share_summary(load_shares_));
}

template <int D>
void AnalysisParts<D>::finish_dissipation() {
  if (budgets_.empty()) return;
  out_.write("dissipation.csv", power_budget_table(budgets_));
  summary_.add("dissipation", power_budget_summary(budgets_));
}

#define SABLE_FINISH(D)                                \
  template void AnalysisParts<D>::finish_forces();     \
  template void AnalysisParts<D>::finish_stress();     \
  template void AnalysisParts<D>::finish_walls();      \
  template void AnalysisParts<D>::finish_wall_loads(); \
  template void AnalysisParts<D>::finish_fields();     \
  template void AnalysisParts<D>::finish_per_grain();  \
  template void AnalysisParts<D>::finish_janssen();    \
  template void AnalysisParts<D>::finish_drag();       \
  template void AnalysisParts<D>::finish_load_share(); \
  template void AnalysisParts<D>::finish_dissipation();
SABLE_FINISH(2)
SABLE_FINISH(3)
#undef SABLE_FINISH

}  // namespace sable
