// Each wall's total force and torque over its contacts, summed exactly (core/exact_sum.hpp):
// the same bits whatever the order in which the contacts are added, so whatever the thread,
// the slot order or the process that holds them. The sums are rounded once, when read.
#pragma once

#include <cstddef>
#include <vector>

#include "sable/core/exact_sum.hpp"
#include "sable/core/space.hpp"
#include "sable/geometry/walls.hpp"

namespace sable {

template <int D>
class WallTotals {
 public:
  using Vec = typename Space<D>::Vec;
  using Rot = typename Space<D>::Rot;
  static constexpr int kRot = D == 3 ? 3 : 1;
  static constexpr int kParts = D + kRot;  // a wall's components: force, then torque

  void reset(std::size_t walls) { sums_.assign(walls * kParts, {}); }
  std::size_t size() const { return sums_.size() / kParts; }

  void add_force(std::size_t wall, const Vec& f) {
    for (int d = 0; d < D; ++d) component(wall, d).add(f[d]);
  }
  void add_torque(std::size_t wall, const Rot& t) {
    if constexpr (D == 3) {
      for (int d = 0; d < 3; ++d) component(wall, D + d).add(t[d]);
    } else {
      component(wall, D).add(t);
    }
  }
  // Adds another set of totals over the same walls (partial sums of other threads or ranks).
  void merge(const WallTotals& o) {
    for (std::size_t k = 0; k < sums_.size(); ++k) sums_[k].merge(o.sums_[k]);
  }

  // Component c of a wall's total: force d = 0 .. D-1, then torque (one component in 2D).
  ExactSum& component(std::size_t wall, int c) { return sums_[wall * kParts + c]; }
  const ExactSum& component(std::size_t wall, int c) const { return sums_[wall * kParts + c]; }
  // Every component of every wall, wall by wall (for a sum over processes).
  ExactSum* data() { return sums_.data(); }
  std::size_t components() const { return sums_.size(); }

  // Each wall's force and torque set to its totals, rounded once.
  void store(std::vector<Wall<D>>& walls) const {
    for (std::size_t w = 0; w < walls.size(); ++w) {
      walls[w].force = force(w);
      walls[w].torque = torque(w);
    }
  }

  Vec force(std::size_t wall) const {
    Vec f;
    for (int d = 0; d < D; ++d) f[d] = component(wall, d).value();
    return f;
  }
  Rot torque(std::size_t wall) const {
    if constexpr (D == 3) {
      return Rot(component(wall, 3).value(), component(wall, 4).value(),
                 component(wall, 5).value());
    } else {
      return component(wall, D).value();
    }
  }

 private:
  std::vector<ExactSum> sums_;
};

}  // namespace sable
