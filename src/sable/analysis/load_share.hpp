// Who carries the weight of the grains above a horizontal level: the grains below (through the
// cut), each wall, and the grains' own momentum rate.
//
// For the set A of free grains whose centre lies above the level (x . up > Z, up = -g / |g|),
// Newton's second law of each grain, summed over A, gives along up
//   sum_A m a.up = F_cut + sum_w F_w + F_fixed - W,
// because the contacts between two grains of A cancel in pairs (Newton's third law). So
//   W = F_cut + sum_w F_w + F_fixed - sum_A m a.up
// holds exactly at any instant for the forces the solver integrated, whatever the state:
//  - W = sum_A m |g|, the weight of A (> 0);
//  - F_cut = the up-component of the forces on grains of A from free grains below the level:
//    the exact planar cut (contacts whose two centres lie on either side). It equals the
//    integral of the contact part of sigma_zz over the cross-section, and carries the load
//    upwards when > 0;
//  - F_w = the up-component of the force wall w's contacts exert on grains of A (> 0: the
//    wall holds them up: a side wall's friction, a floor, a mesh body's support);
//  - F_fixed = the same from fixed grains, on either side of the level (supports, like walls);
//  - sum_A m a.up = the momentum rate of A along up (0 at rest).
// The residual W - F_cut - sum F_w - F_fixed + sum_A m a.up is the consistency check: zero
// to round-off. Each support's share is F / W.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "sable/analysis/report.hpp"
#include "sable/analysis/sample.hpp"

namespace sable {

struct LoadShare {
  double time = 0.0, level = 0.0;
  std::size_t grains_above = 0, cut_contacts = 0;
  double weight = 0.0, cut = 0.0, fixed = 0.0, momentum_rate = 0.0;  // N (2D: per thickness)
  std::vector<std::string> wall_names;                               // the sample's walls, in order
  std::vector<double> wall_support;                                  // F_w, by wall
  double walls() const;
  double residual() const;
};

// Throws InputError (naming s.source) for a sample without gravity or whose contacts name
// grains it does not hold.
template <int D>
LoadShare load_share(const Sample<D>& s, double level);

// load_share.csv: one row per snapshot (time, grains above, W, F_cut, each wall, fixed grains,
// momentum rate, residual).
Table load_share_table(const std::vector<LoadShare>& rows);
// The means over snapshots with their standard deviations, and each support's share of W.
Summary load_share_summary(const std::vector<LoadShare>& rows);

}  // namespace sable
