// Polyhedral grains in a World: adding them, and their inertia (the shapes' table is
// geometry/grain_shapes.hpp, World::shapes).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "sable/geometry/grain_shapes.hpp"
#include "sable/world/world.hpp"

namespace sable {

// Append a polyhedral grain of shape row `shape`, its centroid at `position`, turned by
// `orientation`, its density `density` (kg/m^3). Throws InputError for a shape row out of
// range or a density that is not a positive number.
ParticleId add_polyhedral_grain(World<3>& w, std::uint32_t shape, const Eigen::Vector3d& position,
                                const Eigen::Quaterniond& orientation, double density,
                                MaterialIndex material, bool is_fixed = false);

// The grain whose corners are `points` (world frame) where they are: a new row of the table
// (GrainShapes::add), the grain at its centroid, turned by its frame.
ParticleId add_polyhedral_grain(World<3>& w, const std::vector<Eigen::Vector3d>& points,
                                double density, MaterialIndex material, bool is_fixed = false);

// Grain k's principal moments (kg m^2, body axes): its shape's per unit density times its
// density (mass / volume).
inline Eigen::Vector3d principal_inertia(const World<3>& w, std::size_t k) {
  return w.shapes[w.particles.shape_index[k]].moments(w.particles.mass[k]);
}

}  // namespace sable
