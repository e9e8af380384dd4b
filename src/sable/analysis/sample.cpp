#include "sable/analysis/sample.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "sable/core/error.hpp"
#include "sable/core/rigid_rotation.hpp"
#include "sable/io/snapshot.hpp"
#include "sable/world/world.hpp"

namespace sable {

template <int D>
void ContactSet<D>::clear() {
  i.clear();
  j.clear();
  wall.clear();
  n.clear();
  force.clear();
  fn.clear();
  ft.clear();
  arm_i.clear();
  arm_j.clear();
  branch.clear();
  overlap.clear();
  friction.clear();
  vrel.clear();
  damping_n.clear();
  damping_t.clear();
  spring.clear();
}

template <int D>
void ContactSet<D>::push(std::uint32_t gi, std::uint32_t partner, bool at_wall, const Vec& normal,
                         const Vec& f, const Vec& a_i, const Vec& a_j, const Vec& l, double delta,
                         double mu, const ContactMotion<D>& motion) {
  i.push_back(gi);
  j.push_back(partner);
  wall.push_back(at_wall ? 1 : 0);
  n.push_back(normal);
  force.push_back(f);
  const double f_n = -f.dot(normal);
  fn.push_back(f_n);
  ft.push_back(f + f_n * normal);
  arm_i.push_back(a_i);
  arm_j.push_back(a_j);
  branch.push_back(l);
  overlap.push_back(delta);
  friction.push_back(mu);
  vrel.push_back(motion.vrel);
  damping_n.push_back(motion.damping_n);
  damping_t.push_back(motion.damping_t);
  spring.push_back(motion.spring);
}

template <int D>
double Sample<D>::total_mass() const {
  double m = 0.0;
  for (double mk : mass) m += mk;
  return m;
}

namespace {

// A polyhedral grain's volume, its mean principal moment (the `inertia` scalar), its second
// moment of mass in the world frame, and its angular acceleration by Euler's equations,
// I_w alpha = torque - omega x I_w omega (the gyroscopic term is zero for a sphere, not for a
// polyhedron). 3D only: a 2D world holds no polyhedra.
template <int D>
void add_polyhedron(const World<D>& w, std::size_t k, Sample<D>& s) {
  if constexpr (D == 3) {
    const auto& p = w.particles;
    const PolyhedronShape& shape = w.shapes[p.shape_index[k]];
    const Eigen::Vector3d moments = shape.moments(p.mass[k]);
    s.volume[k] = shape.volume;
    s.inertia[k] = moments.sum() / 3.0;
    const Eigen::Matrix3d r = p.q[k].toRotationMatrix();
    // int rho r r^T along the principal axes: J_x = (I_y + I_z - I_x) / 2, and so on.
    const Eigen::Vector3d j = Eigen::Vector3d::Constant(0.5 * moments.sum()) - moments;
    s.second_moment[k] = r * j.asDiagonal() * r.transpose();
    if (p.fixed(k)) return;
    const Eigen::Matrix3d inertia = r * moments.asDiagonal() * r.transpose();
    const Eigen::Vector3d& omega = p.omega[k];
    s.alpha[k] = world_inverse_inertia(p.q[k], moments.cwiseInverse()) *
                 (p.t[k] - omega.cross(Eigen::Vector3d(inertia * omega)));
  }
}

template <int D>
void add_grains(const World<D>& w, Sample<D>& s) {
  using S = Space<D>;
  const auto& p = w.particles;
  const std::size_t n = p.size();
  s.x = p.x;
  if (s.geometry == ForceGeometry::kContactDynamics)
    for (std::size_t k = 0; k < n; ++k) s.x[k] -= w.dt * p.v[k];
  s.v = p.v;
  s.omega = p.omega;
  s.radius = p.radius;
  s.mass = p.mass;
  s.a.resize(n);
  s.alpha.resize(n);
  s.volume.resize(n);
  s.inertia.resize(n);
  s.fixed.resize(n);
  s.id.resize(n);
  if (s.polyhedra) s.second_moment.assign(n, Eigen::Matrix<double, D, D>::Zero());
  constexpr double pi = 3.14159265358979323846;
  for (std::size_t k = 0; k < n; ++k) {
    const double r = p.radius[k];
    s.volume[k] = D == 3 ? 4.0 / 3.0 * pi * r * r * r : pi * r * r * w.thickness;
    s.inertia[k] = ParticleStore<D>::inertia_factor() * p.mass[k] * r * r;
    s.fixed[k] = p.fixed(k) ? 1 : 0;
    s.id[k] = p.id[k].index;
    if (p.fixed(k)) {
      s.a[k] = S::zero();
      s.alpha[k] = S::zero_rot();
    } else {
      s.a[k] = p.f[k] * p.inv_mass[k] + w.gravity;
      s.alpha[k] = p.t[k] * p.inv_inertia[k];
    }
    if (p.polyhedron(k)) add_polyhedron(w, k, s);
  }
}

// The normal law's damping coefficients and the tangential spring's force of a touching soft
// contact (zero otherwise: contact dynamics has no dashpot and no spring, an open capillary
// bridge no overlap).
template <int D>
ContactMotion<D> contact_motion(const World<D>& w, const PairParams& pp, bool soft, double delta,
                                double r_eff, double m_eff, const typename Space<D>::Vec& vrel,
                                const typename Space<D>::Vec& shear) {
  ContactMotion<D> m;
  m.vrel = vrel;
  if (!soft || !(delta > 0.0)) return m;
  const NormalCoeffs c = NormalLaws::visit(
      w.model.normal, [&]<class Law>() { return Law::coeffs(pp, w.model, delta, r_eff, m_eff); });
  // Positive: the kernel multiplies minus the relative velocity by them (contact_model.hpp).
  m.damping_n = c.gn;
  m.damping_t = c.gt;
  m.spring = c.kt * shear.norm();
  return m;
}

// Soft contacts: the contact point sits in the middle of the overlap (where DEM applies the
// force; for an open gap each arm ends on its grain's surface). Contact dynamics: arms end on
// the surfaces. Geometry from the sample's positions (see sample.hpp for CD).
template <int D>
void add_contacts(const World<D>& w, Sample<D>& s) {
  using S = Space<D>;
  using Vec = typename S::Vec;
  const auto& p = w.particles;
  const bool soft = s.geometry == ForceGeometry::kSoft;
  const std::vector<Vec>& x = s.x;
  const auto& pl = w.neighbors.pairs;
  auto& c = s.contacts;
  c.clear();
  auto inv_mass = [&](std::uint32_t g) { return p.fixed(g) ? 0.0 : 1.0 / p.mass[g]; };
  for (std::size_t k = 0; k < pl.size(); ++k) {
    const Vec& f = pl.force[k];
    if (f.squaredNorm() == 0.0) continue;
    const std::uint32_t i = pl.i[k], j = pl.j[k];
    const Vec d = x[j] - x[i];
    const double dist = d.norm();
    const Vec n = dist > 0.0 ? Vec(d / dist) : Vec(Vec::UnitX());
    const double delta = p.radius[i] + p.radius[j] - dist;
    const double half = soft ? 0.5 * std::max(delta, 0.0) : 0.0;
    const PairParams& pp = w.materials.pair(p.material[i], p.material[j]);
    const Vec arm_i = (p.radius[i] - half) * n, arm_j = -(p.radius[j] - half) * n;
    const Vec vrel =
        p.v[i] + S::spin_velocity(p.omega[i], arm_i) - p.v[j] - S::spin_velocity(p.omega[j], arm_j);
    const double r_eff = p.radius[i] * p.radius[j] / (p.radius[i] + p.radius[j]);
    const double m_eff = 1.0 / std::max(inv_mass(i) + inv_mass(j), 1e-300);
    c.push(i, j, false, n, f, arm_i, arm_j, d, delta, pp.friction,
           contact_motion(w, pp, soft, delta, r_eff, m_eff, vrel, pl.shear[k]));
  }
  const auto& wl = w.neighbors.wall_pairs;
  for (std::size_t k = 0; k < wl.size(); ++k) {
    const Vec& f = wl.force[k];
    if (f.squaredNorm() == 0.0) continue;
    const std::uint32_t i = wl.i[k];
    Wall<D> wall = w.walls[wl.wall[k]];
    if (!soft) wall.point -= w.dt * wall.velocity;  // where it was when the impulse was made
    Vec into;
    const double dist = wall.distance(x[i], into);
    const Vec n = -into;  // from the grain towards the wall
    const double delta = p.radius[i] - dist;
    const Vec arm = (p.radius[i] - (soft ? 0.5 * std::max(delta, 0.0) : 0.0)) * n;
    const PairParams& pp = w.materials.pair(p.material[i], wall.material);
    const Vec vrel = p.v[i] + S::spin_velocity(p.omega[i], arm) - wall.velocity_at(x[i] + arm);
    c.push(i, wl.wall[k], true, n, f, arm, Vec::Zero(), arm, delta, pp.friction,
           contact_motion(w, pp, soft, delta, p.radius[i], p.mass[i], vrel, wl.shear[k]));
  }
}

}  // namespace

// Polyhedral contacts: normal, point and depth as the solver stored them
// (world/contact_geometry.hpp), arms relative to the centres, so that they hold at the CD
// sample's positions too. Neither dashpots nor springs per entry: the DEM law has them per
// manifold point, which the lists do not keep (the dissipation analysis refuses polyhedra).
template <int D>
void add_polyhedral_contacts(const World<D>& w, Sample<D>& s) {
  using S = Space<D>;
  using Vec = typename S::Vec;
  const auto& p = w.particles;
  const auto& g = w.contact_geometry;
  const auto& pl = w.neighbors.pairs;
  const auto& wl = w.neighbors.wall_pairs;
  auto& c = s.contacts;
  c.clear();
  const auto any_force = [](const std::vector<Vec>& f) {
    return std::any_of(f.begin(), f.end(), [](const Vec& v) { return v.squaredNorm() > 0.0; });
  };
  if (!g.matches(pl.size(), wl.size())) {
    if (!any_force(pl.force) && !any_force(wl.force)) return;  // nothing touches yet
    throw InputError(
        "analysis of polyhedral grains: the contacts' normals and points are missing (a "
        "snapshot written before they were kept, or a World not stepped since its lists were "
        "made): step the run once and write it again");
  }
  for (std::size_t k = 0; k < pl.size(); ++k) {
    const Vec& f = pl.force[k];
    if (f.squaredNorm() == 0.0) continue;
    const std::uint32_t i = pl.i[k], j = pl.j[k];
    const Vec arm_i = g.pairs.arm[k];
    const Vec arm_j = s.x[i] + arm_i - s.x[j];
    ContactMotion<D> m;
    m.vrel =
        p.v[i] + S::spin_velocity(p.omega[i], arm_i) - p.v[j] - S::spin_velocity(p.omega[j], arm_j);
    c.push(i, j, false, g.pairs.normal[k], f, arm_i, arm_j, Vec(s.x[j] - s.x[i]), g.pairs.depth[k],
           w.materials.pair(p.material[i], p.material[j]).friction, m);
  }
  for (std::size_t k = 0; k < wl.size(); ++k) {
    const Vec& f = wl.force[k];
    if (f.squaredNorm() == 0.0) continue;
    const std::uint32_t i = wl.i[k];
    Wall<D> wall = w.walls[wl.wall[k]];
    if (s.geometry == ForceGeometry::kContactDynamics) wall.point -= w.dt * wall.velocity;
    const Vec arm = g.wall_pairs.arm[k];
    ContactMotion<D> m;
    m.vrel = p.v[i] + S::spin_velocity(p.omega[i], arm) - wall.velocity_at(Vec(s.x[i] + arm));
    c.push(i, wl.wall[k], true, g.wall_pairs.normal[k], f, arm, Vec::Zero(), arm,
           g.wall_pairs.depth[k], w.materials.pair(p.material[i], wall.material).friction, m);
  }
}

template <int D>
Sample<D> make_sample(const World<D>& w, ForceGeometry geometry) {
  using S = Space<D>;
  Sample<D> s;
  s.geometry = geometry;
  s.polyhedra = !w.shapes.empty();
  add_grains(w, s);
  if (s.polyhedra)
    add_polyhedral_contacts(w, s);
  else
    add_contacts(w, s);
  for (const auto& wall : w.walls) {
    SampleWall sw;
    sw.name = wall.name;
    sw.type = wall.type_name();
    sw.plane = wall.plane() != nullptr;
    sw.point = S::to_array(wall.point);
    sw.normal = S::to_array(wall.normal());
    sw.force = S::to_array(wall.force);
    sw.torque = S::rot_to_array(wall.torque);
    sw.pivot = S::to_array(wall.pivot);
    if (const auto* c = std::get_if<CylinderShape<D>>(&wall.shape)) sw.radius = c->radius;
    s.walls.push_back(sw);
  }
  s.gravity = w.gravity;
  s.thickness = w.thickness;
  s.time = w.time;
  s.step = w.step;
  s.source = "live";
  return s;
}

template <int D>
void check_contact_indices(const Sample<D>& s) {
  const auto& c = s.contacts;
  for (std::size_t k = 0; k < c.size(); ++k)
    if (c.i[k] >= s.size() || (!c.is_wall(k) && c.j[k] >= s.size()))
      throw InputError(fmt::format("{}: contact {} names grain {} or {}, the sample holds {}",
                                   s.source, k, c.i[k], c.j[k], s.size()));
}

template <int D>
void refuse_polyhedra(const Sample<D>& s, const std::string& analysis, const std::string& why) {
  if (s.polyhedra)
    throw InputError(fmt::format("{}: the {} analysis does not apply to polyhedral grains: {}",
                                 s.source, analysis, why));
}

int snapshot_dimension(const std::string& path) {
  return read_snapshot_info(path).dimension;
}

template <int D>
double Region<D>::volume(double thickness) const {
  if (!bounded()) throw InputError("the volume of an unbounded region was asked for");
  double v = 1.0;
  for (int d = 0; d < D; ++d) v *= std::max(hi[d] - lo[d], 0.0);
  return D == 2 ? v * thickness : v;
}

template <int D>
Region<D> grain_bounds(const Sample<D>& s) {
  Region<D> r;
  if (s.size() == 0) throw InputError(fmt::format("{}: the sample holds no grains", s.source));
  r.lo = s.x[0].array() - s.radius[0];
  r.hi = s.x[0].array() + s.radius[0];
  for (std::size_t k = 1; k < s.size(); ++k) {
    r.lo = r.lo.cwiseMin(typename Space<D>::Vec(s.x[k].array() - s.radius[k]));
    r.hi = r.hi.cwiseMax(typename Space<D>::Vec(s.x[k].array() + s.radius[k]));
  }
  return r;
}

template struct ContactSet<2>;
template struct ContactSet<3>;
template struct Sample<2>;
template struct Sample<3>;
template struct Region<2>;
template struct Region<3>;
template Sample<2> make_sample(const World<2>&, ForceGeometry);
template Sample<3> make_sample(const World<3>&, ForceGeometry);
template void check_contact_indices(const Sample<2>&);
template void check_contact_indices(const Sample<3>&);
template void refuse_polyhedra(const Sample<2>&, const std::string&, const std::string&);
template void refuse_polyhedra(const Sample<3>&, const std::string&, const std::string&);
template Region<2> grain_bounds(const Sample<2>&);
template Region<3> grain_bounds(const Sample<3>&);

}  // namespace sable
