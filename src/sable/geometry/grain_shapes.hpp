// The shapes of a run's polyhedral grains: one table per World (World::shapes), each grain naming
// its row (ParticleStore::shape_index). Grains of one shape share a row; a generator of random
// polyhedra gives each grain its own.
//
// A row holds the shape in its body frame: the centroid at the origin and the principal axes
// of inertia along x, y, z, so that a grain's state is its centroid's position, a unit
// quaternion (body -> world) and the diagonal inertia of core/rigid_rotation.hpp. Volume and
// inertia are exact for the hull (geometry/polyhedron_mass.hpp), per unit density; a grain's
// are these times its density (mass / volume). Nothing about a polyhedron is taken from a
// sphere: its `radius` in the store is only the bounding sphere the broad phase uses.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "sable/geometry/convex_polyhedron.hpp"

namespace sable {

struct PolyhedronShape {
  // The body-frame points the solid was built from (the hull's, as given to add_body_frame):
  // a snapshot keeps these, so that a resumed run builds the same solid to the last bit.
  std::vector<Eigen::Vector3d> points;
  ConvexPolyhedron solid;  // body frame: centroid at the origin, principal axes
  double volume = 0.0;     // m^3
  // The principal moments about the centroid per unit density (m^5), along the body's x, y, z.
  Eigen::Vector3d inertia = Eigen::Vector3d::Zero();

  // A grain's principal moments (kg m^2, body axes): its density, mass / volume, times these.
  Eigen::Vector3d moments(double mass) const { return inertia * (mass / volume); }
};

// Where a shape's body frame sits in the frame its points were given in:
// point = centroid + frame * body point.
struct ShapePlacement {
  std::uint32_t index = 0;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  Eigen::Quaterniond frame = Eigen::Quaterniond::Identity();
};

class GrainShapes {
 public:
  // The convex hull of `points` (any frame, any order; interior points are dropped), moved
  // into its body frame. When the hull's inertia about its centroid is diagonal already (to
  // 1e-12 of its trace: a cube or box given along its axes), the axes are kept as they are
  // (frame = identity); otherwise they are the tensor's eigenvectors, smallest moment first,
  // turned to a right-handed frame. Throws InputError, `what` naming the shape, when the
  // points span no volume or a face would have over ConvexPolyhedron::kMaxFaceCorners corners.
  ShapePlacement add(const std::vector<Eigen::Vector3d>& points,
                     const char* what = "polyhedral grain");
  // A shape given in its body frame (a snapshot's row): its hull's corners, kept as given,
  // with its volume and principal moments per unit density.
  std::uint32_t add_body_frame(const std::vector<Eigen::Vector3d>& vertices, double volume,
                               const Eigen::Vector3d& inertia, const char* what);

  const PolyhedronShape& operator[](std::size_t k) const { return shapes_[k]; }
  std::size_t size() const { return shapes_.size(); }
  bool empty() const { return shapes_.empty(); }

 private:
  std::vector<PolyhedronShape> shapes_;
};

}  // namespace sable
