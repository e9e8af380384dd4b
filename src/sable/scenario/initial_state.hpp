// The grains a scenario starts with must be a state the solvers can start from
// (docs/reliability.md, "Starting states"). A grain whose centre lies behind a wall (below
// the floor, outside a cylinder, or every grain behind a wall whose normal was flipped) is
// pushed through it at once; two grains at the same position have no contact normal; an
// overlap of a tenth of a radius releases its elastic energy in one contact time and shoots
// the grains off. None of these is a physical starting state, so `sable check` and `sable run`
// refuse them, naming the grains. Fixed grains are exempt among themselves and from walls:
// nothing moves them.
#pragma once

#include "sable/scenario/config.hpp"
#include "sable/world/world.hpp"

namespace sable {

// Throws InputError naming up to five offending grains (id, position, by how much) and how
// many there are: centres behind a wall; grains overlapping a wall or another grain by more
// than simulation.initial_overlap of the (smaller) radius; grains at the same position.
template <int D>
void check_initial_state(const ScenarioConfig& cfg, const World<D>& world);

}  // namespace sable
