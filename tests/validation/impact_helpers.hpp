// Shared helpers for the validation tests: build small worlds, run one impact and record what
// the benchmarks compare (contact start and end, maximum overlap and force, rebound velocity),
// and a few closed-form results of classical contact mechanics used by several tests.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "sable/core/material.hpp"
#include "sable/dem/dem_solver.hpp"
#include "sable/world/world.hpp"

namespace sable::validation {

// ---------------------------------------------------------------------------------------------
// Closed-form Hertz impact (elastic, frictionless, no gravity), e.g. Johnson (1985) "Contact
// Mechanics" section 11.4, as quoted by Chung & Ooi (2011). F = 4/3 Y* sqrt(R*) delta^(3/2).

// Maximum overlap for approach speed v: (15 m* v^2 / (16 Y* sqrt(R*)))^(2/5).
inline double hertz_max_overlap(double m_eff, double r_eff, double y_star, double v) {
  return std::pow(15.0 * m_eff * v * v / (16.0 * y_star * std::sqrt(r_eff)), 0.4);
}
// Contact time 2.868 (m*^2 / (R* Y*^2 v))^(1/5). (The exact coefficient is
// 2 (15/16)^(2/5) * integral_0^1 dx / sqrt(1 - x^(5/2)) = 2.8682.)
inline double hertz_contact_time(double m_eff, double r_eff, double y_star, double v) {
  return 2.868 * std::pow(m_eff * m_eff / (r_eff * y_star * y_star * v), 0.2);
}
inline double hertz_force(double r_eff, double y_star, double delta) {
  return 4.0 / 3.0 * y_star * std::sqrt(r_eff) * std::pow(delta, 1.5);
}
// Elastic energy stored in a Hertz contact: integral of the force, 8/15 Y* sqrt(R*) d^(5/2).
inline double hertz_energy(double r_eff, double y_star, double delta) {
  return delta > 0.0 ? 8.0 / 15.0 * y_star * std::sqrt(r_eff) * std::pow(delta, 2.5) : 0.0;
}

// ---------------------------------------------------------------------------------------------
// Small-world construction.

inline Material make_material(const char* name, double density, double young, double poisson,
                              double restitution, double friction, bool rigid = false) {
  Material m;
  m.name = name;
  m.density = density;
  m.young = young;
  m.poisson = poisson;
  m.restitution = restitution;
  m.friction = friction;
  m.rigid = rigid;
  return m;
}

// An infinite plane through `point` with unit normal `normal` pointing into the grains.
template <int D>
Wall<D> make_plane(const typename Space<D>::Vec& point, const typename Space<D>::Vec& normal,
                   MaterialIndex material) {
  Wall<D> wall;
  wall.name = "plane";
  wall.point = point;
  wall.set_plane(normal.normalized());
  wall.material = material;
  return wall;
}

// Neighbour-list settings covering a box around the grains.
template <int D>
void set_domain(World<D>& w, double lo, double hi, double skin) {
  w.neighbors.skin = skin;
  w.neighbors.domain_lo = Space<D>::Vec::Constant(lo);
  w.neighbors.domain_hi = Space<D>::Vec::Constant(hi);
}

// ---------------------------------------------------------------------------------------------
// One impact, observed step by step.

struct ImpactResult {
  bool touched = false;  // a contact happened
  bool ended = false;    // ... and ended (the grains separated again)
  double t_start = 0.0;  // first touch, interpolated between steps on the gap (s)
  double t_end = 0.0;    // separation, same interpolation (s)
  double contact_time = 0.0;
  double max_overlap = 0.0;  // over the sampled steps (m)
  double max_force = 0.0;    // normal component of the contact force on grain 0 (N)
  double min_force = std::numeric_limits<double>::infinity();  // while overlapping (N)
  double vn_before = 0.0;    // normal relative velocity before (negative: approaching)
  double vn_after = 0.0;     // normal relative velocity after (positive: separating)
  double restitution = 0.0;  // -vn_after / vn_before
  std::size_t steps = 0;
  std::vector<double> time, overlap, force;  // the history, when requested
};

// Run the solver until the contact observed by `gap` (signed distance; < 0 when overlapping)
// has ended and `extra_steps` more steps are done, or `max_steps` is reached. `normal` gives
// the contact normal pointing towards grain 0, `vrel` grain 0's velocity relative to its
// partner, and `force_n` the normal contact force on grain 0 (positive: repulsive).
template <int D, class Gap, class Normal, class VRel, class ForceN>
ImpactResult observe_impact(World<D>& w, Gap gap, Normal normal, VRel vrel, ForceN force_n,
                            std::size_t max_steps, bool keep_history, std::size_t extra_steps = 2) {
  DemSolver<D> solver(w);
  solver.initialize();
  ImpactResult r;
  r.vn_before = vrel().dot(normal());
  double g_prev = gap();
  double t_prev = w.time;
  std::size_t after_end = 0;
  for (std::size_t k = 0; k < max_steps; ++k) {
    solver.step();
    ++r.steps;
    const double g = gap();
    const double t = w.time;
    if (!r.touched && g < 0.0) {
      r.touched = true;
      r.t_start = t_prev + (t - t_prev) * g_prev / (g_prev - g);
    }
    if (r.touched && !r.ended) {
      if (g < 0.0) {
        const double f = force_n();
        r.max_overlap = std::max(r.max_overlap, -g);
        r.max_force = std::max(r.max_force, f);
        r.min_force = std::min(r.min_force, f);
        if (keep_history) {
          r.time.push_back(t);
          r.overlap.push_back(-g);
          r.force.push_back(f);
        }
      } else {
        r.ended = true;
        r.t_end = t_prev + (t - t_prev) * g_prev / (g_prev - g);
        r.contact_time = r.t_end - r.t_start;
      }
    }
    if (r.ended && ++after_end >= extra_steps) break;
    g_prev = g;
    t_prev = t;
  }
  r.vn_after = vrel().dot(normal());
  r.restitution = r.vn_before != 0.0 ? -r.vn_after / r.vn_before : 0.0;
  return r;
}

// Grains 0 and 1 of `w` colliding (no walls involved).
template <int D>
ImpactResult run_pair_impact(World<D>& w, std::size_t max_steps, bool keep_history = false) {
  auto& p = w.particles;
  auto gap = [&] { return (p.x[0] - p.x[1]).norm() - p.radius[0] - p.radius[1]; };
  auto normal = [&]() -> typename Space<D>::Vec { return (p.x[0] - p.x[1]).normalized(); };
  auto vrel = [&]() -> typename Space<D>::Vec { return p.v[0] - p.v[1]; };
  // p.f holds contact forces only (gravity enters the kicks as an acceleration).
  auto force_n = [&] { return p.f[0].dot(normal()); };
  return observe_impact(w, gap, normal, vrel, force_n, max_steps, keep_history);
}

// Grain 0 of `w` hitting the plane wall `wall_index` (no other grains).
template <int D>
ImpactResult run_wall_impact(World<D>& w, std::size_t max_steps, std::size_t wall_index = 0,
                             bool keep_history = false) {
  auto& p = w.particles;
  auto gap = [&] {
    typename Space<D>::Vec n;
    return w.walls[wall_index].distance(p.x[0], n) - p.radius[0];
  };
  auto normal = [&]() -> typename Space<D>::Vec {
    typename Space<D>::Vec n;
    w.walls[wall_index].distance(p.x[0], n);
    return n;
  };
  auto vrel = [&]() -> typename Space<D>::Vec { return p.v[0] - w.walls[wall_index].velocity; };
  auto force_n = [&] { return p.f[0].dot(normal()); };
  return observe_impact(w, gap, normal, vrel, force_n, max_steps, keep_history);
}

// Head-on impact of two identical grains along x, each approaching at `speed`, starting a gap
// of `gap0` apart; no gravity, no walls. Sets the model fields the caller left alone.
template <int D>
void setup_pair_impact(World<D>& w, const Material& mat, double radius, double speed, double gap0,
                       double dt) {
  using Vec = typename Space<D>::Vec;
  const MaterialIndex mi = w.materials.add(mat);
  w.materials.finalize();
  Vec x0 = Vec::Zero(), x1 = Vec::Zero();
  x0.x() = -(radius + 0.5 * gap0);
  x1.x() = radius + 0.5 * gap0;
  w.particles.add(x0, radius, mat.density, mi, 1.0);
  w.particles.add(x1, radius, mat.density, mi, 1.0);
  w.particles.v[0].x() = speed;
  w.particles.v[1].x() = -speed;
  w.gravity.setZero();
  w.dt = dt;
  set_domain(w, -4.0 * radius, 4.0 * radius, 0.5 * radius);
}

// One grain of `mat` starting `gap0` above a plane z = 0 (y = 0 in 2D) of `wall_mat`, moving
// with velocity `v` (its normal component must point into the plane); no gravity.
template <int D>
void setup_wall_impact(World<D>& w, const Material& mat, const Material& wall_mat, double radius,
                       const typename Space<D>::Vec& v, double gap0, double dt) {
  using Vec = typename Space<D>::Vec;
  const MaterialIndex mi = w.materials.add(mat);
  const MaterialIndex wi = w.materials.add(wall_mat);
  w.materials.finalize();
  Vec up = Vec::Zero();
  up[D - 1] = 1.0;
  w.walls.push_back(make_plane<D>(Vec::Zero(), up, wi));
  w.particles.add(Vec((radius + gap0) * up), radius, mat.density, mi, 1.0);
  w.particles.v[0] = v;
  w.gravity.setZero();
  w.dt = dt;
  set_domain(w, -4.0 * radius, 4.0 * radius, 0.5 * radius);
}

// A number for RecordProperty, with 7 significant digits whatever its size.
inline std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.7g", v);
  return buf;
}

// Least-squares slope of y(t).
inline double fit_slope(const std::vector<double>& t, const std::vector<double>& y) {
  const double n = static_cast<double>(t.size());
  double st = 0.0, sy = 0.0, stt = 0.0, sty = 0.0;
  for (std::size_t k = 0; k < t.size(); ++k) {
    st += t[k];
    sy += y[k];
    stt += t[k] * t[k];
    sty += t[k] * y[k];
  }
  return (n * sty - st * sy) / (n * stt - st * st);
}

}  // namespace sable::validation
