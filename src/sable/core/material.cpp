#include "sable/core/material.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace sable {

MaterialIndex MaterialTable::add(Material m) {
  materials_.push_back(std::move(m));
  return static_cast<MaterialIndex>(materials_.size() - 1);
}

void MaterialTable::add_override(const PairOverride& o) {
  overrides_.push_back(o);
}

std::optional<MaterialIndex> MaterialTable::find(const std::string& name) const {
  for (std::size_t i = 0; i < materials_.size(); ++i)
    if (materials_[i].name == name) return static_cast<MaterialIndex>(i);
  return std::nullopt;
}

double MaterialTable::beta_from_restitution(double e) {
  if (e >= 1.0) return 0.0;
  if (e <= 0.0) return -1.0;  // the limit e -> 0: critical damping
  const double l = std::log(e);
  return l / std::sqrt(l * l + std::numbers::pi * std::numbers::pi);
}

PairParams MaterialTable::mix(const Material& a, const Material& b) {
  // Compliances add (LIGGGHTS 3.8 / the drag paper's Table I); a rigid body adds none.
  auto normal_compliance = [](const Material& m) {
    return m.rigid ? 0.0 : (1.0 - m.poisson * m.poisson) / m.young;
  };
  auto shear_compliance = [](const Material& m) {
    return m.rigid ? 0.0 : 2.0 * (2.0 - m.poisson) * (1.0 + m.poisson) / m.young;
  };
  PairParams p;
  p.y_star = 1.0 / (normal_compliance(a) + normal_compliance(b));
  p.g_star = 1.0 / (shear_compliance(a) + shear_compliance(b));
  // Mixing rule for restitution and friction when no override is given: the geometric mean
  // for restitution is symmetric and equals the common value for equal materials; friction
  // takes the smaller (weaker surface) of the two, the usual conservative choice.
  p.restitution = std::sqrt(a.restitution * b.restitution);
  p.friction = std::min(a.friction, b.friction);
  p.rolling_friction = std::min(a.rolling_friction, b.rolling_friction);
  p.beta = beta_from_restitution(p.restitution);
  return p;
}

void MaterialTable::finalize() {
  const std::size_t n = materials_.size();
  pairs_.assign(n * n, PairParams{});
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j) pairs_[i * n + j] = mix(materials_[i], materials_[j]);
  for (const auto& o : overrides_) {
    for (auto [i, j] : {std::pair{o.a, o.b}, std::pair{o.b, o.a}}) {
      PairParams& p = pairs_[static_cast<std::size_t>(i) * n + j];
      if (o.friction) p.friction = *o.friction;
      if (o.rolling_friction) p.rolling_friction = *o.rolling_friction;
      if (o.restitution) {
        p.restitution = *o.restitution;
        p.beta = beta_from_restitution(p.restitution);
      }
      if (o.young_star) p.y_star = *o.young_star;
    }
  }
  for (PairParams& p : pairs_)
    p.st_over_sn_sqrt = p.y_star > 0.0 ? std::sqrt(4.0 * p.g_star / p.y_star) : 0.0;
}

}  // namespace sable
