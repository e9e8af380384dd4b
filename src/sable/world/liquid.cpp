#include "sable/world/liquid.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "sable/core/error.hpp"
#include "sable/core/exact_sum.hpp"

namespace sable {
namespace {

struct Eligible {
  std::size_t count = 0;  // a prefix of `order`
  double share_sum = 0.0;
};

// The largest self-consistent eligible set (see liquid.hpp): a prefix of the pairs sorted by
// key = (max(gap, 0) / (1 + theta/2))^3 / d. Touching pairs have key 0 and come first, so
// the contacts alone are the prefix of keys 0.
Eligible eligible_prefix(const std::vector<std::size_t>& order, const std::vector<double>& key,
                         const std::vector<double>& share, double volume, LiquidPairs pairs) {
  Eligible e;
  double sum = 0.0;
  for (std::size_t m = 0; m < order.size(); ++m) {
    const std::size_t k = order[m];
    if (pairs == LiquidPairs::kContacts && key[k] > 0.0) break;
    sum += share[k];
    if (key[k] * sum > volume) break;  // key_k <= V / S, without dividing
    e = {m + 1, sum};
  }
  return e;
}

template <int D>
double max_radius(const World<D>& w) {
  double r = 0.0;
  for (double x : w.particles.radius) r = std::max(r, x);
  return r;
}

// Gap, reduced diameter and sort key of every listed pair; `order` sorts them by key (ties
// by list position, so the result is the same on every machine).
template <int D>
void candidates(const World<D>& w, std::vector<double>& gap, std::vector<double>& share,
                std::vector<double>& key, std::vector<std::size_t>& order) {
  const auto& p = w.particles;
  const auto& pl = w.neighbors.pairs;
  const double scale = 1.0 + 0.5 * w.model.capillary.contact_angle;
  gap.resize(pl.size());
  share.resize(pl.size());
  key.resize(pl.size());
  for (std::size_t k = 0; k < pl.size(); ++k) {
    const std::uint32_t i = pl.i[k], j = pl.j[k];
    gap[k] = (p.x[i] - p.x[j]).norm() - p.radius[i] - p.radius[j];
    share[k] = Capillary::reduced_diameter(p.radius[i], p.radius[j]);
    const double g = std::max(gap[k], 0.0) / scale;
    key[k] = g * g * g / share[k];
  }
  order.resize(pl.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return key[a] < key[b]; });
}

}  // namespace

template <int D>
WettingResult wet_grains(World<D>& w, double water_content, double liquid_density,
                         LiquidPairs pairs) {
  if (w.model.cohesion != CohesionModel::kCapillary)
    throw InputError("wetting the grains needs contact.cohesion = \"capillary\"");
  auto& p = w.particles;
  auto& nl = w.neighbors;
  ExactSum mass;  // exact: the same bits for any order of the grains
  for (std::size_t k = 0; k < p.size(); ++k)
    if (!p.fixed(k)) mass.add(p.mass[k]);
  WettingResult r;
  r.volume = water_content * mass.value() / liquid_density;
  const double d_max = Capillary::reduced_diameter(max_radius(w), max_radius(w));
  nl.bridges = true;
  std::vector<double> gap, share, key;
  std::vector<std::size_t> order;
  Eligible e;
  // The skin must hold every pair the liquid can reach: the widest bridge a pair of the
  // largest grains would get, (V d_max / S)^(1/3) (1 + theta/2). Raising the skin adds
  // candidates, which can only lower that bound, so this settles in a few rounds.
  for (int round = 0;; ++round) {
    if (round == 0 || nl.pairs.bridge.size() != nl.pairs.size() || nl.needs_rebuild(p, w.walls))
      nl.build(p, w.walls);
    candidates(w, gap, share, key, order);
    e = eligible_prefix(order, key, share, r.volume, pairs);
    if (e.count == 0)
      throw InputError(fmt::format(
          "wetting: no pair of grains is {} to hold a bridge ({} candidate pairs within the "
          "neighbour skin {:.4g} m); wet a packed sample",
          pairs == LiquidPairs::kContacts ? "touching" : "close enough", nl.pairs.size(), nl.skin));
    const double reach =
        Capillary::rupture_distance(w.model.capillary, r.volume * d_max / e.share_sum);
    if (reach <= nl.skin || round == 8) break;
    nl.skin = 1.05 * reach;
  }
  std::fill(nl.pairs.bridge.begin(), nl.pairs.bridge.end(), PairList<D>::kNoBridge);
  for (std::size_t m = 0; m < e.count; ++m) {
    const std::size_t k = order[m];
    const double v = r.volume * share[k] / e.share_sum;
    nl.pairs.bridge[k] = v;
    r.contacts += gap[k] <= 0.0 ? 1 : 0;
    r.debonding_distance = std::max(r.debonding_distance, gap[k]);
    r.max_rupture = std::max(r.max_rupture, Capillary::rupture_distance(w.model.capillary, v));
  }
  r.bridges = e.count;
  w.liquid.film.assign(p.size(), 0.0);
  w.liquid.total = r.volume;
  w.liquid.lost = 0.0;
  return r;
}

template <int D>
LiquidBalance liquid_balance(const World<D>& w) {
  LiquidBalance b;
  for (double v : w.neighbors.pairs.bridge)
    if (v >= 0.0) {
      b.bridges += v;
      ++b.bridge_count;
    }
  for (double v : w.liquid.film) b.films += v;
  b.lost = w.liquid.lost;
  b.total = w.liquid.total;
  return b;
}

template WettingResult wet_grains<2>(World<2>&, double, double, LiquidPairs);
template WettingResult wet_grains<3>(World<3>&, double, double, LiquidPairs);
template LiquidBalance liquid_balance<2>(const World<2>&);
template LiquidBalance liquid_balance<3>(const World<3>&);

}  // namespace sable
