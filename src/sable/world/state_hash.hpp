// Bit-exact hash of a World's dynamic state, for determinism and restart checks.
//
// Two worlds hash equal only if every double of every particle array, wall, contact-list entry
// (with its history and last force), the clock and the random generator are bit-identical.
// Static data that a scenario rebuilds (materials, wall geometry and names, contact model) is
// not hashed: a snapshot restores the dynamic state onto a world built from its scenario.
#pragma once

#include <algorithm>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "sable/core/hash.hpp"
#include "sable/world/world.hpp"

namespace sable {

namespace detail {

// Eigen vectors and quaternions are plain arrays of doubles without padding, but not
// "trivially copyable" in the standard's sense, so Hasher::array would refuse them.
template <class T>
void hash_dense(Hasher& h, const std::vector<T>& v) {
  if constexpr (std::is_trivially_copyable_v<T>) {
    h.array(v);
  } else {
    static_assert(sizeof(T) % sizeof(double) == 0, "hash_dense: expects a dense array of doubles");
    h.value(v.size());
    if (!v.empty()) h.bytes(v.data(), v.size() * sizeof(T));
  }
}

template <class V>
void hash_vec(Hasher& h, const V& x) {
  h.bytes(x.data(), static_cast<std::size_t>(x.size()) * sizeof(double));
}

}  // namespace detail

// `order_key`: false only to check a snapshot written before the grains had an order_key (the
// hash it carries does not cover one).
template <int D>
std::uint64_t state_hash(const World<D>& w, bool order_key = true) {
  using detail::hash_dense;
  Hasher h;
  const auto& p = w.particles;
  hash_dense(h, p.x);
  hash_dense(h, p.v);
  hash_dense(h, p.omega);
  hash_dense(h, p.f);
  hash_dense(h, p.t);
  hash_dense(h, p.radius);
  hash_dense(h, p.inv_mass);
  hash_dense(h, p.inv_inertia);
  hash_dense(h, p.material);
  hash_dense(h, p.flags);
  hash_dense(h, p.q);
  hash_dense(h, p.mass);
  hash_dense(h, p.id);
  hash_dense(h, p.shape);
  if (order_key) hash_dense(h, p.order_key);
  hash_dense(h, p.ids.slots());
  hash_dense(h, p.ids.generations());
  hash_dense(h, p.ids.free_list());
  h.value(w.walls.size());
  for (const auto& wall : w.walls) {
    detail::hash_vec(h, wall.point);
    detail::hash_vec(h, wall.velocity);
    detail::hash_vec(h, wall.force);
    if (wall.moves_about()) {  // only walls given a rotation: the others hash as they did
      hash_dense(h, std::vector{wall.orientation});
      hash_dense(h, std::vector{wall.spin});
      detail::hash_vec(h, wall.pivot);
      hash_dense(h, std::vector{wall.torque});
    }
  }
  const auto& nl = w.neighbors;
  h.value(nl.skin);
  detail::hash_vec(h, nl.domain_lo);
  detail::hash_vec(h, nl.domain_hi);
  hash_dense(h, nl.pairs.i);
  hash_dense(h, nl.pairs.j);
  hash_dense(h, nl.pairs.shear);
  hash_dense(h, nl.pairs.force);
  hash_dense(h, nl.wall_pairs.i);
  hash_dense(h, nl.wall_pairs.wall);
  hash_dense(h, nl.wall_pairs.shear);
  hash_dense(h, nl.wall_pairs.force);
  if (nl.bridges) {  // only for a wet law: dry runs hash as they always did
    hash_dense(h, nl.pairs.bridge);
    hash_dense(h, w.liquid.film);
    h.value(w.liquid.total);
    h.value(w.liquid.lost);
  }
  if (std::any_of(w.walls.begin(), w.walls.end(),
                  [](const auto& wall) { return wall.is_mesh(); })) {
    hash_dense(h, nl.wall_pairs.element);  // only with a mesh wall (0 for other shapes)
    hash_dense(h, nl.wall_pairs.feature);
    hash_dense(h, nl.wall_reach);  // a still mesh's half reach (NeighborList::list_reach)
  }
  if (nl.rolling) {  // only with rolling resistance: other runs hash as they always did
    hash_dense(h, nl.pairs.roll);
    hash_dense(h, nl.wall_pairs.roll);
  }
  hash_dense(h, nl.x_ref);
  hash_dense(h, nl.wall_ref);
  for (std::size_t k = 0; k < w.walls.size() && k < nl.wall_ref_turn.size(); ++k)
    if (w.walls[k].moves_about()) hash_dense(h, std::vector{nl.wall_ref_turn[k]});
  h.value(w.time);
  h.value(w.step);
  h.value(w.dt);
  h.value(w.rng.state());
  return h.digest();
}

}  // namespace sable
