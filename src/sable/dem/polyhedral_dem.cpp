#include "sable/dem/polyhedral_dem.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "sable/contact/contact_model.hpp"
#include "sable/contact/linear_law.hpp"
#include "sable/contact/registry.hpp"
#include "sable/core/error.hpp"
#include "sable/core/parallel.hpp"
#include "sable/core/rigid_rotation.hpp"
#include "sable/geometry/polyhedron_contact.hpp"
#include "sable/geometry/polyhedron_plane.hpp"
#include "sable/world/guards.hpp"

namespace sable {

namespace {

using Vec = Eigen::Vector3d;

// The manifold law of the header: the normal springs and dashpots of the points in overlap,
// one tangential spring at their centre of pressure. `velocity(x)`: the velocity of grain i's
// material point at x less its partner's. The spring `shear` is advanced as contact_force()
// advances a round contact's (turned into the tangent plane with its length kept, or only
// projected, as the model says; Coulomb-capped with no damping while sliding).
template <class Velocity>
PolyhedralDem::EntryForce manifold_force(const PolyhedronContact& c, const Vec& n,
                                         Velocity&& velocity, const PairParams& pp,
                                         const ContactModel& model, double m_eff, double dt,
                                         Vec& shear) {
  PolyhedralDem::EntryForce e;
  int points = 0;
  for (int t = 0; t < c.count; ++t) points += c.points[t].gap < 0.0 ? 1 : 0;
  if (points == 0) {
    shear.setZero();
    return e;
  }
  ContactModel parallel = model;  // the springs of the points in parallel
  parallel.kn *= points;
  parallel.kt *= points;
  const NormalCoeffs k = LinearNormal::coeffs(pp, parallel, 0.0, 0.0, m_eff);
  const double g_point = k.gn / points;  // the translational dashpot shared by the points
  double normal = 0.0;
  Vec centre = Vec::Zero(), deep_centre = Vec::Zero();
  double depth_sum = 0.0;
  for (int t = 0; t < c.count; ++t) {
    const double d = -c.points[t].gap;
    if (!(d > 0.0)) continue;
    const Vec& x = c.points[t].position;
    double f = model.kn * d - g_point * velocity(x).dot(n);
    if (!model.attractive_damping && f < 0.0) f = 0.0;
    normal += f;
    centre += f * x;
    deep_centre += d * x;
    depth_sum += d;
    e.depth = std::max(e.depth, d);
  }
  // The centre of pressure, where the normal forces have no moment (while they push; the
  // depth-weighted centre when every dashpot cancels its spring).
  e.at = normal > 0.0 ? Vec(centre / normal) : Vec(deep_centre / depth_sum);
  e.force = normal * n;
  e.normal = -n;
  if (model.tangential == TangentialModel::kNone || pp.friction == 0.0) {
    shear.setZero();
    return e;
  }
  const Vec v = velocity(e.at);
  const Vec vt = v - v.dot(n) * n;
  const double s2 = shear.squaredNorm();
  if (s2 > 0.0) {
    shear -= shear.dot(n) * n;
    const double s2_new = shear.squaredNorm();
    if (model.keep_spring_length && s2_new > 0.0) shear *= std::sqrt(s2 / s2_new);
  }
  shear += vt * dt;
  const double f_max = pp.friction * normal;
  const double f_spring2 = k.kt * k.kt * shear.squaredNorm();
  if (f_spring2 > f_max * f_max) {
    shear *= f_spring2 > 0.0 ? f_max / std::sqrt(f_spring2) : 0.0;
    e.force -= k.kt * shear;
  } else {
    e.force -= k.kt * shear + k.gt * vt;
  }
  return e;
}

}  // namespace

void PolyhedralDem::check_world() {
  const auto& p = w_.particles;
  for (std::size_t k = 0; k < p.size(); ++k) {
    if (!p.polyhedron(k))
      throw InputError(fmt::format(
          "DEM: grain {} is a sphere in a world of polyhedral grains; a world holds one kind of "
          "grain",
          p.id[k].index));
    if (p.flags[k] & kGhost)
      throw InputError("DEM: polyhedral grains run on one process (no MPI yet)");
  }
  for (std::size_t k = 0; k < w_.walls.size(); ++k)
    if (w_.walls[k].plane() == nullptr)
      throw InputError(fmt::format("DEM: wall {} is a {}; polyhedral grains touch plane walls only",
                                   k, w_.walls[k].type_name()));
  const ContactModel& m = w_.model;
  if (!(m.normal == NormalLaws::id<LinearNormal>()))
    throw InputError(
        "DEM with polyhedral grains: contact.normal = \"linear\" (a spring per contact point; a "
        "Hertz law needs a curvature, which corners and edges do not have)");
  if (m.rolling != RollingModel::kNone || m.cohesion != CohesionModel::kNone)
    throw InputError(
        "DEM with polyhedral grains: no rolling resistance (faces resist rolling) and no "
        "cohesion yet");
  checked_ = true;
}

void PolyhedralDem::initialize() {
  check_world();
  w_.neighbors.rolling = false;
  reorder_.build_lists(w_);
  compute_forces();
}

void PolyhedralDem::step() {
  if (!checked_) check_world();  // a resumed run steps without initialize()
  const double h = w_.dt;
  {
    auto scope = timers_.time(Phase::kIntegrate);
    kick(0.5 * h);
    drift(h);
    for (auto& wall : w_.walls) wall.advance(h);
  }
  {
    auto scope = timers_.time(Phase::kNeighbors);
    if (w_.neighbors.needs_rebuild(w_.particles, w_.walls)) reorder_.build_lists(w_);
  }
  compute_forces();
  {
    auto scope = timers_.time(Phase::kClosing);
    kick(0.5 * h);
  }
  w_.time += h;
  ++w_.step;
  check_grain_states(w_);
}

// v += h (f / m + g), omega += h I_w^-1 t (I_w at the current orientation), then the stage's
// viscous damping, as the round grains' kick does.
void PolyhedralDem::kick(double h) {
  auto& p = w_.particles;
  const double keep = w_.viscous_rate > 0.0 ? 1.0 / (1.0 + w_.viscous_rate * h) : 1.0;
  for (std::size_t k = 0; k < p.size(); ++k) {
    if (p.inv_mass[k] == 0.0) continue;
    const Vec inv = w_.shapes[p.shape_index[k]].moments(p.mass[k]).cwiseInverse();
    p.v[k] = keep * (p.v[k] + h * (p.inv_mass[k] * p.f[k] + w_.gravity));
    p.omega[k] = keep * (p.omega[k] + world_inverse_inertia(p.q[k], inv) * (h * p.t[k]));
  }
}

void PolyhedralDem::drift(double h) {
  auto& p = w_.particles;
  for (std::size_t k = 0; k < p.size(); ++k) {
    if (p.inv_mass[k] == 0.0) continue;
    p.x[k] += h * p.v[k];
    free_rotation(p.q[k], p.omega[k], w_.shapes[p.shape_index[k]].moments(p.mass[k]), h);
  }
}

// The contact of pair entry k (its tangential spring advanced), or none.
PolyhedralDem::EntryForce PolyhedralDem::pair_force(std::size_t k) {
  const auto& p = w_.particles;
  auto& pl = w_.neighbors.pairs;
  const std::uint32_t i = pl.i[k], j = pl.j[k];
  PolyhedronContact c;
  if (!((p.x[i] - p.x[j]).norm() > p.radius[i] + p.radius[j]))
    c = polyhedron_contact(w_.shapes[p.shape_index[i]].solid, p.x[i], p.q[i],
                           w_.shapes[p.shape_index[j]].solid, p.x[j], p.q[j], 0.0);
  const auto velocity = [&](const Vec& x) -> Vec {
    return p.v[i] + p.omega[i].cross(x - p.x[i]) - p.v[j] - p.omega[j].cross(x - p.x[j]);
  };
  const double m_eff = p.inv_mass[j] == 0.0   ? p.mass[i]
                       : p.inv_mass[i] == 0.0 ? p.mass[j]
                                              : p.mass[i] * p.mass[j] / (p.mass[i] + p.mass[j]);
  // The normal from j to i: the narrow phase's runs from i (A) to j (B).
  return manifold_force(c, -c.normal, velocity, w_.materials.pair(p.material[i], p.material[j]),
                        w_.model, m_eff, w_.dt, pl.shear[k]);
}

PolyhedralDem::EntryForce PolyhedralDem::wall_force(std::size_t k) {
  const auto& p = w_.particles;
  auto& wl = w_.neighbors.wall_pairs;
  const std::uint32_t i = wl.i[k];
  const Wall<3>& wall = w_.walls[wl.wall[k]];
  const Vec n = wall.normal();
  PolyhedronContact c;
  if (!(n.dot(p.x[i] - wall.point) > p.radius[i]))
    c = polyhedron_plane_contact(w_.shapes[p.shape_index[i]].solid, p.x[i], p.q[i], wall.point, n,
                                 0.0);
  const auto velocity = [&](const Vec& x) -> Vec {
    return p.v[i] + p.omega[i].cross(x - p.x[i]) - wall.velocity_at(x);
  };
  return manifold_force(c, n, velocity, w_.materials.pair(p.material[i], wall.material), w_.model,
                        p.mass[i], w_.dt, wl.shear[k]);
}

void PolyhedralDem::compute_forces() {
  auto scope = timers_.time(Phase::kPairPass);
  const auto np = static_cast<std::ptrdiff_t>(w_.neighbors.pairs.size());
  const auto nw = static_cast<std::ptrdiff_t>(w_.neighbors.wall_pairs.size());
  pair_out_.resize(static_cast<std::size_t>(np));
  wall_out_.resize(static_cast<std::size_t>(nw));
#pragma omp parallel for schedule(dynamic, 64) if (np >= kMinParallelItems)
  for (std::ptrdiff_t k = 0; k < np; ++k)
    pair_out_[static_cast<std::size_t>(k)] = pair_force(static_cast<std::size_t>(k));
#pragma omp parallel for schedule(dynamic, 64) if (nw >= kMinParallelItems)
  for (std::ptrdiff_t k = 0; k < nw; ++k)
    wall_out_[static_cast<std::size_t>(k)] = wall_force(static_cast<std::size_t>(k));
  sum_forces();
}

// Each entry's force into its grains' sums and its wall's totals, in the lists' order.
void PolyhedralDem::sum_forces() {
  auto& p = w_.particles;
  auto& nl = w_.neighbors;
  for (std::size_t k = 0; k < p.size(); ++k) {
    p.f[k].setZero();
    p.t[k].setZero();
  }
  wall_totals_.reset(w_.walls.size());
  diag_.touching = 0;
  diag_.max_overlap_ratio = 0.0;
  auto& geometry = w_.contact_geometry;
  geometry.pairs.resize(pair_out_.size());
  geometry.wall_pairs.resize(wall_out_.size());
  for (std::size_t k = 0; k < pair_out_.size(); ++k) {
    const EntryForce& e = pair_out_[k];
    nl.pairs.force[k] = e.force;
    const std::uint32_t i = nl.pairs.i[k], j = nl.pairs.j[k];
    const Vec arm = e.at - p.x[i];
    geometry.pairs.set(k, e.normal, e.depth == 0.0 ? Vec::Zero() : arm, e.depth);
    if (e.depth == 0.0) continue;
    p.f[i] += e.force;
    p.t[i] += arm.cross(e.force);
    p.f[j] -= e.force;
    p.t[j] -= (e.at - p.x[j]).cross(e.force);
    ++diag_.touching;
    diag_.max_overlap_ratio =
        std::max(diag_.max_overlap_ratio, e.depth / std::min(p.radius[i], p.radius[j]));
  }
  for (std::size_t k = 0; k < wall_out_.size(); ++k) {
    const EntryForce& e = wall_out_[k];
    nl.wall_pairs.force[k] = e.force;
    const std::uint32_t i = nl.wall_pairs.i[k], wall = nl.wall_pairs.wall[k];
    const Vec arm = e.at - p.x[i];
    geometry.wall_pairs.set(k, e.normal, e.depth == 0.0 ? Vec::Zero() : arm, e.depth);
    if (e.depth == 0.0) continue;
    p.f[i] += e.force;
    p.t[i] += arm.cross(e.force);
    wall_totals_.add_force(wall, -e.force);
    wall_totals_.add_torque(wall, -(e.at - w_.walls[wall].pivot).cross(e.force));
    ++diag_.touching;
    diag_.max_overlap_ratio = std::max(diag_.max_overlap_ratio, e.depth / p.radius[i]);
  }
  wall_totals_.store(w_.walls);
}

}  // namespace sable
