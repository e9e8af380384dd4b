// Recursive coordinate bisection (RCB) of the domain among P processes, as LAMMPS' `balance
// rcb` does: the box is cut across its longest axis where the grains below the cut are the
// share of the processes below it (floor(P / 2) of P), then each half likewise, until each
// process has a box. The cut only decides who steps which grain: no result depends on it
// (world/domain.hpp), so it may be made again at any list build.
//
// The grains' positions may be spread over the processes: the cut is found from histograms of
// the positions along the axis (kBins bins a box), summed over every process by `reduce`,
// so every process finds the same cuts. The grains may be weighed by their work (MpiDomain:
// the process's measured time shared by the grains' list entries), as LAMMPS' time weights.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "sable/core/space.hpp"

namespace sable {

template <int D>
class Rcb {
 public:
  using Vec = typename Space<D>::Vec;
  struct Box {
    Vec lo, hi;
  };
  static constexpr int kBins = 1024;
  // Sums an array of counts over every process, in place (serial: nothing to do).
  using Reduce = std::function<void(std::vector<std::int64_t>&)>;

  // Cuts [lo, hi] into `parts` boxes, weighing the grains at `points` (this process's share)
  // and everyone else's through `reduce`: each grain by its entry of `weights` (integers, so
  // that the sum over processes, and so the cuts, are the same on every process), or 1 when
  // `weights` is empty.
  // `bias` scales the share of the lower half of each cut (1: even; tests force lopsided cuts
  // with less, which must change no result).
  void cut(const Vec& lo, const Vec& hi, int parts, const std::vector<Vec>& points,
           const Reduce& reduce, double bias = 1.0, const std::vector<std::int64_t>& weights = {});

  int parts() const { return static_cast<int>(boxes_.size()); }
  const Box& box(int part) const { return boxes_[static_cast<std::size_t>(part)]; }
  // The part whose box holds x; a point outside the domain (or NaN) goes to the part whose box
  // is nearest along each cut.
  int owner(const Vec& x) const;
  // The squared distance from x to part's box (0 inside), the box reaching to infinity past
  // each face it shares with the domain: a grain that left the domain still belongs to, and is
  // near, the boxes along its side.
  double distance2(const Vec& x, int part) const;

 private:
  struct Node {
    int axis = -1;  // -1: a leaf
    double at = 0.0;
    int below = -1, above = -1;  // children (nodes_ indices)
    int part = -1;               // a leaf's part
  };
  std::vector<Node> nodes_;
  std::vector<Box> boxes_;
  Vec lo_ = Vec::Zero(), hi_ = Vec::Zero();  // the domain
};

}  // namespace sable
