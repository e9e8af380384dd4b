#include "sable/loading/servo.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "sable/core/error.hpp"
#include "sable/core/exact_sum.hpp"

namespace sable {

namespace {

// The sample's extent along `axis`: between the facing plane walls there, else the domain.
template <int D>
double extent(const World<D>& w, int axis) {
  double lo = w.neighbors.domain_lo[axis], hi = w.neighbors.domain_hi[axis];
  bool has_lo = false, has_hi = false;
  for (const auto& wall : w.walls) {
    if (wall.facing_axis() != axis) continue;
    if (wall.normal()[axis] > 0.0) {
      lo = has_lo ? std::max(lo, wall.point[axis]) : wall.point[axis];
      has_lo = true;
    } else {
      hi = has_hi ? std::min(hi, wall.point[axis]) : wall.point[axis];
      has_hi = true;
    }
  }
  return std::max(hi - lo, 0.0);
}

}  // namespace

template <int D>
double wall_area(const World<D>& w, std::size_t k) {
  const Wall<D>& wall = w.walls[k];
  const int axis = wall.facing_axis();
  if (axis < 0)
    throw InputError(fmt::format(
        "wall '{}': stress control needs a plane wall facing a coordinate axis", clip(wall.name)));
  double area = D == 2 ? w.thickness : 1.0;
  for (int d = 0; d < D; ++d)
    if (d != axis) area *= extent(w, d);
  return area;
}

template <int D>
double wall_normal_stress(const World<D>& w, std::size_t k) {
  return -w.walls[k].force.dot(w.walls[k].normal()) / wall_area(w, k);
}

template <int D>
void servo_walls(World<D>& w, const std::vector<ServoTarget>& targets, const ServoSettings& s,
                 const Domain<D>* domain) {
  double gain = s.gain;
  if (gain <= 0.0) {
    double top = 0.0;
    for (const auto& t : targets) top = std::max(top, t.stress);
    if (top <= 0.0) top = s.zero_target_scale;
    if (top <= 0.0 && !targets.empty())
      throw InputError(
          "stress-controlled walls: every target is 0 Pa; set a gain (servo_gain) or the stress "
          "scale a zero target refers to (stress_scale)");
    gain = top > 0.0 ? s.max_velocity / top : 0.0;
  }
  std::vector<char> targeted(w.walls.size(), 0);
  for (const auto& t : targets) targeted[t.wall] = 1;
  std::vector<ExactSum> response(2 * w.walls.size());
  add_wall_responses(w, response.data(), [&](std::size_t k) { return targeted[k] != 0; });
  if (domain) domain->sum(response.data(), static_cast<int>(response.size()));
  for (const auto& t : targets) {
    const double area = wall_area(w, t.wall);
    const double error = -w.walls[t.wall].force.dot(w.walls[t.wall].normal()) / area - t.stress;
    const double resist = response[2 * t.wall].value() * w.dt + response[2 * t.wall + 1].value();
    const double g = resist > 0.0 ? std::min(gain, 0.5 * area / resist) : gain;
    const double speed = std::clamp(g * error, -s.max_velocity, s.max_velocity);
    w.walls[t.wall].velocity = -speed * w.walls[t.wall].normal();
  }
}

template <int D>
std::vector<WallBody> wall_bodies(const World<D>& w, const std::vector<ServoTarget>& targets,
                                  const ServoSettings& s) {
  constexpr double kStepsPerDiameter = 10.0;  // see the mass rule in servo.hpp
  const auto& p = w.particles;
  ExactSum grain_sum, diameters;  // exact: the same bits for any order of the grains
  std::size_t movable = 0;
  for (std::size_t k = 0; k < p.size(); ++k) {
    if (p.fixed(k)) continue;
    grain_sum.add(p.mass[k]);
    diameters.add(2.0 * p.radius[k]);
    ++movable;
  }
  const double grains = grain_sum.value();
  const double d = movable > 0 ? diameters.value() / static_cast<double>(movable) : 0.0;
  std::vector<WallBody> out;
  out.reserve(targets.size());
  for (const auto& t : targets) {
    const double force = t.stress * wall_area(w, t.wall);
    const double resolved =
        d > 0.0 ? 0.5 * kStepsPerDiameter * kStepsPerDiameter * w.dt * w.dt * force / d : 0.0;
    const double mass = s.wall_mass > 0.0 ? s.wall_mass : std::max(grains, resolved);
    if (!(mass > 0.0))
      throw InputError(fmt::format(
          "wall '{}': no grains and no force to set its mass from; give servo_wall_mass",
          clip(w.walls[t.wall].name)));
    out.push_back({t.wall, force, mass, s.max_velocity});
  }
  return out;
}

template <int D>
double servo_error(const World<D>& w, const std::vector<ServoTarget>& targets,
                   double zero_target_scale) {
  double worst = 0.0;
  for (const auto& t : targets) {
    const double scale = t.stress > 0.0 ? t.stress : zero_target_scale;
    if (scale <= 0.0)
      throw InputError(fmt::format(
          "wall '{}': a 0 Pa target needs a stress scale (stress_scale) to measure its error",
          clip(w.walls[t.wall].name)));
    worst = std::max(worst, std::abs(wall_normal_stress(w, t.wall) - t.stress) / scale);
  }
  return worst;
}

#define SABLE_SERVO(D)                                                                         \
  template double wall_area(const World<D>&, std::size_t);                                     \
  template double wall_normal_stress(const World<D>&, std::size_t);                            \
  template void servo_walls(World<D>&, const std::vector<ServoTarget>&, const ServoSettings&,  \
                            const Domain<D>*);                                                 \
  template std::vector<WallBody> wall_bodies(const World<D>&, const std::vector<ServoTarget>&, \
                                             const ServoSettings&);                            \
  template double servo_error(const World<D>&, const std::vector<ServoTarget>&, double);
SABLE_SERVO(2)
SABLE_SERVO(3)
#undef SABLE_SERVO

}  // namespace sable
