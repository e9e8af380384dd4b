#include "sable/geometry/polyhedron_plane.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "sable/core/error.hpp"
#include "sable/geometry/manifold_reduction.hpp"

namespace sable {

namespace {

using Vec = Eigen::Vector3d;

// The grain's vertices posed in the world and measured against the plane. Every pass computes
// them afresh by the same expressions, so that each gets the same bits each time.
struct Posed {
  const std::vector<Vec>& v;  // body frame
  Eigen::Matrix3d R;
  Vec x, p, n;
  Vec at(std::size_t k) const { return R * v[k] + x; }
  double gap(std::size_t k) const { return n.dot(at(k) - p); }
};

// The face of `a` whose normal is lowest along m (body frame), the first of equals.
std::uint32_t lowest_face(const ConvexPolyhedron& a, const Vec& m) {
  std::uint32_t best = 0;
  double low = m.dot(a.normals()[0]);
  for (std::uint32_t f = 1; f < a.face_count(); ++f)
    if (const double h = m.dot(a.normals()[f]); h < low) {
      low = h;
      best = f;
    }
  return best;
}

// Over 4 vertices within the margin: the 4 of the shared rule, in the order of the vertices.
void reduce_posed(const Posed& w, double margin, const ManifoldMotion& motion,
                  PolyhedronContact& c) {
  std::array<std::size_t, 4> keep{};
  const std::size_t count = w.v.size();
  c.count = detail::reduce_to_four(
      count, [&](std::size_t k) { return w.at(k); },
      [&](std::size_t k) { return motion.predicted(w.at(k), c.normal, w.gap(k)); },
      [&](std::size_t k) { return w.gap(k) <= margin; }, w.n, keep);
  // The whole array, the unused places last (sorting a prefix of c.count trips GCC 12's bounds
  // warning, which cannot see that the rule keeps at most 4).
  std::fill(keep.begin() + c.count, keep.end(), ~std::size_t{0});
  std::sort(keep.begin(), keep.end());
  for (int i = 0; i < c.count; ++i) c.points[i] = {w.at(keep[i]), w.gap(keep[i])};
}

}  // namespace

PolyhedronContact polyhedron_plane_contact(const ConvexPolyhedron& a,
                                           const Eigen::Vector3d& position,
                                           const Eigen::Quaterniond& orientation,
                                           const Eigen::Vector3d& plane_point,
                                           const Eigen::Vector3d& plane_normal, double margin,
                                           const ManifoldMotion& motion) {
  if (!(margin >= 0.0) || !std::isfinite(margin))
    throw InputError(fmt::format("polyhedron-plane contact: margin {}, expected >= 0", margin));
  if (const double len = plane_normal.norm(); !(std::abs(len - 1.0) <= kPlaneNormalTolerance))
    throw InputError(fmt::format(
        "polyhedron-plane contact: plane normal ({}, {}, {}) of length {}, expected unit",
        plane_normal.x(), plane_normal.y(), plane_normal.z(), len));
  const Posed w{a.vertices(), orientation.toRotationMatrix(), position, plane_point, plane_normal};
  PolyhedronContact c;
  c.kind = PolyhedronContactKind::kFaceB;
  c.normal = -plane_normal;
  // One pass: the least gap (from the first vertex's, so that a NaN pose reads NaN), and the
  // vertices within the margin, the first 4 of them kept as they come.
  std::size_t within = 0;
  double low = w.gap(0);
  for (std::size_t k = 0; k < w.v.size(); ++k) {
    const Vec y = w.at(k);
    const double g = w.n.dot(y - w.p);  // w.gap(k), its world vertex at hand
    low = std::min(low, g);
    if (g <= margin) {
      if (within < PolyhedronContact::kMaxPoints) c.points[within] = {y, g};
      ++within;
    }
  }
  c.separation = low;
  if (!(low <= margin)) return c;
  c.feature_a = lowest_face(a, w.R.transpose() * plane_normal);
  if (within <= PolyhedronContact::kMaxPoints)
    c.count = static_cast<int>(within);
  else
    reduce_posed(w, margin, motion, c);
  return c;
}

}  // namespace sable
