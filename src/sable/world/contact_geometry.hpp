// Where a polyhedral contact acts: per entry of the neighbour lists, the normal, the contact
// point and the depth of the contact whose force the entry holds.
//
// A round pair's normal and point follow from the grains' centres and radii, so its entry keeps
// only the force; a polyhedral pair's follow from its manifold (the orientations, the faces),
// which an analysis cannot redo from the force alone. The solvers therefore write them beside
// the force once a step's forces are known, indexed like the lists (pairs[k] belongs to
// neighbors.pairs entry k, wall_pairs[k] to neighbors.wall_pairs entry k). They are outputs,
// like the force: nothing in a step reads them, and they stay empty while every grain is round.
#pragma once

#include <cstddef>
#include <vector>

#include "sable/core/space.hpp"

namespace sable {

template <int D>
struct EntryGeometry {
  using Vec = typename Space<D>::Vec;
  // Unit normal from grain i towards its partner (grain j, or into the wall).
  std::vector<Vec> normal;
  // The contact point less x_i, in the configuration where the force was computed (contact
  // dynamics: the start of the step; DEM: the step's end, where its forces are found).
  std::vector<Vec> arm;
  // The deepest manifold point's overlap along the normal: > 0 overlapping, < 0 an open gap
  // (contact dynamics keeps points within the step's reach).
  std::vector<double> depth;

  std::size_t size() const { return normal.size(); }
  void resize(std::size_t n) {
    normal.resize(n, Vec::Zero());
    arm.resize(n, Vec::Zero());
    depth.resize(n, 0.0);
  }
  void clear() {
    normal.clear();
    arm.clear();
    depth.clear();
  }
  void set(std::size_t k, const Vec& n, const Vec& a, double d) {
    normal[k] = n;
    arm[k] = a;
    depth[k] = d;
  }
};

template <int D>
struct ContactPoints {
  EntryGeometry<D> pairs, wall_pairs;
  bool empty() const { return pairs.size() == 0 && wall_pairs.size() == 0; }
  void clear() {
    pairs.clear();
    wall_pairs.clear();
  }
  // Whether it holds one row per entry of lists of these sizes.
  bool matches(std::size_t n_pairs, std::size_t n_wall_pairs) const {
    return pairs.size() == n_pairs && pairs.arm.size() == n_pairs &&
           pairs.depth.size() == n_pairs && wall_pairs.size() == n_wall_pairs &&
           wall_pairs.arm.size() == n_wall_pairs && wall_pairs.depth.size() == n_wall_pairs;
  }
};

}  // namespace sable
