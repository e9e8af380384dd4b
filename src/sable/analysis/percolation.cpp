#include "sable/analysis/percolation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "sable/core/error.hpp"

namespace sable {

namespace {

// Union-find with path halving; the root of a set is always its smallest element, so the
// labels come out the same whatever the order of the edges.
class DisjointSets {
 public:
  explicit DisjointSets(std::size_t n) : parent_(n) {
    std::iota(parent_.begin(), parent_.end(), std::uint32_t{0});
  }
  std::uint32_t find(std::uint32_t a) {
    while (parent_[a] != a) {
      parent_[a] = parent_[parent_[a]];
      a = parent_[a];
    }
    return a;
  }
  void join(std::uint32_t a, std::uint32_t b) {
    a = find(a);
    b = find(b);
    if (a < b) parent_[b] = a;
    if (b < a) parent_[a] = b;
  }

 private:
  std::vector<std::uint32_t> parent_;
};

template <int D>
void check_input(const Sample<D>& s, const std::vector<double>& value,
                 const PercolationOptions& opt) {
  if (s.size() == 0)
    throw InputError(fmt::format("{}: the sample holds no grains to find clusters in", s.source));
  if (value.size() != s.size())
    throw InputError(fmt::format("percolation: {} values for {} grains", value.size(), s.size()));
  for (std::size_t g = 0; g < value.size(); ++g)
    if (!std::isfinite(value[g]))
      throw InputError(fmt::format("percolation: the value of grain {} is not finite", g));
  if (!(opt.slab >= 0.0) || !std::isfinite(opt.slab))
    throw InputError(fmt::format("percolation: the slab thickness must be >= 0, got {}", opt.slab));
  for (const auto& e : opt.extra_edges)
    if (e[0] >= s.size() || e[1] >= s.size())
      throw InputError(fmt::format("percolation: extra edge ({}, {}) names a grain past the {}",
                                   e[0], e[1], s.size()));
  check_contact_indices(s);
}

// The clusters of one phase (sign), given the union-find over all same-phase edges.
template <int D>
PercolationPhase collect(const Sample<D>& s, const Percolation& p, std::int8_t sign,
                         DisjointSets& sets, const Region<D>& box) {
  PercolationPhase ph;
  ph.name = sign > 0 ? "positive" : "negative";
  std::vector<std::int64_t> index(s.size(), -1);   // root -> position in ph.clusters
  std::vector<std::array<std::uint8_t, 3>> faces;  // per cluster and axis: 1 low, 2 high face
  for (std::size_t g = 0; g < s.size(); ++g) {
    if (p.phase[g] != sign) continue;
    ++ph.grains;
    const std::uint32_t root = sets.find(static_cast<std::uint32_t>(g));
    if (index[root] < 0) {  // roots are the smallest slots: clusters appear by increasing label
      index[root] = static_cast<std::int64_t>(ph.clusters.size());
      ph.clusters.push_back({root, 0, {}});
      faces.push_back({0, 0, 0});
    }
    const auto at = static_cast<std::size_t>(index[root]);
    ++ph.clusters[at].size;
    for (int d = 0; d < D; ++d) {
      const auto dd = static_cast<std::size_t>(d);
      if (s.x[g][d] - s.radius[g] <= box.lo[d] + p.slab) faces[at][dd] |= 1;
      if (s.x[g][d] + s.radius[g] >= box.hi[d] - p.slab) faces[at][dd] |= 2;
    }
  }
  for (std::size_t k = 0; k < ph.clusters.size(); ++k) {
    auto& cl = ph.clusters[k];
    for (std::size_t d = 0; d < 3; ++d) {
      cl.spans[d] = faces[k][d] == 3;
      ph.percolates[d] = ph.percolates[d] || cl.spans[d];
    }
    if (cl.size > ph.largest) {
      ph.largest = cl.size;
      ph.largest_spans = cl.spans;
    }
  }
  return ph;
}

}  // namespace

template <int D>
Percolation percolation(const Sample<D>& s, const std::vector<double>& value,
                        const PercolationOptions& opt) {
  check_input(s, value, opt);
  Percolation p;
  p.dim = D;
  const Region<D> box = grain_bounds(s);
  p.box_lo.assign(box.lo.data(), box.lo.data() + D);
  p.box_hi.assign(box.hi.data(), box.hi.data() + D);
  p.slab = opt.slab;
  if (p.slab == 0.0)
    for (double r : s.radius) p.slab = std::max(p.slab, 2.0 * r);
  p.phase.resize(s.size());
  for (std::size_t g = 0; g < s.size(); ++g)
    p.phase[g] = static_cast<std::int8_t>(value[g] > 0.0 ? 1 : (value[g] < 0.0 ? -1 : 0));
  // Grains of the same (non-zero) phase joined by a contact or an extra edge: one cluster.
  DisjointSets sets(s.size());
  const auto link = [&](std::uint32_t a, std::uint32_t b) {
    if (p.phase[a] != 0 && p.phase[a] == p.phase[b]) sets.join(a, b);
  };
  const auto& c = s.contacts;
  for (std::size_t k = 0; k < c.size(); ++k)
    if (!c.is_wall(k)) link(c.i[k], c.j[k]);
  for (const auto& e : opt.extra_edges) link(e[0], e[1]);
  p.positive = collect(s, p, 1, sets, box);
  p.negative = collect(s, p, -1, sets, box);
  p.label.assign(s.size(), -1);
  for (std::size_t g = 0; g < s.size(); ++g)
    if (p.phase[g] != 0) p.label[g] = sets.find(static_cast<std::uint32_t>(g));
  return p;
}

namespace {

Summary phase_summary(const PercolationPhase& ph, int dim) {
  static const char* const axes[3] = {"x", "y", "z"};
  Summary s;
  s.add("grains", ph.grains).add("clusters", ph.clusters.size()).add("largest", ph.largest);
  std::vector<double> sizes;
  for (const auto& cl : ph.clusters) sizes.push_back(static_cast<double>(cl.size));
  std::sort(sizes.begin(), sizes.end(), std::greater<>());
  if (sizes.size() > 10) sizes.resize(10);  // the full list is in the cluster table
  s.add("largest_sizes", sizes);
  Summary spans, perc;
  for (std::size_t d = 0; d < static_cast<std::size_t>(dim); ++d) {
    spans.add(axes[d], ph.largest_spans[d]);
    perc.add(axes[d], ph.percolates[d]);
  }
  s.add("largest_spans", spans).add("percolates", perc);
  return s;
}

}  // namespace

Summary summary(const Percolation& p) {
  Summary s;
  s.add("grains", p.phase.size()).add("slab_m", p.slab);
  s.add("box_lo_m", p.box_lo).add("box_hi_m", p.box_hi);
  s.add("positive", phase_summary(p.positive, p.dim));
  s.add("negative", phase_summary(p.negative, p.dim));
  return s;
}

Table table(const Percolation& p) {
  std::vector<double> slot, phase, label;
  for (std::size_t g = 0; g < p.phase.size(); ++g) {
    slot.push_back(static_cast<double>(g));
    phase.push_back(p.phase[g]);
    label.push_back(static_cast<double>(p.label[g]));
  }
  Table t;
  t.add("slot", slot);
  t.add("phase", phase);
  t.add("label", label);
  return t;
}

Table cluster_table(const Percolation& p) {
  std::vector<double> phase, label, size;
  std::array<std::vector<double>, 3> spans;
  for (const auto* ph : {&p.positive, &p.negative})
    for (const auto& cl : ph->clusters) {
      phase.push_back(ph == &p.positive ? 1.0 : -1.0);
      label.push_back(cl.label);
      size.push_back(static_cast<double>(cl.size));
      for (std::size_t d = 0; d < 3; ++d) spans[d].push_back(cl.spans[d] ? 1.0 : 0.0);
    }
  Table t;
  t.add("phase", phase);
  t.add("label", label);
  t.add("size", size);
  static const char* const names[3] = {"spans_x", "spans_y", "spans_z"};
  for (std::size_t d = 0; d < static_cast<std::size_t>(p.dim); ++d) t.add(names[d], spans[d]);
  return t;
}

template Percolation percolation<2>(const Sample<2>&, const std::vector<double>&,
                                    const PercolationOptions&);
template Percolation percolation<3>(const Sample<3>&, const std::vector<double>&,
                                    const PercolationOptions&);

}  // namespace sable
