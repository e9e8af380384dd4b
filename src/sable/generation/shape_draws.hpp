// The shapes of a [[grains]] block's polyhedral grains (GrainShapeConfig): random convex
// polyhedra, one per grain, or one given convex shape; each turned at random or as given.
//
// Every draw comes from the block's shape stream (shape_stream()), seeded from the block's seed
// but apart from the stream that places the grains and draws their radii: giving a block a
// shape does not move its grains. Per grain, in order: a random polyhedron's points (again
// while they span no solid), then its turn. A shape comes as its unit shape: the corners of
// its hull about the hull's centroid, scaled so that the farthest corner (the bounding radius
// GrainShapes gives a row: PolyhedronShape::solid.radius()) is at 1. A grain of radius r is
// that shape times r, its centroid at the grain's position.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "sable/core/rng.hpp"
#include "sable/generation/grains_config.hpp"

namespace sable {

// The most draws of one random polyhedron's points before the block is refused: points drawn
// uniformly on a sphere span a solid with probability 1, so only an aspect so small that the
// stretched sphere is flat to the hull's tolerance (1e-12 of its size) reaches it.
inline constexpr int kMaxShapeDraws = 100;

// The block's shape stream.
Rng shape_stream(std::uint64_t block_seed);

// `n` points drawn uniformly on the unit sphere (z and the azimuth uniform: Archimedes), each
// then scaled by `aspect` along x, y, z; drawn again, up to kMaxShapeDraws times, while they
// span no solid (spans_volume). Throws InputError naming `what` after that.
std::vector<Eigen::Vector3d> random_polyhedron_points(std::size_t n, const Vec3a& aspect, Rng& rng,
                                                      const std::string& what);

// A rotation drawn uniformly (Haar measure) from three uniform numbers (K. Shoemake, "Uniform
// random rotations", Graphics Gems III, 1992).
Eigen::Quaterniond random_rotation(Rng& rng);

// The unit shape of the convex hull of `points`, in the points' own axes: its corners minus the
// hull's centroid, divided by the largest distance of a corner from it. Throws InputError
// naming `what` when the points span no solid or GrainShapes refuses the hull.
std::vector<Eigen::Vector3d> unit_shape(const std::vector<Eigen::Vector3d>& points,
                                        const std::string& what);

class ShapeDraws {
 public:
  // `given`: a given shape's points (a file's vertices, read by the caller), named `what` in
  // messages; empty for the shape's own `points`. Unused for random polyhedra.
  ShapeDraws(const GrainShapeConfig& shape, std::uint64_t block_seed,
             const std::vector<Eigen::Vector3d>& given = {}, const std::string& what = "");
  // Draw the next grain's shape (random polyhedra; a given shape stays) and turn.
  void next();
  // The current grain's unit shape, and its turn (world from the points' axes).
  const std::vector<Eigen::Vector3d>& unit() const { return unit_; }
  const Eigen::Quaterniond& turn() const { return turn_; }
  // Whether each grain has a shape of its own (random polyhedra).
  bool random_shapes() const { return shape_.kind == GrainShapeConfig::Kind::kRandomPolyhedron; }

 private:
  const GrainShapeConfig& shape_;
  Rng rng_;
  std::vector<Eigen::Vector3d> unit_;
  Eigen::Quaterniond turn_ = Eigen::Quaterniond::Identity();
};

}  // namespace sable
