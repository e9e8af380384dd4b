// Percolation of the pressure phases of a sample: clusters of grains of one sign.
//
// Given one value per grain (e.g. the particle pressure, positive in compression), the grains
// with value > 0 form the "positive" phase and those with value < 0 the "negative" one (value
// 0: neither). Two grains of the same phase belong to the same cluster when a path of contacts
// joins them through grains of that phase; the contacts are the Sample's grain-grain contacts
// (the force-carrying ones) plus an optional extra edge list (e.g. liquid bridges).
//
// Spanning (box-slab rule): the box is grain_bounds(sample); a grain touches the lower face of
// axis d when x_d - r <= lo_d + slab, the upper face when x_d + r >= hi_d - slab. A cluster spans
// axis d when it holds a grain touching each face (one grain may touch both). The slab
// thickness defaults to the largest grain diameter. A phase percolates along d when one of its
// clusters spans d.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "sable/analysis/report.hpp"
#include "sable/analysis/sample.hpp"

namespace sable {

struct PercolationOptions {
  double slab = 0.0;  // face slab thickness (m); 0: the largest grain diameter
  std::vector<std::array<std::uint32_t, 2>> extra_edges;  // more grain pairs that connect
};

struct PercolationCluster {
  std::uint32_t label = 0;      // the smallest grain slot in the cluster
  std::size_t size = 0;         // grains
  std::array<bool, 3> spans{};  // per axis (z unused in 2D)
};

struct PercolationPhase {
  std::string name;  // "positive" or "negative"
  std::size_t grains = 0;
  std::vector<PercolationCluster> clusters;  // by increasing label
  std::size_t largest = 0;                   // size of the largest cluster (0 if none)
  std::array<bool, 3> largest_spans{};       // the largest cluster (first by label on a tie)
  std::array<bool, 3> percolates{};          // some cluster spans
};

struct Percolation {
  int dim = 3;
  double slab = 0.0;
  std::vector<double> box_lo, box_hi;  // grain_bounds of the sample
  std::vector<std::int8_t> phase;      // per grain: +1, -1, 0 (value 0)
  std::vector<std::int64_t> label;     // per grain: its cluster's label, -1 for phase 0
  PercolationPhase positive, negative;
};

// Throws InputError when `value` does not hold one finite value per grain, the sample has no
// grains, the slab is negative or an extra edge names a missing grain.
template <int D>
Percolation percolation(const Sample<D>& s, const std::vector<double>& value,
                        const PercolationOptions& opt = {});

Summary summary(const Percolation& p);
Table table(const Percolation& p);          // per grain: slot, phase, label
Table cluster_table(const Percolation& p);  // per cluster: phase, label, size, spans_x, ...

}  // namespace sable
