// Mass properties of a solid bounded by a closed triangle surface: volume, centroid and the
// inertia tensor about the centroid, exact (to rounding) for any closed polyhedron, convex or
// not. The volume integrals of 1, x, y, z, x^2, y^2, z^2, xy, yz and zx are turned into sums
// over the boundary triangles by the divergence theorem, each triangle's share a polynomial of
// its corners (D. Eberly, "Polyhedral Mass Properties (Revisited)", 2002; B. Mirtich, "Fast
// and Accurate Computation of Polyhedral Mass Properties", 1996). Angular grains take their
// mass, centre and body-frame inertia from here: no sphere shortcut.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace sable {

struct PolyhedronMass {
  double volume = 0.0;  // m^3: the mass at unit density
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  // About the centroid, per unit density (m^5): times the density, kg m^2. Products of
  // inertia enter with their sign (I_xy = -integral of x y).
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
};

// The triangles index `vertices` and wind counterclockwise seen from outside (their normals
// (b - a) x (c - a) point out of the solid). Throws InputError when the surface encloses no
// volume, or a negative one (the triangles wind inward), or an index is out of range;
// `what` names the shape in the message.
PolyhedronMass polyhedron_mass(const std::vector<Eigen::Vector3d>& vertices,
                               const std::vector<std::array<std::uint32_t, 3>>& triangles,
                               const char* what = "polyhedron");

}  // namespace sable
