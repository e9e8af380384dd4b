// Grain generation: where grains start and how large they are.
//
// Generators produce plain (position, radius) lists; the scenario builder turns them into
// grains. Every random draw comes from a seeded generator, so a scenario with a seed always
// produces the same grains, bit for bit.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "sable/generation/grains_config.hpp"

namespace sable {

struct GrainSeed {
  Vec3a x{0, 0, 0};
  double radius = 0.0;
};

// Whether a grain of radius r at x may not be placed (it would overlap a wall or sit inside
// a body); the lattice skips such sites and random insertion draws again. Empty: none.
using Blocked = std::function<bool(const Vec3a& x, double r)>;

// Generate the grains of one [[grains]] block. `dim` is 2 or 3; `seed` the block's seed.
// Throws InputError (naming block.loc) when the block cannot be satisfied, e.g. a region too
// small for `count` grains.
std::vector<GrainSeed> generate_grains(const GrainsConfig& block, int dim, std::uint64_t seed,
                                       const std::vector<GrainSeed>& existing,
                                       const Blocked& blocked = {});

// Read grains from a LAMMPS/LIGGGHTS data file (atom_style granular/sphere: the "Atoms"
// section lines are `id type diameter density x y z`), sorted by id.
std::vector<GrainSeed> read_lammps_data(const std::string& path, int dim);

}  // namespace sable
