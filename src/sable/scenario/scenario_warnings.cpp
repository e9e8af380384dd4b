// Choices a scenario may make on purpose but rarely does: printed once by `check` and `run`.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "sable/scenario/config.hpp"

namespace sable {
namespace {

const MaterialConfig* find_material(const ScenarioConfig& cfg, const std::string& name) {
  for (const auto& m : cfg.materials)
    if (m.material.name == name) return &m;
  return nullptr;
}

bool has_override(const ScenarioConfig& cfg, const std::string& a, const std::string& b) {
  return std::any_of(cfg.overrides.begin(), cfg.overrides.end(), [&](const auto& o) {
    return (o.a == a && o.b == b) || (o.a == b && o.b == a);
  });
}

// A rigid wall material usually omits friction and restitution (they read as properties of
// the grains), and then the mixing rules give its contacts friction min(0, mu) = 0 and
// restitution sqrt(1 e): rarely what was meant against frictional grains.
void rigid_wall_defaults(const ScenarioConfig& cfg, std::vector<std::string>& out) {
  std::set<std::pair<std::string, std::string>> seen;
  for (const auto& wall : cfg.walls) {
    const MaterialConfig* w = find_material(cfg, wall.material);
    if (!w || !w->material.rigid || (w->friction_given && w->restitution_given)) continue;
    for (const auto& block : cfg.grains) {
      const MaterialConfig* g = find_material(cfg, block.material);
      if (!g || g == w || has_override(cfg, w->material.name, g->material.name)) continue;
      const double mu = std::min(w->material.friction, g->material.friction);
      const double e = std::sqrt(w->material.restitution * g->material.restitution);
      const bool surprising = (!w->friction_given && g->material.friction > 0.0) ||
                              (!w->restitution_given && g->material.restitution < 1.0);
      if (!surprising || !seen.emplace(w->material.name, g->material.name).second) continue;
      out.push_back(fmt::format(
          "rigid wall material '{}' sets no {}, so its contacts with grains of '{}' get friction "
          "{:.4g} and restitution {:.4g} by the mixing rules (the smaller friction, the geometric "
          "mean of the restitutions); add a [[material_pair]] with materials = [\"{}\", \"{}\"] "
          "to choose them",
          w->material.name,
          !w->friction_given && !w->restitution_given ? "friction or restitution"
          : !w->friction_given                        ? "friction"
                                                      : "restitution",
          g->material.name, mu, e, w->material.name, g->material.name));
    }
  }
}

}  // namespace

std::vector<std::string> scenario_warnings(const ScenarioConfig& cfg) {
  std::vector<std::string> out;
  rigid_wall_defaults(cfg, out);
  return out;
}

}  // namespace sable
