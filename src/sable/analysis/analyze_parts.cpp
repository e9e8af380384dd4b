#include "sable/analysis/analyze_parts.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "sable/analysis/forces.hpp"
#include "sable/analysis/percolation.hpp"
#include "sable/core/error.hpp"

namespace sable {

namespace {

template <int D>
void append(ContactSet<D>& dst, const ContactSet<D>& src, const std::vector<bool>& mask) {
  for (std::size_t k = 0; k < src.size(); ++k)
    if (mask[k])
      dst.push(src.i[k], src.j[k], src.is_wall(k), src.n[k], src.force[k], src.arm_i[k],
               src.arm_j[k], src.branch[k], src.overlap[k], src.friction[k], src.motion(k));
}

// A polyhedron's diameter here is its volume-equivalent sphere's (its `radius` is its bounding
// sphere's, which a flat or long grain far exceeds).
template <int D>
double mean_diameter(const Sample<D>& s) {
  constexpr double pi = 3.14159265358979323846;
  double d = 0.0;
  for (std::size_t k = 0; k < s.size(); ++k)
    d += s.polyhedra ? std::cbrt(6.0 * s.volume[k] / pi) : 2.0 * s.radius[k];
  return s.size() ? d / static_cast<double>(s.size()) : 0.0;
}

template <int D>
FieldSpec<D> field_spec(const AnalyzeOptions& opt, const Sample<D>& s,
                        const std::optional<Region<D>>& region) {
  FieldSpec<D> spec;
  spec.kernel = parse_cg_kernel(opt.kernel, "--kernel");
  spec.width = opt.width > 0.0 ? opt.width : 2.0 * mean_diameter(s);  // Guillard: R = 2d
  if (region) spec.box = *region;
  if (!opt.line.empty()) {
    spec.layout = FieldLayout::Line;
    const auto colon1 = opt.line.find(':'), colon2 = opt.line.rfind(':');
    if (colon1 == std::string::npos || colon1 == colon2)
      throw InputError(fmt::format("option --line: '{}' is not 'from:to:points'", clip(opt.line)));
    std::vector<double> a, b;
    for (auto [text, out] : {std::pair{opt.line.substr(0, colon1), &a},
                             std::pair{opt.line.substr(colon1 + 1, colon2 - colon1 - 1), &b}}) {
      std::size_t pos = 0;
      while (pos <= text.size()) {
        const std::size_t c = std::min(text.find(',', pos), text.size());
        try {
          out->push_back(std::stod(text.substr(pos, c - pos)));
        } catch (const std::exception&) {
          throw InputError(fmt::format("option --line: '{}' has a non-number", clip(opt.line)));
        }
        pos = c + 1;
      }
    }
    if (a.size() != static_cast<std::size_t>(D) || b.size() != static_cast<std::size_t>(D))
      throw InputError(fmt::format("option --line: '{}' needs two {}D points", clip(opt.line), D));
    for (int d = 0; d < D; ++d) {
      spec.from[d] = a[static_cast<std::size_t>(d)];
      spec.to[d] = b[static_cast<std::size_t>(d)];
    }
    try {
      spec.points = std::stoi(opt.line.substr(colon2 + 1));
    } catch (const std::exception&) {
      throw InputError(
          fmt::format("option --line: '{}' ends without a point count", clip(opt.line)));
    }
  } else if (!opt.grid.empty()) {
    std::size_t pos = 0;
    for (int d = 0; d < D; ++d) {
      const std::size_t x = std::min(opt.grid.find('x', pos), opt.grid.size());
      try {
        spec.cells[static_cast<std::size_t>(d)] = std::stoi(opt.grid.substr(pos, x - pos));
      } catch (const std::exception&) {
        throw InputError(fmt::format("option --grid: '{}' is not {} counts like 10x10{}",
                                     clip(opt.grid), D, D == 3 ? "x40" : ""));
      }
      pos = x + 1;
    }
    if (pos <= opt.grid.size())
      throw InputError(
          fmt::format("option --grid: '{}' has more than {} counts", clip(opt.grid), D));
  } else {
    spec.spacing = opt.spacing > 0.0 ? opt.spacing : spec.width;
  }
  validate(spec);
  return spec;
}

}  // namespace

Table pressure_pdf(const std::vector<double>& p, int bins, double& p_ref) {
  double sum = 0.0, top = 0.0;
  std::size_t n = 0;
  for (double v : p)
    if (v != 0.0) {
      sum += std::abs(v);
      top = std::max(top, std::abs(v));
      ++n;
    }
  if (n == 0) throw InputError("no grain carries a non-zero pressure: no pressure PDF");
  p_ref = sum / static_cast<double>(n);
  const double lo = -top / p_ref, width = 2.0 * top / p_ref / bins;
  std::vector<double> x(static_cast<std::size_t>(bins)), count(x.size(), 0.0), pdf(x.size());
  for (double v : p) {
    const auto b = static_cast<std::size_t>(
        std::clamp(std::floor((v / p_ref - lo) / width), 0.0, static_cast<double>(bins - 1)));
    count[b] += 1.0;
  }
  for (std::size_t b = 0; b < x.size(); ++b) {
    x[b] = lo + (static_cast<double>(b) + 0.5) * width;
    pdf[b] = count[b] / (static_cast<double>(p.size()) * width);
  }
  Table t;
  t.add("p_over_mean_abs", x);
  t.add("count", count);
  t.add("pdf", pdf);
  return t;
}

template <int D>
AnalysisParts<D>::AnalysisParts(const AnalyzeOptions& opt, const ResultWriter& out,
                                std::optional<Region<D>> region)
    : opt_(opt), out_(out), region_(region) {
  series_names_ = {"time_s", "step"};
  if (wants("coordination"))
    series_names_.insert(series_names_.end(),
                         {"z", "z_compressive", "z_tensile", "rattler_fraction"});
  if (wants("stress"))
    series_names_.insert(series_names_.end(), {"mean_stress_pressure_Pa", "mean_stress_asymmetry",
                                               "contact_part_asymmetry", "love_weber_pressure_Pa"});
}

template <int D>
Region<D> AnalysisParts<D>::region_of(const Sample<D>& s) const {
  return region_ ? *region_ : grain_bounds(s);
}

template <int D>
void AnalysisParts<D>::add(const Sample<D>& s) {
  if (samples_ == 0) {
    for (const auto& w : s.walls)
      if (opt_.walls.empty() || std::count(opt_.walls.begin(), opt_.walls.end(), w.name))
        wall_names_.push_back(w.name);
    for (const auto& name : opt_.walls)
      if (std::find(wall_names_.begin(), wall_names_.end(), name) == wall_names_.end())
        throw InputError(
            fmt::format("option --walls: {} has no wall named '{}'", s.source, clip(name)));
    if (wants("walls"))  // the per-snapshot series: each wall's force, then its torque
      for (const auto& name : wall_names_) {
        for (const char* ax : {"x", "y", "z"})
          if (D == 3 || ax[0] != 'z')
            series_names_.push_back(fmt::format("wall_{}_f{}_N", name, ax));
        for (const char* ax : {"x", "y", "z"})
          if (D == 3 || ax[0] == 'z')
            series_names_.push_back(fmt::format("wall_{}_t{}_Nm", name, ax));
      }
  }
  std::vector<double> row{s.time, static_cast<double>(s.step)};
  add_contacts(s);
  if (wants("coordination")) {
    const Coordination c = coordination(s);
    row.insert(row.end(), {c.z, c.z_compressive, c.z_tensile, c.rattler_fraction});
  }
  add_stress(s, row);
  add_walls(s);
  add_wall_loads(s, row);
  add_fields(s);
  if (wants("load-share")) load_shares_.push_back(load_share(s, opt_.level));
  series_.push_back(row);
  ++samples_;
  last_ = s;
}

template <int D>
void AnalysisParts<D>::skip_refused(const Sample<D>& s) {
  if (!s.polyhedra) return;
  std::vector<std::pair<std::string, std::string>> refused{{"dissipation", kDissipationPolyhedra}};
  if (opt_.kernel == "sphere") refused.emplace_back("fields", kSphereKernelPolyhedra);
  for (const auto& [name, why] : refused) {
    if (!analysis_wanted(opt_, name.c_str()) || skipped_.count(name)) continue;
    if (!opt_.only.empty()) refuse_polyhedra(s, name, why);
    skipped_[name] = why;
    summary_.add("skipped_" + name, "polyhedral grains: " + why);
    if (opt_.log) *opt_.log << fmt::format("{}: skipped for polyhedral grains: {}\n", name, why);
  }
}

template <int D>
void AnalysisParts<D>::add_lab(const Sample<D>& s) {
  skip_refused(s);
  if (wants("dissipation")) budgets_.push_back(power_budget(s));
}

template <int D>
void AnalysisParts<D>::add_contacts(const Sample<D>& s) {
  const auto& c = s.contacts;
  append(all_, c, std::vector<bool>(c.size(), true));
  append(bulk_, c, region_ ? select_region(c, s.x, *region_) : select_bulk(c));
  append(walls_, c, select_walls(c));
  for (std::uint32_t w = 0; w < s.walls.size(); ++w)
    if (std::count(wall_names_.begin(), wall_names_.end(), s.walls[w].name))
      append(by_wall_[s.walls[w].name], c, select_wall(c, w));
}

template <int D>
void AnalysisParts<D>::add_stress(const Sample<D>& s, std::vector<double>& row) {
  const Region<D> region = region_of(s);
  if (wants("stress")) {
    const MeanStress<D> m = mean_stress(s, region);
    const Tensor<D> lw = love_weber(s, region);
    mean_sum_.contact += m.contact;
    mean_sum_.gravity += m.gravity;
    mean_sum_.inertia += m.inertia;
    mean_sum_.volume += m.volume;
    mean_sum_.grains += m.grains;
    love_weber_sum_ += lw;
    row.insert(row.end(), {m.total().trace() / D, asymmetry<D>(m.total()), asymmetry<D>(m.contact),
                           lw.trace() / D});
  }
  if (wants("particle-stress") || wants("percolation")) {
    const ParticleStresses<D> ps = particle_stresses(
        s, opt_.solid_fraction > 0.0 ? opt_.solid_fraction : solid_fraction(s, region));
    pressures_.insert(pressures_.end(), ps.pressure.begin(), ps.pressure.end());
    nu_sum_ += ps.solid_fraction;
  }
}

template <int D>
void AnalysisParts<D>::add_walls(const Sample<D>& s) {
  if (!wants("walls") && !wants("janssen")) return;
  // Global balance of a silo: the floors' support plus the side walls' friction carry the
  // weight (floors: plane walls perpendicular to the up axis).
  const auto up = s.gravity.squaredNorm() > 0.0
                      ? typename Space<D>::Vec(-s.gravity.normalized())
                      : typename Space<D>::Vec(Space<D>::Vec::Unit(D - 1));
  weight_sum_ += s.total_mass() * s.gravity.norm();
  for (std::size_t g = 0; g < s.size(); ++g)
    if (!s.fixed[g]) momentum_sum_ += s.mass[g] * s.a[g].dot(up);
  for (std::size_t w = 0; w < s.walls.size(); ++w) {
    if (is_side_wall(s, w) || s.walls[w].mesh()) continue;  // a mesh is no floor either
    for (int d = 0; d < D; ++d) floor_sum_ -= s.walls[w].force[static_cast<std::size_t>(d)] * up[d];
  }
  for (std::size_t w = 0; w < s.walls.size(); ++w) {
    const std::string& name = s.walls[w].name;
    if (!std::count(wall_names_.begin(), wall_names_.end(), name)) continue;
    if (s.walls[w].mesh()) continue;  // no height profile: its loads only (add_wall_loads)
    // By default only side walls get a height profile; a named floor is an error.
    if (opt_.walls.empty() && !is_side_wall(s, w)) continue;
    WallProfileOptions o;
    o.bin = opt_.wall_bin;
    auto fixed = profile_bins_.find(name);
    if (fixed != profile_bins_.end()) o = fixed->second;
    const WallProfile p = wall_profile(s, name, o);
    if (fixed == profile_bins_.end()) {
      // Later snapshots use the first one's bins so that the profiles can be averaged.
      o.count = p.height.size();
      o.bin = p.bin;
      o.top = p.top;
      o.bottom = p.height.empty() ? 0.0 : p.height.front() - 0.5 * p.bin;
      o.width = p.width;
      profile_bins_[name] = o;
      profiles_[name] = p;
      friction_sum_ += p.total_shear;
    } else {
      accumulate(profiles_[name], p);
      friction_sum_ += p.total_shear;
    }
  }
}

// Each selected wall's force and torque: summed for the summary, and one row of the series
// (NaN for a wall this snapshot lacks).
template <int D>
void AnalysisParts<D>::add_wall_loads(const Sample<D>& s, std::vector<double>& row) {
  if (!wants("walls")) return;
  for (const auto& name : wall_names_) {
    const auto it = std::find_if(s.walls.begin(), s.walls.end(),
                                 [&](const SampleWall& w) { return w.name == name; });
    if (it == s.walls.end()) {
      row.insert(row.end(), D == 3 ? 6 : 3, std::nan(""));
      continue;
    }
    WallLoad& load = loads_[name];
    load.type = it->type;
    load.pivot = it->pivot;
    for (std::size_t d = 0; d < 3; ++d) {
      load.force[d] += it->force[d];
      load.torque[d] += it->torque[d];
    }
    for (std::size_t d = 0; d < static_cast<std::size_t>(D); ++d) row.push_back(it->force[d]);
    if (D == 3)
      row.insert(row.end(), it->torque.begin(), it->torque.end());
    else
      row.push_back(it->torque[2]);
  }
}

template <int D>
void AnalysisParts<D>::add_fields(const Sample<D>& s) {
  if (!wants("fields")) return;
  if (!field_spec_) {
    field_spec_ = field_spec(opt_, s, region_);
    if (field_spec_->layout == FieldLayout::Grid && !field_spec_->box.bounded()) {
      // Fix the box on the first snapshot, so every snapshot is averaged on the same nodes.
      const Region<D> b = grain_bounds(s);
      for (int d = 0; d < D; ++d) {
        if (field_spec_->box.lo[d] < -1e299) field_spec_->box.lo[d] = b.lo[d];
        if (field_spec_->box.hi[d] > 1e299) field_spec_->box.hi[d] = b.hi[d];
      }
    }
  }
  const Fields<D> f = coarse_grain(s, *field_spec_);
  if (!fields_)
    fields_ = f;
  else
    accumulate(*fields_, f);
}

template <int D>
void AnalysisParts<D>::finish() {
  summary_.add("inputs", static_cast<std::int64_t>(opt_.snapshots.size()));
  summary_.add("first_input", opt_.snapshots.front());
  summary_.add("dimension", D);
  summary_.add("frame", opt_.frame.empty()
                            ? std::string("lab")
                            : fmt::format("rotating {} at {} rad/s", opt_.frame, opt_.omega));
  finish_forces();
  finish_stress();
  finish_walls();
  finish_wall_loads();
  finish_fields();
  finish_per_grain();
  finish_janssen();
  finish_drag();
  finish_load_share();
  finish_dissipation();
  if (samples_ > 1) {
    Table t;
    for (std::size_t c = 0; c < series_.front().size(); ++c) {
      std::vector<double> col;
      for (const auto& r : series_) col.push_back(r[c]);
      t.add(series_names_.size() > c ? series_names_[c] : fmt::format("c{}", c), col);
    }
    out_.write("series.csv", t);
  }
  out_.write("summary.json", summary_);
}

// Members defined here; the finish_* ones are instantiated in analyze_finish.cpp.
#define SABLE_PARTS(D)                                                                 \
  template AnalysisParts<D>::AnalysisParts(const AnalyzeOptions&, const ResultWriter&, \
                                           std::optional<Region<D>>);                  \
  template void AnalysisParts<D>::add(const Sample<D>&);                               \
  template void AnalysisParts<D>::add_lab(const Sample<D>&);                           \
  template void AnalysisParts<D>::finish();
SABLE_PARTS(2)
SABLE_PARTS(3)
#undef SABLE_PARTS

}  // namespace sable
