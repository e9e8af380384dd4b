// The force on each element of a mesh wall, from the contacts' forces the last evaluation
// left in the neighbour list (either solver writes every wall entry's force there, zero for
// an entry apart): an output quantity, derived when written rather than kept up each step.
#pragma once

#include <cstddef>
#include <vector>

#include "sable/world/world.hpp"

namespace sable {

// Per element of wall w (empty for a wall that is not a mesh): minus the sum of its entries'
// forces on their grains, in list order. These sum to the wall's force up to round-off.
template <int D>
std::vector<typename Space<D>::Vec> element_forces(const World<D>& world, std::size_t w) {
  const Wall<D>& wall = world.walls[w];
  std::vector<typename Space<D>::Vec> out(wall.is_mesh() ? wall.elements() : 0, Space<D>::zero());
  if (out.empty()) return out;
  const auto& wl = world.neighbors.wall_pairs;
  for (std::size_t k = 0; k < wl.size(); ++k)
    if (wl.wall[k] == w) out[wl.element[k]] -= wl.force[k];
  return out;
}

}  // namespace sable
