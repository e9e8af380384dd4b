// From a validated ScenarioConfig to a ready World<D>: materials, contact law, walls, grains,
// time step. The world is not initialised (no neighbour list yet): the solver does that, or a
// snapshot supplies it when resuming.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "sable/scenario/config.hpp"
#include "sable/world/domain.hpp"
#include "sable/world/solver.hpp"
#include "sable/world/world.hpp"

namespace sable {

// Everything but the grains. Used on its own when resuming: grains come from the snapshot.
template <int D>
void build_model(const ScenarioConfig& cfg, World<D>& world);

// Generate and add the grains of every [[grains]] block, and check the state they start in
// (scenario/initial_state.hpp) and their masses: InputError if it is not one to start from.
template <int D>
void build_grains(const ScenarioConfig& cfg, World<D>& world);

// The automatic time step: dt_safety times the Rayleigh time of the smallest grain (Hertz), or
// times sqrt(m/kn) of the lightest grain (linear law). Explained in docs/contact-laws.md.
template <int D>
double automatic_time_step(const ScenarioConfig& cfg, const World<D>& world);

// The DEM time step against the bounds kTimeStepWarning and kTimeStepError (config.hpp) times
// the critical time of automatic_time_step (dt_safety = 1): an InputError above the second,
// a warning to print above the first. Contact dynamics has no such bound (rigid grains).
template <int D>
std::optional<std::string> check_time_step(const ScenarioConfig& cfg, const World<D>& world);

// The time step and neighbour skin the scenario asks for the world's grains: simulation.dt
// (else the automatic one) and simulation.skin (else half the largest radius). Used when the
// grains are built and when a snapshot is resumed.
template <int D>
double scenario_time_step(const ScenarioConfig& cfg, const World<D>& world);
template <int D>
double scenario_skin(const ScenarioConfig& cfg, const World<D>& world);

// Indices of the walls a stage's `wall_velocity` key names (a box name means all its planes).
template <int D>
std::vector<std::size_t> walls_named(const World<D>& world, const std::string& key);

// The time stepper the scenario asks for (simulation.solver), bound to `world`, stepping the
// grains of `domain` (null: all of them, a serial run). Contact dynamics and wet stages are
// not decomposed: a distributed domain refuses them (InputError naming the key).
template <int D>
std::unique_ptr<Solver> make_solver(const ScenarioConfig& cfg, World<D>& world,
                                    Domain<D>* domain = nullptr);

}  // namespace sable
