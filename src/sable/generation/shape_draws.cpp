#include "sable/generation/shape_draws.hpp"

#include <fmt/format.h>

#include <cmath>
#include <numbers>

#include "sable/core/error.hpp"
#include "sable/geometry/convex_hull.hpp"
#include "sable/geometry/grain_shapes.hpp"

namespace sable {

Rng shape_stream(std::uint64_t block_seed) {
  // Any constant but the lattice jitter's (generate.cpp): Rng runs the seed through
  // splitmix64, so streams of different seeds are unrelated.
  return Rng(block_seed ^ 0x6a09e667f3bcc909ULL);
}

std::vector<Eigen::Vector3d> random_polyhedron_points(std::size_t n, const Vec3a& aspect, Rng& rng,
                                                      const std::string& what) {
  std::vector<Eigen::Vector3d> points(n);
  for (int draw = 0; draw < kMaxShapeDraws; ++draw) {
    for (Eigen::Vector3d& p : points) {
      const double z = rng.uniform(-1.0, 1.0);
      const double phi = 2.0 * std::numbers::pi * rng.uniform();
      const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
      p = Eigen::Vector3d(aspect[0] * s * std::cos(phi), aspect[1] * s * std::sin(phi),
                          aspect[2] * z);
    }
    if (spans_volume(points)) return points;
  }
  throw InputError(fmt::format(
      "{}: {} draws of {} points stretched by aspect = [{}, {}, {}] gave no solid (the points lie "
      "in one plane to 1e-12 of their size): raise the smallest aspect",
      what, kMaxShapeDraws, n, aspect[0], aspect[1], aspect[2]));
}

Eigen::Quaterniond random_rotation(Rng& rng) {
  const double u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform();
  const double a = std::sqrt(1.0 - u1), b = std::sqrt(u1);
  const double t2 = 2.0 * std::numbers::pi * u2, t3 = 2.0 * std::numbers::pi * u3;
  return Eigen::Quaterniond(a * std::sin(t2), a * std::cos(t2), b * std::sin(t3), b * std::cos(t3))
      .normalized();
}

std::vector<Eigen::Vector3d> unit_shape(const std::vector<Eigen::Vector3d>& points,
                                        const std::string& what) {
  // The table's own centroid and bounding radius (its corners, flat vertices dropped), so that
  // a grain made of this shape times r has the bounding radius r to rounding.
  GrainShapes probe;
  const ShapePlacement placed = probe.add(points, what.c_str());
  const double radius = probe[placed.index].solid.radius();
  std::vector<Eigen::Vector3d> unit = convex_hull(points, what.c_str()).vertices;
  for (Eigen::Vector3d& p : unit) p = (p - placed.centroid) / radius;
  return unit;
}

ShapeDraws::ShapeDraws(const GrainShapeConfig& shape, std::uint64_t block_seed,
                       const std::vector<Eigen::Vector3d>& given, const std::string& what)
    : shape_(shape), rng_(shape_stream(block_seed)) {
  if (shape.kind != GrainShapeConfig::Kind::kGiven) return;
  std::vector<Eigen::Vector3d> points = given;
  if (points.empty())
    for (const Vec3a& p : shape.points) points.emplace_back(p[0], p[1], p[2]);
  unit_ = unit_shape(points, what.empty() ? shape.key + ".points" : what);
}

void ShapeDraws::next() {
  if (random_shapes())
    unit_ = unit_shape(
        random_polyhedron_points(shape_.vertices, shape_.aspect, rng_, shape_.key + ".polyhedron"),
        shape_.key + ".polyhedron");
  turn_ = shape_.random_orientation || random_shapes() ? random_rotation(rng_)
                                                       : Eigen::Quaterniond::Identity();
}

}  // namespace sable
