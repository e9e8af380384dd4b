// The [[wall]] tables of a scenario and the wall keys of its stages (wall_velocity,
// wall_rotation); parse.cpp reads the rest. Mesh walls' surfaces are only described here
// (MeshConfig): the file is read and the surface made when the world is built (build.cpp).
#pragma once

#include <string>
#include <vector>

#include "sable/scenario/config.hpp"
#include "sable/scenario/toml_reader.hpp"

namespace sable::detail {

// The material a table's `material` key names, checked against the [[material]] tables
// (parse.cpp).
std::string material_ref(const Table& t, const std::vector<MaterialConfig>& materials);

// Every [[wall]] of `root` (cfg: the dimension, the solver, the materials, the scenario's path
// for relative mesh files), and in `names` every name a stage may use for them: wall names
// and box plane names (NAME.xlo, ...).
std::vector<WallConfig> parse_walls(const Table& root, const ScenarioConfig& cfg,
                                    std::vector<std::string>& names);

// A stage's wall_velocity = { NAME = [...] } (a box name or box plane names too).
void parse_wall_velocity(const Table& s, StageConfig& st, const std::vector<std::string>& names,
                         int dim);

// A stage's wall_rotation = { NAME = { point, axis, rate } }: NAME a wall that is not a box.
// cfg: the dimension, the solver and the walls, read before the stages.
void parse_wall_rotation(const Table& s, StageConfig& st, const ScenarioConfig& cfg);

}  // namespace sable::detail
