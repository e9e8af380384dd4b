#include "sable/mpi/records.hpp"

#include <algorithm>
#include <cstring>
#include <numeric>
#include <tuple>
#include <type_traits>

#include "sable/core/error.hpp"

namespace sable::mpi_records {

namespace {

// Raw bytes of plain values (Eigen's fixed vectors and quaternions hold their doubles and
// nothing else: copying their bytes copies the value).
template <class T>
void put(std::vector<char>& out, const T& v) {
  const auto* bytes = reinterpret_cast<const char*>(&v);
  out.insert(out.end(), bytes, bytes + sizeof(T));
}
template <class T>
const char* get(const char* in, T& v) {
  std::memcpy(static_cast<void*>(&v), in, sizeof(T));
  return in + sizeof(T);
}

template <int D>
bool nonzero(const typename Space<D>::Rot& r) {
  return Space<D>::rot_norm2(r) != 0.0;
}

}  // namespace

template <int D>
std::size_t grain_record_bytes() {
  static const std::size_t bytes = [] {
    std::size_t sum = 0;
    ParticleStore<D> p;
    p.for_each_array(
        [&](auto& a) { sum += sizeof(typename std::decay_t<decltype(a)>::value_type); });
    return sum + sizeof(double);  // the film
  }();
  return bytes;
}

template <int D>
void put_grain(std::vector<char>& out, const ParticleStore<D>& p, const std::vector<double>& film,
               std::uint32_t k) {
  // for_each_array() visits the arrays of a mutable store; it reads nothing here.
  auto& store = const_cast<ParticleStore<D>&>(p);
  store.for_each_array([&](auto& a) { put(out, a[k]); });
  put(out, k < film.size() ? film[k] : 0.0);
}

namespace {

// `count` grain records from `at`, appended to s as ghosts or as owned grains; returns where
// they end.
template <int D>
const char* read_grain_records(const char* at, std::size_t count, LocalState<D>& s, bool ghosts) {
  auto& p = s.particles;
  for (std::size_t n = 0; n < count; ++n) {
    p.for_each_array([&](auto& a) {
      typename std::decay_t<decltype(a)>::value_type v;
      at = get(at, v);
      a.push_back(v);
    });
    p.flags.back() = ghosts ? (p.flags.back() | kGhost) : (p.flags.back() & ~kGhost);
    s.film.emplace_back();
    at = get(at, s.film.back());
  }
  return at;
}

}  // namespace

template <int D>
void read_grains(const std::vector<char>& bytes, LocalState<D>& s, bool ghosts) {
  const std::size_t record = grain_record_bytes<D>();
  if (bytes.size() % record != 0)
    throw IoError("mpi: a message of grains is not a whole number of grain records");
  read_grain_records(bytes.data(), bytes.size() / record, s, ghosts);
}

template <int D>
bool carries_history(const PairList<D>& pl, std::size_t e) {
  return pl.shear[e].squaredNorm() != 0.0 || pl.force[e].squaredNorm() != 0.0 ||
         (!pl.roll.empty() && nonzero<D>(pl.roll[e])) ||
         (!pl.bridge.empty() && pl.bridge[e] != PairList<D>::kNoBridge);
}

template <int D>
PairRecord<D> pair_record(const World<D>& w, std::size_t e) {
  const auto& pl = w.neighbors.pairs;
  const auto& p = w.particles;
  return {p.id[pl.i[e]],
          p.id[pl.j[e]],
          pl.shear[e],
          pl.force[e],
          pl.roll.empty() ? Space<D>::zero_rot() : pl.roll[e],
          pl.bridge.empty() ? PairList<D>::kNoBridge : pl.bridge[e]};
}

template <int D>
WallRecord<D> wall_record(const World<D>& w, std::size_t e) {
  const auto& wl = w.neighbors.wall_pairs;
  return {w.particles.id[wl.i[e]],
          wl.wall[e],
          wl.element[e],
          wl.feature.empty() ? std::uint32_t{0} : wl.feature[e],
          wl.shear[e],
          wl.force[e],
          wl.roll.empty() ? Space<D>::zero_rot() : wl.roll[e]};
}

template <int D>
void put_pair(std::vector<char>& out, const World<D>& w, std::size_t e) {
  put(out, pair_record(w, e));
}

template <int D>
void put_wall_pair(std::vector<char>& out, const World<D>& w, std::size_t e) {
  put(out, wall_record(w, e));
}

// The records of a message, whole structs as put() wrote them.
template <class Record>
void read_records(const std::vector<char>& bytes, std::vector<Record>& out) {
  if (bytes.size() % sizeof(Record) != 0)
    throw IoError("mpi: a message of list entries is not a whole number of records");
  for (const char* at = bytes.data(); at < bytes.data() + bytes.size();) {
    Record r;
    at = get(at, r);
    out.push_back(r);
  }
}

template <int D>
void read_pairs(const std::vector<char>& bytes, std::vector<PairRecord<D>>& out) {
  read_records(bytes, out);
}

template <int D>
void read_wall_pairs(const std::vector<char>& bytes, std::vector<WallRecord<D>>& out) {
  read_records(bytes, out);
}

template <int D>
LocalState<D> extract(const World<D>& w, const std::function<bool(std::uint32_t)>& keep) {
  LocalState<D> s;
  const auto& p = w.particles;
  // Every array copied whole, then compacted to the kept grains (as owned: scatter() marks
  // its ghosts after): a grain record each would copy them element by element, twice.
  std::vector<std::uint32_t> kept;
  std::vector<char> mask(p.size(), 0);
  for (std::uint32_t k = 0; k < p.size(); ++k)
    if (keep(k)) {
      kept.push_back(k);
      mask[k] = 1;
    }
  s.particles = p;
  s.particles.for_each_array([&](auto& a) {
    for (std::size_t m = 0; m < kept.size(); ++m) a[m] = a[kept[m]];
    a.resize(kept.size());
  });
  for (auto& f : s.particles.flags) f = static_cast<std::uint8_t>(f & ~kGhost);
  const auto& film = w.liquid.film;
  s.film.resize(kept.size(), 0.0);
  if (film.size() == p.size())
    for (std::size_t m = 0; m < kept.size(); ++m) s.film[m] = film[kept[m]];
  // The list's reference positions, when it has them (a resumed world: the next rebuild
  // comes when it would have come in the serial run).
  if (w.neighbors.x_ref.size() == p.size())
    for (std::uint32_t k : kept) s.x_ref.push_back(w.neighbors.x_ref[k]);
  const auto& pl = w.neighbors.pairs;
  for (std::size_t e = 0; e < pl.size(); ++e)
    if (mask[pl.i[e]] || mask[pl.j[e]]) s.pairs.push_back(pair_record(w, e));
  const auto& wl = w.neighbors.wall_pairs;
  for (std::size_t e = 0; e < wl.size(); ++e)
    if (mask[wl.i[e]]) s.wall_pairs.push_back(wall_record(w, e));
  return s;
}

namespace {

// Slots of the grains sorted into the global order: order[new] = old.
template <int D>
std::vector<std::uint32_t> global_order(const ParticleStore<D>& p) {
  std::vector<std::uint32_t> order(p.size());
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return std::pair{p.order_key[a], p.id[a].index} < std::pair{p.order_key[b], p.id[b].index};
  });
  return order;
}

// The entries of `records` whose grains are here, in slots, with the later of two copies,
// written into the list as a build leaves it (sorted by (i, j)).
template <int D>
void install_pairs(World<D>& w, const std::vector<PairRecord<D>>& records,
                   const std::vector<std::uint32_t>& slot_of_index) {
  const auto& p = w.particles;
  auto slot = [&](ParticleId id) {
    return id.index < slot_of_index.size() ? slot_of_index[id.index] : IdRegistry::kNoSlot;
  };
  struct Entry {
    std::uint32_t i, j, source;
  };
  std::vector<Entry> entries;
  for (std::uint32_t r = 0; r < records.size(); ++r) {
    std::uint32_t i = slot(records[r].a), j = slot(records[r].b);
    if (i == IdRegistry::kNoSlot || j == IdRegistry::kNoSlot) continue;
    if ((p.flags[i] & kGhost) && (p.flags[j] & kGhost)) continue;
    if (i > j) throw IoError("mpi: a pair entry arrived in the other order of its grains");
    entries.push_back({i, j, r});
  }
  // Sorted by (i, j), a later copy after an earlier one; keep the last of each pair.
  std::stable_sort(entries.begin(), entries.end(), [](const Entry& x, const Entry& y) {
    return std::pair{x.i, x.j} < std::pair{y.i, y.j};
  });
  auto& pl = w.neighbors.pairs;
  pl.clear();
  for (std::size_t e = 0; e < entries.size(); ++e) {
    if (e + 1 < entries.size() && entries[e + 1].i == entries[e].i &&
        entries[e + 1].j == entries[e].j)
      continue;
    const PairRecord<D>& r = records[entries[e].source];
    pl.i.push_back(entries[e].i);
    pl.j.push_back(entries[e].j);
    pl.shear.push_back(r.shear);
    pl.force.push_back(r.force);
    if (w.neighbors.rolling) pl.roll.push_back(r.roll);
    if (w.neighbors.bridges) pl.bridge.push_back(r.bridge);
  }
}

template <int D>
void install_wall_pairs(World<D>& w, const std::vector<WallRecord<D>>& records,
                        const std::vector<std::uint32_t>& slot_of_index) {
  const auto& p = w.particles;
  struct Entry {
    std::uint32_t i, wall, element, source;
  };
  std::vector<Entry> entries;
  for (std::uint32_t r = 0; r < records.size(); ++r) {
    const ParticleId id = records[r].a;
    if (id.index >= slot_of_index.size() || slot_of_index[id.index] == IdRegistry::kNoSlot)
      continue;
    const std::uint32_t i = slot_of_index[id.index];
    if (p.flags[i] & kGhost) continue;
    entries.push_back({i, records[r].wall, records[r].element, r});
  }
  std::stable_sort(entries.begin(), entries.end(), [](const Entry& x, const Entry& y) {
    return std::tuple{x.i, x.wall, x.element} < std::tuple{y.i, y.wall, y.element};
  });
  auto& wl = w.neighbors.wall_pairs;
  wl.clear();
  for (std::size_t e = 0; e < entries.size(); ++e) {
    const Entry& x = entries[e];
    if (e + 1 < entries.size() && entries[e + 1].i == x.i && entries[e + 1].wall == x.wall &&
        entries[e + 1].element == x.element)
      continue;
    const WallRecord<D>& r = records[x.source];
    wl.i.push_back(x.i);
    wl.wall.push_back(x.wall);
    wl.element.push_back(x.element);
    wl.feature.push_back(r.feature);
    wl.shear.push_back(r.shear);
    wl.force.push_back(r.force);
    if (w.neighbors.rolling) wl.roll.push_back(r.roll);
  }
}

}  // namespace

template <int D>
void install(World<D>& w, LocalState<D>&& local) {
  // The grains into the global order, each array permuted as a whole, the films with them.
  ParticleStore<D> p = std::move(local.particles);
  const std::vector<std::uint32_t> order = global_order(p);
  p.for_each_array([&](auto& a) {
    auto from = a;
    for (std::size_t s = 0; s < order.size(); ++s) a[s] = from[order[s]];
  });
  if (local.film.size() != order.size())
    throw IoError("mpi: a process's grains and their liquid films do not match");
  // A world is wet on every process or on none (LiquidState::total is global).
  const bool films = w.liquid.has_films();
  w.liquid.film.clear();
  if (films)
    for (std::uint32_t k : order) w.liquid.film.push_back(local.film[k]);
  std::uint32_t max_index = 0;
  for (const ParticleId& id : p.id) max_index = std::max(max_index, id.index);
  // The registry: each local grain's id to its slot; the others' indices free of any slot.
  std::vector<std::uint32_t> slots(p.size() ? max_index + 1 : 0, IdRegistry::kNoSlot);
  std::vector<std::uint32_t> generations(slots.size(), 0);
  for (std::uint32_t s = 0; s < p.size(); ++s) {
    slots[p.id[s].index] = s;
    generations[p.id[s].index] = p.id[s].generation;
  }
  p.ids.restore(slots, generations, {});
  std::vector<typename Space<D>::Vec> x_ref;
  if (!local.x_ref.empty())
    for (std::uint32_t k : order) x_ref.push_back(local.x_ref[k]);
  w.particles = std::move(p);
  install_pairs(w, local.pairs, slots);
  install_wall_pairs(w, local.wall_pairs, slots);
  w.neighbors.x_ref = x_ref.empty() ? w.particles.x : std::move(x_ref);
  w.neighbors.wall_begin.clear();  // the incidence is made again
}

template <int D>
void drop_ghost_entries(World<D>& w) {
  const auto& p = w.particles;
  auto& pl = w.neighbors.pairs;
  std::size_t kept = 0;
  for (std::size_t e = 0; e < pl.size(); ++e) {
    if ((p.flags[pl.i[e]] & kGhost) && (p.flags[pl.j[e]] & kGhost)) continue;
    pl.i[kept] = pl.i[e];
    pl.j[kept] = pl.j[e];
    pl.shear[kept] = pl.shear[e];
    pl.force[kept] = pl.force[e];
    if (!pl.roll.empty()) pl.roll[kept] = pl.roll[e];
    if (!pl.bridge.empty()) pl.bridge[kept] = pl.bridge[e];
    ++kept;
  }
  pl.i.resize(kept);
  pl.j.resize(kept);
  pl.shear.resize(kept);
  pl.force.resize(kept);
  if (!pl.roll.empty()) pl.roll.resize(kept);
  if (!pl.bridge.empty()) pl.bridge.resize(kept);
  auto& wl = w.neighbors.wall_pairs;
  kept = 0;
  for (std::size_t e = 0; e < wl.size(); ++e) {
    if (p.flags[wl.i[e]] & kGhost) continue;
    wl.i[kept] = wl.i[e];
    wl.wall[kept] = wl.wall[e];
    wl.element[kept] = wl.element[e];
    if (!wl.feature.empty()) wl.feature[kept] = wl.feature[e];
    wl.shear[kept] = wl.shear[e];
    wl.force[kept] = wl.force[e];
    if (!wl.roll.empty()) wl.roll[kept] = wl.roll[e];
    ++kept;
  }
  wl.i.resize(kept);
  wl.wall.resize(kept);
  wl.element.resize(kept);
  if (!wl.feature.empty()) wl.feature.resize(kept);
  wl.shear.resize(kept);
  wl.force.resize(kept);
  if (!wl.roll.empty()) wl.roll.resize(kept);
  w.neighbors.wall_begin.clear();
}

template <int D>
void put_motion(std::vector<char>& out, const ParticleStore<D>& p, std::uint32_t k) {
  put(out, p.x[k]);
  put(out, p.v[k]);
  put(out, p.omega[k]);
  put(out, p.q[k]);
}

template <int D>
const char* get_motion(const char* in, ParticleStore<D>& p, std::uint32_t k) {
  return get(get(get(get(in, p.x[k]), p.v[k]), p.omega[k]), p.q[k]);
}

template <int D>
void put_owned(const World<D>& w, std::vector<char>& grains, std::vector<char>& pairs,
               std::vector<char>& walls) {
  const auto& p = w.particles;
  const auto& nl = w.neighbors;
  for (std::uint32_t k = 0; k < p.size(); ++k) {
    if (p.flags[k] & kGhost) continue;
    put_grain(grains, p, w.liquid.film, k);
    put(grains, k < nl.x_ref.size() ? nl.x_ref[k] : p.x[k]);
  }
  for (std::size_t e = 0; e < nl.pairs.size(); ++e)
    if (!(p.flags[nl.pairs.i[e]] & kGhost)) put_pair(pairs, w, e);
  for (std::size_t e = 0; e < nl.wall_pairs.size(); ++e)
    if (!(p.flags[nl.wall_pairs.i[e]] & kGhost)) put_wall_pair(walls, w, e);
}

template <int D>
void assemble(World<D>& whole, const std::vector<char>& grains, const std::vector<char>& pairs,
              const std::vector<char>& walls) {
  LocalState<D> s;
  const std::size_t step = grain_record_bytes<D>() + sizeof(typename Space<D>::Vec);
  if (grains.size() % step != 0)
    throw IoError("mpi: the gathered grains are not a whole number of grain records");
  for (const char* at = grains.data(); at < grains.data() + grains.size();) {
    at = read_grain_records(at, 1, s, false);
    s.x_ref.emplace_back();
    at = get(at, s.x_ref.back());
  }
  read_pairs(pairs, s.pairs);
  read_wall_pairs(walls, s.wall_pairs);
  install(whole, std::move(s));
}

#define SABLE_MPI_RECORDS(D)                                                                     \
  template std::size_t grain_record_bytes<D>();                                                  \
  template void put_grain<D>(std::vector<char>&, const ParticleStore<D>&,                        \
                             const std::vector<double>&, std::uint32_t);                         \
  template void read_grains<D>(const std::vector<char>&, LocalState<D>&, bool);                  \
  template bool carries_history<D>(const PairList<D>&, std::size_t);                             \
  template void put_pair<D>(std::vector<char>&, const World<D>&, std::size_t);                   \
  template void put_wall_pair<D>(std::vector<char>&, const World<D>&, std::size_t);              \
  template void read_pairs<D>(const std::vector<char>&, std::vector<PairRecord<D>>&);            \
  template void read_wall_pairs<D>(const std::vector<char>&, std::vector<WallRecord<D>>&);       \
  template LocalState<D> extract<D>(const World<D>&, const std::function<bool(std::uint32_t)>&); \
  template void install<D>(World<D>&, LocalState<D> &&);                                         \
  template void drop_ghost_entries<D>(World<D>&);                                                \
  template void put_motion<D>(std::vector<char>&, const ParticleStore<D>&, std::uint32_t);       \
  template const char* get_motion<D>(const char*, ParticleStore<D>&, std::uint32_t);             \
  template void put_owned<D>(const World<D>&, std::vector<char>&, std::vector<char>&,            \
                             std::vector<char>&);                                                \
  template void assemble<D>(World<D>&, const std::vector<char>&, const std::vector<char>&,       \
                            const std::vector<char>&);
SABLE_MPI_RECORDS(2)
SABLE_MPI_RECORDS(3)
#undef SABLE_MPI_RECORDS

}  // namespace sable::mpi_records
