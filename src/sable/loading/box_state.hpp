// The state of a sample held in a box of plane walls: what a stress- or strain-controlled stage
// reports (series.csv, the stage summary) and what tests and analyses check.
//
// The box is found from the walls alone: on every axis, the innermost pair of facing
// axis-aligned plane walls (a wall whose normal is +e_d bounds the sample from below on axis d,
// one with -e_d from above), as for the wall areas of loading/servo.hpp. A world without such a
// pair on every axis (a silo open at the top, a cylinder) has no box.
//
// - stress[d]: the mean of the two facing walls' normal stresses wall_normal_stress (Pa,
//   compression positive): sigma_dd of the sample as the walls see it.
// - solid_fraction: the grains' volume over the box's (2D: disk areas over the box's area).
//   Every grain counts in full: a grain pressed against a wall pokes through it only by its
//   overlap (a small fraction of its radius in a stiff packing), so the error is of the order
//   of that overlap times the wall contacts' share of the grains, negligible for the packings
//   this is for; a grain that escaped the box would count too (a run stops before that).
// - strain (box_strain): engineering strain per axis against a reference box,
//   eps_dd = (L0_d - L_d) / L0_d, POSITIVE IN COMPRESSION like the stresses. The runner's
//   reference is the box the scenario builds (its [[wall]] tables, i.e. the start of the run),
//   recomputed from the scenario when a run resumes, so a resumed run reports the same strain
//   as the uninterrupted one; the strain of one stage is the difference of two rows.
#pragma once

#include <array>
#include <cstddef>
#include <optional>

#include "sable/world/world.hpp"

namespace sable {

template <int D>
struct BoxState {
  using Vec = typename Space<D>::Vec;
  std::array<std::size_t, D> lo_wall{}, hi_wall{};  // wall indices, per axis
  Vec lo = Vec::Zero(), hi = Vec::Zero();           // the box's corners (m)
  Vec stress = Vec::Zero();                         // mean wall normal stress per axis (Pa)
  double volume = 0.0;                              // box volume (m^3; 2D: area * thickness)
  double grain_volume = 0.0;                        // grains' volume (m^3; 2D: x thickness)
  double solid_fraction = 0.0;                      // grain_volume / volume
  Vec extent() const { return hi - lo; }
};

// The sample's box now; nullopt when the walls do not form one (see above).
template <int D>
std::optional<BoxState<D>> measure_box(const World<D>& w);

// Engineering strain per axis, (L0 - L) / L0: positive in compression.
template <int D>
typename Space<D>::Vec box_strain(const BoxState<D>& now, const BoxState<D>& reference);

}  // namespace sable
