// A [[grains]] block's `shape` key (GrainShapeConfig; parse.cpp reads the rest of the block),
// and what a scenario with polyhedral grains may hold besides them. As in parse.cpp, every key
// is checked for its type and range; messages give file:line:column, the key's full name and
// what was expected. A shape file is only named here (its existence and kind checked): it is
// read when the grains are built (build.cpp), as a mesh wall's STL file is.
#pragma once

#include "sable/scenario/config.hpp"
#include "sable/scenario/toml_reader.hpp"

namespace sable::detail {

// The block `g`'s shape (round when it has no `shape` key). cfg: the dimension and the solver,
// read before the grains. Refuses a shape in 2D.
GrainShapeConfig parse_grain_shape(const Table& g, const ScenarioConfig& cfg);

// With polyhedral grains in any block: every block polyhedral, plane and box walls only, no
// rolling sub-model (what contact dynamics steps with polyhedra: cd/cd_polyhedra.cpp), and
// with DEM the linear law and no cohesion (dem/polyhedral_dem.hpp), so that `sable check`
// refuses what a run would. cfg: the grains, walls and contact read.
void check_polyhedral_scenario(const Table& root, const ScenarioConfig& cfg);

}  // namespace sable::detail
