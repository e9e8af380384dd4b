#include "sable/mpi/rcb.hpp"

#include <algorithm>
#include <cmath>

namespace sable {

namespace {

// A box still to cut, and the processes [first, first + count) it holds.
template <int D>
struct Open {
  typename Rcb<D>::Box box;
  int first, count, node;
};

template <int D>
int longest_axis(const typename Rcb<D>::Box& b) {
  int axis = 0;
  for (int d = 1; d < D; ++d)
    if (b.hi[d] - b.lo[d] > b.hi[axis] - b.lo[axis]) axis = d;
  return axis;
}

int bin_of(double x, double lo, double hi, int bins) {
  const double q = std::floor((x - lo) / (hi - lo) * bins);
  return q > 0.0 ? (q < bins - 1.0 ? static_cast<int>(q) : bins - 1) : 0;  // NaN: bin 0
}

// The bin edge where a box is cut: the first with at least bias * below / count of the
// weight under it (with no grains, the box is cut in that proportion).
int cut_edge(const std::int64_t* counts, int bins, int below, int count, double bias) {
  std::int64_t total = 0;
  for (int b = 0; b < bins; ++b) total += counts[b];
  if (total == 0) return (bins * below) / count;
  std::int64_t under = 0;
  for (int b = 0; b < bins - 1; ++b) {
    under += counts[b];
    if (static_cast<double>(under) * count >= bias * static_cast<double>(total) * below)
      return b + 1;
  }
  return bins - 1;
}

}  // namespace

template <int D>
void Rcb<D>::cut(const Vec& lo, const Vec& hi, int parts, const std::vector<Vec>& points,
                 const Reduce& reduce, double bias, const std::vector<std::int64_t>& weights) {
  lo_ = lo;
  hi_ = hi;
  nodes_.assign(1, Node{});
  boxes_.assign(static_cast<std::size_t>(std::max(parts, 1)), Box{lo, hi});
  std::vector<Open<D>> open{{Box{lo, hi}, 0, std::max(parts, 1), 0}};
  std::vector<int> where(points.size(), 0);  // each point's open box (index into `open`)
  while (!open.empty()) {
    // One level: every open box of more than one part is cut, all from one reduction.
    std::vector<std::int64_t> counts(open.size() * kBins, 0);
    std::vector<int> axis(open.size());
    for (std::size_t o = 0; o < open.size(); ++o) axis[o] = longest_axis<D>(open[o].box);
    for (std::size_t k = 0; k < points.size(); ++k) {
      const auto o = static_cast<std::size_t>(where[k]);
      if (o >= open.size() || open[o].count < 2) continue;
      const Box& b = open[o].box;
      const int a = axis[o];
      counts[o * kBins + static_cast<std::size_t>(bin_of(points[k][a], b.lo[a], b.hi[a], kBins))] +=
          weights.empty() ? 1 : weights[k];
    }
    const bool splits =
        std::any_of(open.begin(), open.end(), [](const Open<D>& o) { return o.count > 1; });
    if (splits) reduce(counts);  // a level of leaves alone needs no sum
    std::vector<Open<D>> next;
    std::vector<int> child_of(open.size() * 2, -1);
    for (std::size_t o = 0; o < open.size(); ++o) {
      const Open<D>& op = open[o];
      Node& node = nodes_[static_cast<std::size_t>(op.node)];
      if (op.count < 2) {  // a leaf: its part's box
        node.part = op.first;
        boxes_[static_cast<std::size_t>(op.first)] = op.box;
        continue;
      }
      const int a = axis[o];
      const int below = op.count / 2;
      const int edge = cut_edge(&counts[o * kBins], kBins, below, op.count, bias);
      const double at = op.box.lo[a] + (op.box.hi[a] - op.box.lo[a]) * edge / kBins;
      node.axis = a;
      node.at = at;
      Box lower = op.box, upper = op.box;
      lower.hi[a] = at;
      upper.lo[a] = at;
      const int below_node = static_cast<int>(nodes_.size());
      const int above_node = below_node + 1;
      node.below = below_node;  // `node` is not used past the resize below
      node.above = above_node;
      nodes_.resize(nodes_.size() + 2);
      child_of[2 * o] = static_cast<int>(next.size());
      next.push_back({lower, op.first, below, below_node});
      child_of[2 * o + 1] = static_cast<int>(next.size());
      next.push_back({upper, op.first + below, op.count - below, above_node});
    }
    for (std::size_t k = 0; k < points.size(); ++k) {
      const auto o = static_cast<std::size_t>(where[k]);
      if (o >= open.size() || open[o].count < 2) {
        where[k] = -1;
        continue;
      }
      const Node& node = nodes_[static_cast<std::size_t>(open[o].node)];
      where[k] = child_of[2 * o + (points[k][node.axis] < node.at ? 0 : 1)];
    }
    open = std::move(next);
  }
}

template <int D>
int Rcb<D>::owner(const Vec& x) const {
  std::size_t n = 0;
  while (nodes_[n].axis >= 0)
    n = static_cast<std::size_t>(x[nodes_[n].axis] < nodes_[n].at ? nodes_[n].below
                                                                  : nodes_[n].above);
  return nodes_[n].part;
}

template <int D>
double Rcb<D>::distance2(const Vec& x, int part) const {
  const Box& b = boxes_[static_cast<std::size_t>(part)];
  double d2 = 0.0;
  for (int d = 0; d < D; ++d) {
    const double below = b.lo[d] > lo_[d] ? b.lo[d] - x[d] : 0.0;
    const double above = b.hi[d] < hi_[d] ? x[d] - b.hi[d] : 0.0;
    const double out = std::max({below, above, 0.0});
    d2 += out * out;
  }
  return d2;
}

template class Rcb<2>;
template class Rcb<3>;

}  // namespace sable
