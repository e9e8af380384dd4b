#include "sable/world/polyhedral_grains.hpp"

#include <fmt/format.h>

#include <cmath>

#include "sable/core/error.hpp"

namespace sable {

ParticleId add_polyhedral_grain(World<3>& w, std::uint32_t shape, const Eigen::Vector3d& position,
                                const Eigen::Quaterniond& orientation, double density,
                                MaterialIndex material, bool is_fixed) {
  if (shape >= w.shapes.size())
    throw InputError(
        fmt::format("polyhedral grain: shape {} of a table of {}", shape, w.shapes.size()));
  if (!(density > 0.0) || !std::isfinite(density))
    throw InputError(
        fmt::format("polyhedral grain: density {}; expected a positive number", density));
  const PolyhedronShape& s = w.shapes[shape];
  return w.particles.add_polyhedron(position, orientation.normalized(), shape, s.solid.radius(),
                                    density * s.volume, density * s.inertia, material, is_fixed);
}

ParticleId add_polyhedral_grain(World<3>& w, const std::vector<Eigen::Vector3d>& points,
                                double density, MaterialIndex material, bool is_fixed) {
  const ShapePlacement s = w.shapes.add(points);
  return add_polyhedral_grain(w, s.index, s.centroid, s.frame, density, material, is_fixed);
}

}  // namespace sable
