// When a loop over grains or contacts is worth a thread team. Waking OpenMP's team and joining
// it costs a few microseconds; below these sizes a loop runs on the calling thread. Every
// parallel loop gives the same bits on any number of threads (a max, an or, or per-thread
// blocks joined in order), so a threshold changes only the speed.
#pragma once

#include <cstddef>

namespace sable {

// Loops whose items each cost about as much as a grain's update or a contact's force (tens to
// hundreds of nanoseconds): the DEM solver's kick, drift and pair pass.
inline constexpr std::ptrdiff_t kMinParallelItems = 2048;

// Loops of a few nanoseconds an item (a max or an or over the grains, the binning of grains
// into the neighbour cells): twice as many items before the team pays for itself.
inline constexpr std::ptrdiff_t kMinParallelScan = 4096;

}  // namespace sable
