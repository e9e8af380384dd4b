// What a wall shape answers for a grain centre: the feature of the surface nearest to it.
#pragma once

#include <cstdint>
#include <vector>

#include "sable/core/space.hpp"

namespace sable {

// For a grain centre x and one list element of a wall (a mesh triangle; the whole surface for
// the analytic shapes): whether the element holds the surface point nearest to x (`active`;
// a mesh shares each edge and vertex between elements, and only one of them may answer for
// it), the distance `dist` from that point to x (signed for planes and cylinders: negative
// behind the surface), the unit normal n from the surface towards x, and the feature's id,
// which keys the contact's tangential history. The contact point of a grain of radius r is
// x - (r - delta / 2) n with delta = r - dist, as for a grain pair.
template <int D>
struct WallFeature {
  using Vec = typename Space<D>::Vec;
  Vec n = Vec::Zero();
  double dist = 0.0;
  std::uint32_t feature = 0;
  bool active = true;
};

}  // namespace sable
