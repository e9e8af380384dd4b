#include "sable/analysis/stress.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "sable/core/error.hpp"

namespace sable {

namespace {

// [a]x, the matrix of the cross product with a: ([a]x v = a x v). In 2D a is the scalar
// rotation rate about z and [a]x = [[0, -a], [a, 0]].
Tensor<3> cross_matrix(const Eigen::Vector3d& a) {
  Tensor<3> m;
  m << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
  return m;
}
Tensor<2> cross_matrix(double a) {
  Tensor<2> m;
  m << 0.0, -a, a, 0.0;
  return m;
}
// w w^T - |w|^2 I: the centripetal part of int rho r (x) (w x (w x r)) over J.
Tensor<3> centripetal(const Eigen::Vector3d& w) {
  return w * w.transpose() - w.squaredNorm() * Tensor<3>::Identity();
}
Tensor<2> centripetal(double w) {
  return -w * w * Tensor<2>::Identity();
}

}  // namespace

template <int D>
double solid_fraction(const Sample<D>& s, const Region<D>& region) {
  double v = 0.0;
  for (std::size_t k = 0; k < s.size(); ++k)
    if (region.contains(s.x[k])) v += s.volume[k];
  return v / region.volume(s.thickness);
}

template <int D>
ParticleStresses<D> particle_stresses(const Sample<D>& s, double nu) {
  if (nu <= 0.0) nu = solid_fraction(s, grain_bounds(s));
  if (!(nu > 0.0 && nu <= 1.0))
    throw InputError(fmt::format("{}: solid fraction {} is not in (0, 1]", s.source, nu));
  ParticleStresses<D> out;
  out.solid_fraction = nu;
  const std::size_t n = s.size();
  out.sigma.assign(n, Tensor<D>::Zero());
  out.pressure.assign(n, 0.0);
  out.free_volume.resize(n);
  const auto& c = s.contacts;
  for (std::size_t k = 0; k < c.size(); ++k) {
    out.sigma[c.i[k]] -= c.force[k] * c.arm_i[k].transpose();
    if (!c.is_wall(k)) out.sigma[c.j[k]] += c.force[k] * c.arm_j[k].transpose();
  }
  for (std::size_t g = 0; g < n; ++g) {
    out.free_volume[g] = s.volume[g] / nu;
    out.sigma[g] /= out.free_volume[g];
    out.pressure[g] = out.sigma[g].trace() / D;
  }
  return out;
}

template <int D>
Tensor<D> love_weber(const Sample<D>& s, const Region<D>& region) {
  const double volume = region.volume(s.thickness);
  Tensor<D> sum = Tensor<D>::Zero();
  const auto& c = s.contacts;
  std::size_t inside = 0;
  for (std::size_t k = 0; k < c.size(); ++k) {
    const bool in_i = region.contains(s.x[c.i[k]]);
    const bool in_j = !c.is_wall(k) && region.contains(s.x[c.j[k]]);
    // The contact vector joins the two lever arms; a contact leaving the region acts on it as
    // a boundary force applied at the contact point.
    if (in_i && in_j) {
      sum -= c.force[k] * (c.arm_i[k] - c.arm_j[k]).transpose();
    } else if (in_i) {
      sum -= c.force[k] * c.arm_i[k].transpose();
    } else if (in_j) {
      sum += c.force[k] * c.arm_j[k].transpose();
    }
    inside += (in_i || in_j) ? 1 : 0;
  }
  if (inside == 0)
    throw InputError(fmt::format("{}: no contact of a grain inside the region", s.source));
  return sum / volume;
}

template <int D>
MeanStress<D> mean_stress(const Sample<D>& s, const Region<D>& region,
                          const typename Space<D>::Vec& origin) {
  using Vec = typename Space<D>::Vec;
  MeanStress<D> m;
  m.volume = region.volume(s.thickness);
  m.origin = origin;
  const Vec& x0 = m.origin;
  std::vector<std::uint8_t> in(s.size(), 0);
  for (std::size_t g = 0; g < s.size(); ++g) {
    // Fixed grains are supports, like walls: their contacts act on the region from outside.
    if (s.fixed[g] || !region.contains(s.x[g])) continue;
    in[g] = 1;
    ++m.grains;
    const Vec lever = s.x[g] - x0;
    m.gravity -= s.mass[g] * s.gravity * lever.transpose();
    // The spin's part, int rho (alpha x r + w x (w x r)) (x) r = ([alpha]x + w w^T - |w|^2 I) J
    // with J = int rho r r^T: (I / 2) Id for a disk or a sphere, a polyhedron's own tensor.
    const Tensor<D> spin = cross_matrix(s.alpha[g]) + centripetal(s.omega[g]);
    m.inertia += s.mass[g] * s.a[g] * lever.transpose() +
                 (s.second_moment.empty() ? Tensor<D>(0.5 * s.inertia[g] * spin)
                                          : Tensor<D>(spin * s.second_moment[g]));
  }
  if (m.grains == 0) throw InputError(fmt::format("{}: the region holds no grain", s.source));
  const auto& c = s.contacts;
  for (std::size_t k = 0; k < c.size(); ++k) {
    if (in[c.i[k]]) m.contact -= c.force[k] * (s.x[c.i[k]] + c.arm_i[k] - x0).transpose();
    if (!c.is_wall(k) && in[c.j[k]])
      m.contact += c.force[k] * (s.x[c.j[k]] + c.arm_j[k] - x0).transpose();
  }
  m.contact /= m.volume;
  m.gravity /= m.volume;
  m.inertia /= m.volume;
  return m;
}

template <int D>
double asymmetry(const Tensor<D>& t) {
  const double norm = t.norm();
  return norm > 0.0 ? 0.5 * (t - t.transpose()).norm() / norm : 0.0;
}

template <int D>
Table particle_stress_table(const Sample<D>& s, const ParticleStresses<D>& ps) {
  static constexpr const char* axes = "xyz";
  Table t;
  std::vector<double> col(s.size());
  for (std::size_t g = 0; g < s.size(); ++g) col[g] = s.id[g];
  t.add("id", col);
  for (int d = 0; d < D; ++d) {
    for (std::size_t g = 0; g < s.size(); ++g) col[g] = s.x[g][d];
    t.add(fmt::format("{}_m", axes[d]), col);
  }
  t.add("radius_m", s.radius);
  t.add("pressure_Pa", ps.pressure);
  for (int a = 0; a < D; ++a)
    for (int b = 0; b < D; ++b) {
      for (std::size_t g = 0; g < s.size(); ++g) col[g] = ps.sigma[g](a, b);
      t.add(fmt::format("sigma_{}{}_Pa", axes[a], axes[b]), col);
    }
  return t;
}

template <int D>
Summary tensor_summary(const Tensor<D>& t) {
  static constexpr const char* axes = "xyz";
  Summary s;
  for (int a = 0; a < D; ++a)
    for (int b = 0; b < D; ++b) s.add(fmt::format("{}{}_Pa", axes[a], axes[b]), t(a, b));
  s.add("pressure_Pa", t.trace() / D);
  s.add("asymmetry", asymmetry<D>(t));
  const Eigen::SelfAdjointEigenSolver<Tensor<D>> eig(0.5 * (t + t.transpose()));
  std::vector<double> principal(eig.eigenvalues().data(), eig.eigenvalues().data() + D);
  std::sort(principal.rbegin(), principal.rend());
  s.add("principal_Pa", principal);
  return s;
}

template <int D>
Summary mean_stress_summary(const MeanStress<D>& m, const Tensor<D>& lw) {
  Summary s;
  s.add("convention", "compression positive; sigma_ab = sum f_a x_b");
  s.add("volume_m3", m.volume);
  s.add("grains", m.grains);
  s.add("origin_m", std::vector<double>(m.origin.data(), m.origin.data() + D));
  s.add("contact_part", tensor_summary<D>(m.contact));
  s.add("gravity_part", tensor_summary<D>(m.gravity));
  s.add("inertia_part", tensor_summary<D>(m.inertia));
  s.add("total", tensor_summary<D>(m.total()));
  s.add("love_weber", tensor_summary<D>(lw));
  return s;
}

#define SABLE_STRESS(D)                                                               \
  template ParticleStresses<D> particle_stresses(const Sample<D>&, double);           \
  template double solid_fraction(const Sample<D>&, const Region<D>&);                 \
  template Tensor<D> love_weber(const Sample<D>&, const Region<D>&);                  \
  template MeanStress<D> mean_stress(const Sample<D>&, const Region<D>&,              \
                                     const typename Space<D>::Vec&);                  \
  template double asymmetry<D>(const Tensor<D>&);                                     \
  template Table particle_stress_table(const Sample<D>&, const ParticleStresses<D>&); \
  template Summary tensor_summary<D>(const Tensor<D>&);                               \
  template Summary mean_stress_summary(const MeanStress<D>&, const Tensor<D>&);
SABLE_STRESS(2)
SABLE_STRESS(3)
#undef SABLE_STRESS

}  // namespace sable
