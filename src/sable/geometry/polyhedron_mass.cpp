#include "sable/geometry/polyhedron_mass.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>

#include "sable/core/error.hpp"

namespace sable {

namespace {

// A triangle's corner coordinates along one axis (w0, w1, w2) give the polynomials its
// share of the integrals needs: f1 = sum w, f2 = sum of the degree-2 monomials, f3 = of the
// degree-3 ones, and g_k = f2 + w_k (f1 + w_k) (Eberly 2002, section 3).
struct AxisTerms {
  double f1, f2, f3, g0, g1, g2;
};

AxisTerms axis_terms(double w0, double w1, double w2) {
  const double s01 = w0 + w1;
  const double sq0 = w0 * w0;
  const double sq01 = sq0 + w1 * s01;
  AxisTerms t;
  t.f1 = s01 + w2;
  t.f2 = sq01 + w2 * t.f1;
  t.f3 = w0 * sq0 + w1 * sq01 + w2 * t.f2;
  t.g0 = t.f2 + w0 * (t.f1 + w0);
  t.g1 = t.f2 + w1 * (t.f1 + w1);
  t.g2 = t.f2 + w2 * (t.f1 + w2);
  return t;
}

}  // namespace

PolyhedronMass polyhedron_mass(const std::vector<Eigen::Vector3d>& vertices,
                               const std::vector<std::array<std::uint32_t, 3>>& triangles,
                               const char* what) {
  // The integrals are taken about the vertices' mean: far from the origin, the products of
  // large coordinates would cancel in the shift to the centroid.
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  for (const auto& v : vertices) origin += v;
  if (!vertices.empty()) origin /= static_cast<double>(vertices.size());
  // 1, x, y, z, x^2, y^2, z^2, xy, yz, zx
  double in[10] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
  for (const auto& tri : triangles) {
    for (std::uint32_t k : tri)
      if (k >= vertices.size())
        throw InputError(
            fmt::format("{}: a triangle names vertex {} of {}", what, k, vertices.size()));
    const Eigen::Vector3d p0 = vertices[tri[0]] - origin, p1 = vertices[tri[1]] - origin,
                          p2 = vertices[tri[2]] - origin;
    const Eigen::Vector3d n = (p1 - p0).cross(p2 - p0);  // twice the area, outward
    const AxisTerms x = axis_terms(p0.x(), p1.x(), p2.x());
    const AxisTerms y = axis_terms(p0.y(), p1.y(), p2.y());
    const AxisTerms z = axis_terms(p0.z(), p1.z(), p2.z());
    in[0] += n.x() * x.f1;
    in[1] += n.x() * x.f2;
    in[2] += n.y() * y.f2;
    in[3] += n.z() * z.f2;
    in[4] += n.x() * x.f3;
    in[5] += n.y() * y.f3;
    in[6] += n.z() * z.f3;
    in[7] += n.x() * (p0.y() * x.g0 + p1.y() * x.g1 + p2.y() * x.g2);
    in[8] += n.y() * (p0.z() * y.g0 + p1.z() * y.g1 + p2.z() * y.g2);
    in[9] += n.z() * (p0.x() * z.g0 + p1.x() * z.g1 + p2.x() * z.g2);
  }
  const double scale[10] = {1.0 / 6,  1.0 / 24, 1.0 / 24,  1.0 / 24,  1.0 / 60,
                            1.0 / 60, 1.0 / 60, 1.0 / 120, 1.0 / 120, 1.0 / 120};
  for (int k = 0; k < 10; ++k) in[k] *= scale[k];
  PolyhedronMass m;
  m.volume = in[0];
  if (!(m.volume > 0.0))
    throw InputError(fmt::format(
        "{}: its triangles enclose a volume of {:.6g}, expected a positive one (a closed "
        "surface whose triangles wind counterclockwise seen from outside)",
        what, m.volume));
  const Eigen::Vector3d c(in[1] / m.volume, in[2] / m.volume, in[3] / m.volume);
  const double v = m.volume;
  // Second moments about the centroid, then the inertia tensor from them.
  const double xx = in[4] - v * c.x() * c.x(), yy = in[5] - v * c.y() * c.y(),
               zz = in[6] - v * c.z() * c.z();
  const double xy = in[7] - v * c.x() * c.y(), yz = in[8] - v * c.y() * c.z(),
               zx = in[9] - v * c.z() * c.x();
  m.inertia << yy + zz, -xy, -zx, -xy, zz + xx, -yz, -zx, -yz, xx + yy;
  m.centroid = origin + c;
  return m;
}

}  // namespace sable
