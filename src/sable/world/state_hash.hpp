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

// The hash's field order, in one place: `arrays(h, name, v)` hashes each per-grain and
// per-contact array `v` of `w` (or, for a snapshot streamed from its file, the dataset `name`
// that io/snapshot_write.cpp stores it under, read in place of `v`: io/snapshot_hash.hpp); it must
// hash what hash_dense(h, v) would (the element count as a std::size_t, then the elements'
// bytes in memory layout). Everything else (walls, per-wall arrays, the clock, the generator,
// and which optional arrays are hashed at all) comes from `w` itself.
//
// `order_key`: false only to check a snapshot written before the grains had an order_key (the
// hash it carries does not cover one).
template <int D, class Arrays>
std::uint64_t state_hash_with(const World<D>& w, Arrays&& arrays, bool order_key = true) {
  using detail::hash_dense;
  Hasher h;
  const auto& p = w.particles;
  arrays(h, "/particles/x", p.x);
  arrays(h, "/particles/v", p.v);
  arrays(h, "/particles/w", p.omega);
  arrays(h, "/particles/f", p.f);
  arrays(h, "/particles/t", p.t);
  arrays(h, "/particles/radius", p.radius);
  arrays(h, "/particles/inv_mass", p.inv_mass);
  arrays(h, "/particles/inv_inertia", p.inv_inertia);
  arrays(h, "/particles/material", p.material);
  arrays(h, "/particles/flags", p.flags);
  arrays(h, "/particles/q", p.q);
  arrays(h, "/particles/mass", p.mass);
  arrays(h, "/particles/id", p.id);
  arrays(h, "/particles/shape", p.shape);
  if (order_key) arrays(h, "/particles/order_key", p.order_key);
  if (!w.shapes.empty()) {  // only with polyhedral grains: other runs hash as they always did
    arrays(h, "/particles/shape_index", p.shape_index);
    h.value(w.shapes.size());
    for (std::size_t k = 0; k < w.shapes.size(); ++k) {
      hash_dense(h, w.shapes[k].points);
      h.value(w.shapes[k].volume);
      detail::hash_vec(h, w.shapes[k].inertia);
    }
  }
  arrays(h, "/particles/ids/slots", p.ids.slots());
  arrays(h, "/particles/ids/generations", p.ids.generations());
  arrays(h, "/particles/ids/free_list", p.ids.free_list());
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
  arrays(h, "/neighbors/pairs/i", nl.pairs.i);
  arrays(h, "/neighbors/pairs/j", nl.pairs.j);
  arrays(h, "/neighbors/pairs/shear", nl.pairs.shear);
  arrays(h, "/neighbors/pairs/force", nl.pairs.force);
  arrays(h, "/neighbors/wall_pairs/i", nl.wall_pairs.i);
  arrays(h, "/neighbors/wall_pairs/wall", nl.wall_pairs.wall);
  arrays(h, "/neighbors/wall_pairs/shear", nl.wall_pairs.shear);
  arrays(h, "/neighbors/wall_pairs/force", nl.wall_pairs.force);
  if (nl.bridges) {  // only for a wet law: dry runs hash as they always did
    arrays(h, "/neighbors/pairs/bridge", nl.pairs.bridge);
    arrays(h, "/liquid/film", w.liquid.film);
    h.value(w.liquid.total);
    h.value(w.liquid.lost);
  }
  if (std::any_of(w.walls.begin(), w.walls.end(),
                  [](const auto& wall) { return wall.is_mesh(); })) {
    arrays(h, "/neighbors/wall_pairs/element", nl.wall_pairs.element);  // 0 for other shapes
    arrays(h, "/neighbors/wall_pairs/feature", nl.wall_pairs.feature);
    hash_dense(h, nl.wall_reach);  // per wall: a still mesh's half reach (list_reach)
  }
  if (nl.rolling) {  // only with rolling resistance: other runs hash as they always did
    arrays(h, "/neighbors/pairs/roll", nl.pairs.roll);
    arrays(h, "/neighbors/wall_pairs/roll", nl.wall_pairs.roll);
  }
  arrays(h, "/neighbors/x_ref", nl.x_ref);
  hash_dense(h, nl.wall_ref);
  for (std::size_t k = 0; k < w.walls.size() && k < nl.wall_ref_turn.size(); ++k)
    if (w.walls[k].moves_about()) hash_dense(h, std::vector{nl.wall_ref_turn[k]});
  h.value(w.time);
  h.value(w.step);
  h.value(w.dt);
  h.value(w.rng.state());
  return h.digest();
}

// The hash of `w` as it is in memory.
template <int D>
std::uint64_t state_hash(const World<D>& w, bool order_key = true) {
  return state_hash_with(
      w, [](Hasher& h, const char*, const auto& v) { detail::hash_dense(h, v); }, order_key);
}

}  // namespace sable
