// A snapshot as an analysis Sample: the World is rebuilt from the scenario text stored in the
// snapshot (materials, walls, the contact law), then its state is read. The analyses take
// these loaders from their caller (analysis/sample.hpp, SampleLoaders): building a World from
// a scenario sits above them.
#pragma once

#include <string>

#include "sable/analysis/sample.hpp"

namespace sable {

// Throws InputError naming the file if it is missing, truncated or not a Sable snapshot, or
// of the other dimension than D.
template <int D>
Sample<D> load_sample(const std::string& snapshot_path);

// load_sample<2> and load_sample<3>, for run_analysis.
SampleLoaders snapshot_loaders();

}  // namespace sable
