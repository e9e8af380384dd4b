// The wall shapes: one row per shape (geometry/walls.hpp lists what a shape provides).
#pragma once

#include <variant>

#include "sable/geometry/cylinder_wall.hpp"
#include "sable/geometry/mesh_wall.hpp"
#include "sable/geometry/plane_wall.hpp"

namespace sable {

template <int D>
using WallShape = std::variant<PlaneShape<D>, CylinderShape<D>, MeshShape<D>>;

}  // namespace sable
