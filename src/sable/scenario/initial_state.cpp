#include "sable/scenario/initial_state.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <string>
#include <vector>

#include "sable/collision/neighbor_list.hpp"
#include "sable/core/error.hpp"

namespace sable {
namespace {

constexpr std::size_t kListed = 5;  // offenders described in the message; the rest counted

template <int D>
std::string grain_text(const ParticleStore<D>& p, std::size_t k) {
  return fmt::format("grain id {} at ({:.6g})", p.id[k].index,
                     fmt::join(p.x[k].data(), p.x[k].data() + D, ", "));
}

// Collects offenders of one kind and throws once with the first few.
class Offenders {
 public:
  void add(std::string text) {
    ++count_;
    if (texts_.size() < kListed) texts_.push_back(std::move(text));
  }
  void throw_if_any(const std::string& file, const std::string& what,
                    const std::string& remedy) const {
    if (count_ == 0) return;
    std::string list;
    for (const auto& t : texts_) list += "\n  " + t;
    if (count_ > texts_.size()) list += fmt::format("\n  and {} more", count_ - texts_.size());
    throw InputError(fmt::format("{}: {} {}:{}\n{}", file, count_, what, list, remedy));
  }

 private:
  std::size_t count_ = 0;
  std::vector<std::string> texts_;
};

template <int D>
void check_walls(const ScenarioConfig& cfg, const World<D>& w) {
  const auto& p = w.particles;
  const double tol = cfg.sim.initial_overlap;
  Offenders behind, overlapping;
  for (std::size_t k = 0; k < p.size(); ++k) {
    if (p.fixed(k)) continue;
    for (const auto& wall : w.walls) {
      typename Space<D>::Vec n;
      const double d = wall.distance(p.x[k], n);
      if (d < 0.0)
        behind.add(fmt::format("{} is behind wall '{}': its centre lies {:.4g} m on the far side",
                               grain_text(p, k), clip(wall.name), -d));
      else if (p.radius[k] - d > tol * p.radius[k])
        overlapping.add(fmt::format("{} overlaps wall '{}' by {:.4g} m ({:.3g} of its radius)",
                                    grain_text(p, k), clip(wall.name), p.radius[k] - d,
                                    (p.radius[k] - d) / p.radius[k]));
    }
  }
  behind.throw_if_any(cfg.path, "grain centres lie behind a wall (outside the container)",
                      "move the grains (or the [[grains]] region) inside the walls, or check the "
                      "wall's normal: it points into the grains");
  overlapping.throw_if_any(
      cfg.path,
      fmt::format("grains start overlapping a wall by more than simulation.initial_overlap = {} "
                  "of their radius",
                  tol),
      "move them away from the wall, or raise simulation.initial_overlap for a deliberate "
      "overlap");
}

template <int D>
void check_pairs(const ScenarioConfig& cfg, const World<D>& w) {
  const auto& p = w.particles;
  if (p.size() < 2) return;
  NeighborList<D> nl;
  nl.skin = w.neighbors.skin;
  nl.domain_lo = w.neighbors.domain_lo;
  nl.domain_hi = w.neighbors.domain_hi;
  nl.build(p, {});
  const double tol = cfg.sim.initial_overlap;
  Offenders same, overlapping;
  for (std::size_t e = 0; e < nl.pairs.size(); ++e) {
    const std::uint32_t i = nl.pairs.i[e], j = nl.pairs.j[e];
    if (p.fixed(i) && p.fixed(j)) continue;
    const double dist = (p.x[j] - p.x[i]).norm();
    const double rmin = std::min(p.radius[i], p.radius[j]);
    const double overlap = p.radius[i] + p.radius[j] - dist;
    if (dist <= 1e-9 * rmin)
      same.add(fmt::format("{} and id {}", grain_text(p, i), p.id[j].index));
    else if (overlap > tol * rmin)
      overlapping.add(fmt::format("{} and {} by {:.4g} m ({:.3g} of the smaller radius)",
                                  grain_text(p, i), grain_text(p, j), overlap, overlap / rmin));
  }
  same.throw_if_any(cfg.path, "pairs of grains start at the same position",
                    "each grain needs its own place (is a [[grains]] block given twice?)");
  overlapping.throw_if_any(
      cfg.path,
      fmt::format("pairs of grains start overlapping by more than simulation.initial_overlap = {} "
                  "of the smaller radius",
                  tol),
      "separate them (a larger lattice spacing, a smaller radius), or raise "
      "simulation.initial_overlap for a deliberately overlapping packing");
}

}  // namespace

template <int D>
void check_initial_state(const ScenarioConfig& cfg, const World<D>& world) {
  check_walls(cfg, world);
  check_pairs(cfg, world);
}

template void check_initial_state<2>(const ScenarioConfig&, const World<2>&);
template void check_initial_state<3>(const ScenarioConfig&, const World<3>&);

}  // namespace sable
