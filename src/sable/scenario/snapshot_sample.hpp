// A snapshot as an analysis Sample: the World is rebuilt from the scenario text stored in the
// snapshot (materials, walls, the contact law), then its state is read. The analyses take
// these loaders from their caller (analysis/sample.hpp, SampleLoaders): building a World from
// a scenario sits above them.
#pragma once

#include <string>

#include "sable/analysis/sample.hpp"
#include "sable/io/snapshot.hpp"
#include "sable/scenario/config.hpp"
#include "sable/world/world.hpp"

namespace sable {

// The scenario stored in snapshot `path`, parsed; InputError naming the file if it does not
// parse.
ScenarioConfig snapshot_scenario(const std::string& path);

// `w` rebuilt from snapshot `path`: the model from its stored scenario, then its state.
// Throws InputError naming the file if it is missing, damaged, not a Sable snapshot, or of
// the other dimension than D. Returns the stored scenario; `pos` (if given) gets the run's
// position.
template <int D>
ScenarioConfig load_world(const std::string& path, World<D>& w, RunPosition* pos = nullptr);

// Throws InputError naming the file if it is missing, truncated or not a Sable snapshot, or
// of the other dimension than D.
template <int D>
Sample<D> load_sample(const std::string& snapshot_path);

// load_sample<2> and load_sample<3>, for run_analysis.
SampleLoaders snapshot_loaders();

}  // namespace sable
