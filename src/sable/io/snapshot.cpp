#include "sable/io/snapshot.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <tuple>
#include <type_traits>
#include <utility>

#include "sable/core/error.hpp"
#include "sable/io/hdf5_file.hpp"
#include "sable/io/snapshot_pack.hpp"

namespace sable {

namespace {

using snapshot_detail::Pack;

template <class T>
std::vector<T> read_rows(const h5::File& f, const std::string& name,
                         std::optional<hsize_t> rows = {}, const std::string& why = {}) {
  constexpr hsize_t cols = Pack<T>::cols;
  const std::vector<double> flat = f.read<double>(name, cols, rows, why);
  std::vector<T> out;
  out.reserve(flat.size() / cols);
  for (std::size_t k = 0; k < flat.size(); k += cols) out.push_back(Pack<T>::get(flat.data() + k));
  return out;
}

// --- reading

h5::File open_snapshot(const std::string& path) {
  h5::File f = h5::File::open(path, fmt::format("snapshot '{}'", path));
  if (!f.has_attr("/", "format")) {
    f.fail(
        fmt::format("not a Sable snapshot: the root group has no attribute 'format' "
                    "(expected format = \"{}\")",
                    kSnapshotFormat));
  }
  const std::string format = f.read_attr_string("/", "format");
  if (format != kSnapshotFormat) {
    f.fail(fmt::format("not a Sable snapshot: attribute 'format' on '/' is \"{}\", expected \"{}\"",
                       clip(format), kSnapshotFormat));
  }
  const auto version = f.read_attr<std::uint32_t>("/", "version");
  if (version != kSnapshotVersion) {
    f.fail(fmt::format("attribute 'version' on '/' is {}, but this build of Sable reads version {}",
                       version, kSnapshotVersion));
  }
  return f;
}

// Everything load_snapshot reads, gathered and checked before the world is touched.
template <int D>
struct Loaded {
  using Vec = typename Space<D>::Vec;
  ParticleStore<D> particles;
  std::vector<Vec> wall_point, wall_velocity, wall_force, wall_pivot;
  std::vector<typename Space<D>::Orientation> wall_orientation;
  std::vector<typename Space<D>::Rot> wall_spin, wall_torque;
  std::vector<std::uint32_t> wall_pivoted;
  NeighborList<D> neighbors;
  LiquidState liquid;
  GrainShapes shapes;
  ContactPoints<D> contact_geometry;
  double time = 0.0, dt = 0.0;
  std::uint64_t step = 0, hash = 0;
  std::array<std::uint64_t, 4> rng{};
  RunPosition pos;
};

template <int D>
void check_ids(const h5::File& f, const ParticleStore<D>& p,
               const std::vector<std::uint32_t>& slots, const std::vector<std::uint32_t>& gens,
               const std::vector<std::uint32_t>& free) {
  for (std::size_t k = 0; k < p.size(); ++k) {
    const ParticleId id = p.id[k];
    if (id.index >= slots.size() || slots[id.index] != k || gens[id.index] != id.generation) {
      f.fail(
          fmt::format("dataset '/particles/id' row {} (index {}, generation {}) does not match "
                      "'/particles/ids/slots' and '/particles/ids/generations'",
                      k, id.index, id.generation));
    }
  }
  for (std::uint32_t index : free) {
    if (index >= slots.size() || slots[index] != IdRegistry::kNoSlot) {
      f.fail(
          fmt::format("dataset '/particles/ids/free_list' holds index {}, which is not a free "
                      "entry of '/particles/ids/slots'",
                      index));
    }
  }
}

template <int D>
void read_ids(const h5::File& f, ParticleStore<D>& p) {
  const std::string why = "one per grain, as '/particles/x'";
  const auto n = static_cast<hsize_t>(p.size());
  const auto shape = f.read<std::uint8_t>("/particles/shape", 0, n, why);
  const std::uint8_t kinds = D == 3 ? 2 : 1;
  for (std::size_t k = 0; k < shape.size(); ++k) {
    if (shape[k] >= kinds)
      f.fail(fmt::format("dataset '/particles/shape' row {} is {}, expected {}", k, shape[k],
                         D == 3 ? "0 (round) or 1 (polyhedron)" : "0 (round)"));
    p.shape.push_back(static_cast<ShapeKind>(shape[k]));
  }
  const auto id = f.read<std::uint32_t>("/particles/id", 2, n, why);
  for (std::size_t k = 0; k < p.size(); ++k) p.id.push_back({id[2 * k], id[2 * k + 1]});
  if (f.exists("/particles/order_key")) {
    p.order_key = f.read<std::uint64_t>("/particles/order_key", 0, n, why);
  } else {  // a snapshot from before the key: the slots' order is the grains' order
    p.order_key.resize(p.size());
    for (std::size_t k = 0; k < p.size(); ++k) p.order_key[k] = k;
  }
  // The slots follow (order_key, id index) (core/particles.hpp): a process that receives some
  // of these grains orders them by it.
  for (std::size_t k = 1; k < p.size(); ++k) {
    if (std::pair{p.order_key[k - 1], p.id[k - 1].index} >=
        std::pair{p.order_key[k], p.id[k].index})
      f.fail(
          fmt::format("rows {} and {} of '/particles/order_key' and '/particles/id' are out of "
                      "order; expected the rows sorted by (order_key, id index)",
                      k - 1, k));
  }
  auto slots = f.read<std::uint32_t>("/particles/ids/slots", 0);
  auto gens = f.read<std::uint32_t>("/particles/ids/generations", 0, slots.size(),
                                    "one per id index, as '/particles/ids/slots'");
  auto free = f.read<std::uint32_t>("/particles/ids/free_list", 0);
  check_ids(f, p, slots, gens, free);
  p.ids.restore(std::move(slots), std::move(gens), std::move(free));
}

template <int D>
ParticleStore<D> read_particles(const h5::File& f, std::size_t materials) {
  using S = Space<D>;
  ParticleStore<D> p;
  p.x = read_rows<typename S::Vec>(f, "/particles/x");
  const auto n = static_cast<hsize_t>(p.size());
  const std::string why = "one per grain, as '/particles/x'";
  p.v = read_rows<typename S::Vec>(f, "/particles/v", n, why);
  p.omega = read_rows<typename S::Rot>(f, "/particles/w", n, why);
  p.f = read_rows<typename S::Vec>(f, "/particles/f", n, why);
  p.t = read_rows<typename S::Rot>(f, "/particles/t", n, why);
  p.q = read_rows<typename S::Orientation>(f, "/particles/q", n, why);
  p.radius = f.read<double>("/particles/radius", 0, n, why);
  p.inv_mass = f.read<double>("/particles/inv_mass", 0, n, why);
  p.inv_inertia = f.read<double>("/particles/inv_inertia", 0, n, why);
  p.mass = f.read<double>("/particles/mass", 0, n, why);
  p.material = f.read<MaterialIndex>("/particles/material", 0, n, why);
  p.flags = f.read<std::uint8_t>("/particles/flags", 0, n, why);
  // A crash snapshot may hold non-finite positions and velocities (it is written to be looked
  // at), but sizes and masses never change in a run: the cell grid and every kernel rely on
  // them.
  for (std::size_t k = 0; k < p.size(); ++k) {
    const double r = p.radius[k], m = p.mass[k], im = p.inv_mass[k], ii = p.inv_inertia[k];
    if (!(std::isfinite(r) && r > 0.0 && std::isfinite(m) && m > 0.0 && std::isfinite(im) &&
          im >= 0.0 && std::isfinite(ii) && ii >= 0.0))
      f.fail(
          fmt::format("grain {} has radius {}, mass {}, inverse mass {} and inverse inertia {}; "
                      "expected a finite radius and mass > 0 and finite inverses >= 0 "
                      "('/particles/radius', 'mass', 'inv_mass', 'inv_inertia')",
                      k, r, m, im, ii));
    if (p.material[k] >= materials) {
      f.fail(
          fmt::format("dataset '/particles/material' row {} is {}, but the scenario defines {} "
                      "material(s)",
                      k, p.material[k], materials));
    }
  }
  read_ids(f, p);
  return p;
}

// The polyhedral grains' shapes (written by io/snapshot_write.cpp, write_shapes), rebuilt from
// the points they were built from; each grain's row checked against the table.
template <int D>
void read_shapes(const h5::File& f, Loaded<D>& s) {
  auto& p = s.particles;
  const auto n = static_cast<hsize_t>(p.size());
  if (!f.exists("/shapes/first")) {
    for (std::size_t k = 0; k < p.size(); ++k)
      if (p.shape[k] != ShapeKind::kRound)
        f.fail(
            fmt::format("grain {} is a polyhedron ('/particles/shape'), but the file has no "
                        "'/shapes'",
                        k));
    p.shape_index.assign(p.size(), 0);
    return;
  }
  p.shape_index = f.read<std::uint32_t>("/particles/shape_index", 0, n, "one per grain");
  const auto first = f.read<std::uint64_t>("/shapes/first", 0);
  const auto points = read_rows<Eigen::Vector3d>(f, "/shapes/points");
  const hsize_t count = first.empty() ? 0 : first.size() - 1;
  const std::string why = "one per shape, as '/shapes/first' less one";
  const auto volume = f.read<double>("/shapes/volume", 0, count, why);
  const auto inertia = read_rows<Eigen::Vector3d>(f, "/shapes/inertia", count, why);
  if (first.empty() || first.front() != 0 || first.back() != points.size() ||
      !std::is_sorted(first.begin(), first.end()))
    f.fail(
        fmt::format("dataset '/shapes/first' must rise from 0 to the {} rows of "
                    "'/shapes/points'",
                    points.size()));
  for (std::size_t k = 0; k < count; ++k) {
    const std::vector<Eigen::Vector3d> body(
        points.begin() + static_cast<std::ptrdiff_t>(first[k]),
        points.begin() + static_cast<std::ptrdiff_t>(first[k + 1]));
    const std::string what = fmt::format("shape {} of '/shapes'", k);
    try {
      s.shapes.add_body_frame(body, volume[k], inertia[k], what.c_str());
    } catch (const InputError& e) {
      f.fail(e.what());
    }
  }
  for (std::size_t k = 0; k < p.size(); ++k)
    if (p.shape[k] == ShapeKind::kPolyhedron ? p.shape_index[k] >= count : p.shape_index[k] != 0)
      f.fail(fmt::format("dataset '/particles/shape_index' row {} is {}; expected {}", k,
                         p.shape_index[k],
                         p.shape[k] == ShapeKind::kRound
                             ? std::string("0 for a round grain")
                             : fmt::format("a row of the {} shapes of '/shapes'", count)));
}

template <int D>
void read_walls(const h5::File& f, const std::vector<Wall<D>>& walls, Loaded<D>& out) {
  using Vec = typename Space<D>::Vec;
  const auto names = f.read_strings("/walls/names");
  if (names.size() != walls.size()) {
    f.fail(fmt::format("dataset '/walls/names' lists {} wall(s), but the scenario defines {}",
                       names.size(), walls.size()));
  }
  for (std::size_t k = 0; k < walls.size(); ++k) {
    if (names[k] != walls[k].name) {
      f.fail(
          fmt::format("dataset '/walls/names' row {} is \"{}\", but the scenario's wall {} is "
                      "\"{}\"",
                      k, clip(names[k]), k, clip(walls[k].name)));
    }
  }
  const auto w = static_cast<hsize_t>(walls.size());
  const std::string why = "one per wall, as '/walls/names'";
  out.wall_point = read_rows<Vec>(f, "/walls/point", w, why);
  out.wall_velocity = read_rows<Vec>(f, "/walls/velocity", w, why);
  out.wall_force = read_rows<Vec>(f, "/walls/force", w, why);
  // The motion beyond a translation; a file without it holds walls that never turned.
  using S = Space<D>;
  if (!f.exists("/walls/orientation")) {
    out.wall_orientation.assign(walls.size(), S::identity());
    out.wall_spin.assign(walls.size(), S::zero_rot());
    out.wall_pivot.assign(walls.size(), S::zero());
    out.wall_pivoted.assign(walls.size(), 0);
    out.wall_torque.assign(walls.size(), S::zero_rot());
    return;
  }
  out.wall_orientation = read_rows<typename S::Orientation>(f, "/walls/orientation", w, why);
  out.wall_spin = read_rows<typename S::Rot>(f, "/walls/spin", w, why);
  out.wall_pivot = read_rows<Vec>(f, "/walls/pivot", w, why);
  out.wall_pivoted = f.read<std::uint32_t>("/walls/pivoted", 0, w, why);
  out.wall_torque = read_rows<typename S::Rot>(f, "/walls/torque", w, why);
  for (std::size_t k = 0; k < walls.size(); ++k) {
    bool finite = std::isfinite(S::rot_norm2(out.wall_spin[k])) && out.wall_pivot[k].allFinite();
    if constexpr (D == 3) {
      const double n2 = out.wall_orientation[k].squaredNorm();
      finite = finite && std::isfinite(n2) && std::abs(n2 - 1.0) < 1e-6;
    } else {
      finite = finite && std::isfinite(out.wall_orientation[k]);
    }
    if (!finite || out.wall_pivoted[k] > 1)
      f.fail(
          fmt::format("wall {} (\"{}\"): '/walls/orientation', 'spin', 'pivot' or 'pivoted' "
                      "row {} is not finite, not a unit quaternion or not 0/1",
                      k, clip(walls[k].name), k));
  }
}

template <int D>
void check_pairs(const h5::File& f, const NeighborList<D>& nl, std::size_t n,
                 const std::vector<std::uint32_t>& elements) {
  for (std::size_t k = 0; k < nl.pairs.size(); ++k) {
    if (!(nl.pairs.i[k] < nl.pairs.j[k] && nl.pairs.j[k] < n)) {
      f.fail(
          fmt::format("'/neighbors/pairs' row {} pairs slots {} and {}; expected i < j < {} "
                      "(the number of grains)",
                      k, nl.pairs.i[k], nl.pairs.j[k], n));
    }
    // Solvers rely on the lists being sorted (contiguous ranges per grain).
    if (k > 0 && std::pair(nl.pairs.i[k - 1], nl.pairs.j[k - 1]) >=
                     std::pair(nl.pairs.i[k], nl.pairs.j[k])) {
      f.fail(
          fmt::format("'/neighbors/pairs' row {} is out of order; expected rows sorted by "
                      "(i, j) without repeats",
                      k));
    }
  }
  const auto& wl = nl.wall_pairs;
  auto key = [&](std::size_t k) { return std::tuple(wl.i[k], wl.wall[k], wl.element[k]); };
  for (std::size_t k = 1; k < wl.size(); ++k) {
    if (key(k - 1) >= key(k)) {
      f.fail(
          fmt::format("'/neighbors/wall_pairs' row {} is out of order; expected rows sorted "
                      "by (grain, wall, element) without repeats",
                      k));
    }
  }
  for (std::size_t k = 0; k < wl.size(); ++k) {
    if (wl.i[k] >= n || wl.wall[k] >= elements.size()) {
      f.fail(
          fmt::format("'/neighbors/wall_pairs' row {} pairs slot {} with wall {}, element {}; "
                      "expected a slot below {}, a wall below {} and one of its elements",
                      k, wl.i[k], wl.wall[k], wl.element[k], n, elements.size()));
    }
    if (wl.element[k] >= elements[wl.wall[k]]) {
      f.fail(
          fmt::format("'/neighbors/wall_pairs/element' row {} is {}, but wall {} has {} "
                      "element{}; expected one of them (counted from 0)",
                      k, wl.element[k], wl.wall[k], elements[wl.wall[k]],
                      elements[wl.wall[k]] == 1 ? "" : "s"));
    }
  }
}

template <int D>
void read_neighbors(const h5::File& f, std::size_t n, const std::vector<std::uint32_t>& elements,
                    NeighborList<D>& nl) {
  const std::size_t walls = elements.size();
  using Vec = typename Space<D>::Vec;
  const auto lo = f.read<double>("/neighbors/domain_lo", 0, D, "one per dimension");
  const auto hi = f.read<double>("/neighbors/domain_hi", 0, D, "one per dimension");
  nl.domain_lo = Eigen::Map<const Vec>(lo.data());
  nl.domain_hi = Eigen::Map<const Vec>(hi.data());
  // The cell grid is cut from these bounds (any order: an empty extent gives one cell).
  for (int d = 0; d < D; ++d)
    if (!(std::isfinite(lo[d]) && std::isfinite(hi[d])))
      f.fail(
          fmt::format("'/neighbors/domain_lo' and 'domain_hi' are {} and {} on axis {}; "
                      "expected finite bounds",
                      lo[d], hi[d], d));
  nl.skin = f.read_attr<double>("/neighbors", "skin");
  if (!(std::isfinite(nl.skin) && nl.skin >= 0.0))
    f.fail(fmt::format("attribute 'skin' on '/neighbors' is {}; expected a finite skin >= 0",
                       nl.skin));
  nl.builds = f.read_attr<std::uint64_t>("/neighbors", "builds");
  // Reference positions of the last build: one per grain (wall), or none (rebuild at once).
  nl.x_ref = read_rows<Vec>(f, "/neighbors/x_ref");
  nl.wall_ref = read_rows<Vec>(f, "/neighbors/wall_ref");
  if (!nl.x_ref.empty() && nl.x_ref.size() != n)
    f.fail(fmt::format("dataset '/neighbors/x_ref' has {} rows, expected 0 or {} (one per grain)",
                       nl.x_ref.size(), n));
  if (!nl.wall_ref.empty() && nl.wall_ref.size() != walls)
    f.fail(fmt::format("dataset '/neighbors/wall_ref' has {} rows, expected 0 or {} (one per wall)",
                       nl.wall_ref.size(), walls));
  auto& pl = nl.pairs;
  pl.i = f.read<std::uint32_t>("/neighbors/pairs/i", 0);
  const auto np = static_cast<hsize_t>(pl.i.size());
  const std::string why = "one per pair, as '/neighbors/pairs/i'";
  pl.j = f.read<std::uint32_t>("/neighbors/pairs/j", 0, np, why);
  pl.shear = read_rows<Vec>(f, "/neighbors/pairs/shear", np, why);
  pl.force = read_rows<Vec>(f, "/neighbors/pairs/force", np, why);
  auto& wl = nl.wall_pairs;
  wl.i = f.read<std::uint32_t>("/neighbors/wall_pairs/i", 0);
  const auto nw = static_cast<hsize_t>(wl.i.size());
  const std::string wwhy = "one per wall pair, as '/neighbors/wall_pairs/i'";
  wl.wall = f.read<std::uint32_t>("/neighbors/wall_pairs/wall", 0, nw, wwhy);
  wl.shear = read_rows<Vec>(f, "/neighbors/wall_pairs/shear", nw, wwhy);
  wl.force = read_rows<Vec>(f, "/neighbors/wall_pairs/force", nw, wwhy);
  // A list of walls without elements (planes, cylinders) has element and feature 0.
  const bool meshes = f.exists("/neighbors/wall_pairs/element");
  wl.element = meshes ? f.read<std::uint32_t>("/neighbors/wall_pairs/element", 0, nw, wwhy)
                      : std::vector<std::uint32_t>(wl.size(), 0);
  wl.feature = meshes ? f.read<std::uint32_t>("/neighbors/wall_pairs/feature", 0, nw, wwhy)
                      : std::vector<std::uint32_t>(wl.size(), 0);
  nl.wall_ref_turn =
      f.exists("/neighbors/wall_ref_turn")
          ? read_rows<typename Space<D>::Orientation>(f, "/neighbors/wall_ref_turn")
          : std::vector<typename Space<D>::Orientation>(nl.wall_ref.size(), Space<D>::identity());
  if (nl.wall_ref_turn.size() != nl.wall_ref.size())
    f.fail(
        fmt::format("dataset '/neighbors/wall_ref_turn' has {} rows, expected {} (as "
                    "'/neighbors/wall_ref')",
                    nl.wall_ref_turn.size(), nl.wall_ref.size()));
  // Each wall's list reach: absent from files written before it existed, whose lists were
  // all made within the whole skin (empty means exactly that).
  if (f.exists("/neighbors/wall_reach")) {
    nl.wall_reach = f.read<double>("/neighbors/wall_reach", 0);
    if (nl.wall_reach.size() != nl.wall_ref.size())
      f.fail(
          fmt::format("dataset '/neighbors/wall_reach' has {} values, expected {} (as "
                      "'/neighbors/wall_ref')",
                      nl.wall_reach.size(), nl.wall_ref.size()));
    for (std::size_t w = 0; w < nl.wall_reach.size(); ++w)
      if (!(nl.wall_reach[w] >= 0.0 && nl.wall_reach[w] <= nl.skin))
        f.fail(
            fmt::format("'/neighbors/wall_reach' value {} is {}; expected a reach within "
                        "[0, skin = {}]",
                        w, nl.wall_reach[w], nl.skin));
  }
  check_pairs(f, nl, n, elements);
}

// The rolling springs, if the file has them (s.neighbors.rolling says so). A file without
// them resumed by a law with rolling resistance starts its springs at zero; a file with them
// resumed by a law without drops them (load_snapshot).
template <int D>
void read_rolling(const h5::File& f, Loaded<D>& s) {
  using Rot = typename Space<D>::Rot;
  auto& nl = s.neighbors;
  nl.rolling = f.exists("/neighbors/pairs/roll");
  if (!nl.rolling) return;
  auto read = [&](const std::string& name, std::size_t rows, const std::string& why) {
    std::vector<Rot> roll = read_rows<Rot>(f, name, rows, why);
    for (std::size_t k = 0; k < roll.size(); ++k)
      if (!std::isfinite(Space<D>::rot_norm2(roll[k])))
        f.fail(fmt::format("'{}' row {} is not finite; expected a rolling spring (rad)", name, k));
    return roll;
  };
  nl.pairs.roll =
      read("/neighbors/pairs/roll", nl.pairs.size(), "one per pair, as '/neighbors/pairs/i'");
  nl.wall_pairs.roll = read("/neighbors/wall_pairs/roll", nl.wall_pairs.size(),
                            "one per wall pair, as '/neighbors/wall_pairs/i'");
}

// The polyhedral contacts' normals, points and depths, if the file has them (written with
// polyhedra once a solver has stepped: io/snapshot_write.cpp); one row per list entry.
template <int D>
void read_contact_geometry(const h5::File& f, Loaded<D>& s) {
  using Vec = typename Space<D>::Vec;
  if (!f.exists("/neighbors/pairs/normal")) return;
  auto read = [&](const std::string& list, std::size_t rows, EntryGeometry<D>& out) {
    const std::string why = fmt::format("one per entry, as '/neighbors/{}/i'", list);
    const std::string base = "/neighbors/" + list + "/";
    out.normal = read_rows<Vec>(f, base + "normal", rows, why);
    out.arm = read_rows<Vec>(f, base + "arm", rows, why);
    out.depth = read_rows<double>(f, base + "depth", rows, why);
    for (std::size_t k = 0; k < rows; ++k)
      if (!std::isfinite(out.normal[k].squaredNorm() + out.arm[k].squaredNorm() + out.depth[k]))
        f.fail(fmt::format("'{}normal', 'arm' or 'depth' row {} is not finite", base, k));
  };
  read("pairs", s.neighbors.pairs.size(), s.contact_geometry.pairs);
  read("wall_pairs", s.neighbors.wall_pairs.size(), s.contact_geometry.wall_pairs);
}

template <int D>
void read_liquid(const h5::File& f, bool wet_model, std::size_t grains, Loaded<D>& s) {
  auto& pl = s.neighbors.pairs;
  const bool has = f.exists("/neighbors/pairs/bridge");
  s.neighbors.bridges = has;  // the file's hash covers the bridges iff it has them
  if (has && !wet_model)
    f.fail(
        "holds liquid bridges ('/neighbors/pairs/bridge'), but the scenario's contact law is "
        "dry: resume it with contact.cohesion = \"capillary\"");
  if (!wet_model) return;
  if (!has) {  // a dry snapshot continued by a wet scenario: no liquid until a stage wets it
    pl.bridge.assign(pl.size(), PairList<D>::kNoBridge);
    return;
  }
  pl.bridge = f.read<double>("/neighbors/pairs/bridge", 0, static_cast<hsize_t>(pl.size()),
                             "one per pair, as '/neighbors/pairs/i'");
  s.liquid.film = f.read<double>("/liquid/film", 0);
  s.liquid.total = f.read_attr<double>("/liquid", "total");
  s.liquid.lost = f.read_attr<double>("/liquid", "lost");
  if (!s.liquid.film.empty() && s.liquid.film.size() != grains)
    f.fail(fmt::format("'/liquid/film' has {} rows, expected 0 or one per grain ({})",
                       s.liquid.film.size(), grains));
  for (std::size_t k = 0; k < pl.size(); ++k)
    if (!(pl.bridge[k] >= 0.0 || pl.bridge[k] == PairList<D>::kNoBridge) ||
        !std::isfinite(pl.bridge[k]))
      f.fail(
          fmt::format("'/neighbors/pairs/bridge' row {} is {}; expected a volume >= 0 (m^3) "
                      "or -1 (no bridge)",
                      k, pl.bridge[k]));
}

template <int D>
void read_clock(const h5::File& f, Loaded<D>& out) {
  out.step = f.read_attr<std::uint64_t>("/", "step");
  out.time = f.read_attr<double>("/", "time");
  out.dt = f.read_attr<double>("/", "dt");
  out.pos.stage = f.read_attr<std::uint32_t>("/", "stage");
  out.pos.stage_step = f.read_attr<std::uint64_t>("/", "stage_step");
  out.hash = f.read_attr<std::uint64_t>("/", "state_hash");
  if (!(std::isfinite(out.time) && std::isfinite(out.dt)))
    f.fail(fmt::format("attributes 'time' and 'dt' on '/' are {} and {}; expected finite values",
                       out.time, out.dt));
  const auto rng = f.read<std::uint64_t>("/rng_state", 0, 4, "the 4 words of xoshiro256**");
  std::copy(rng.begin(), rng.end(), out.rng.begin());
}

// Exchange the dynamic state of `w` with `s`; applying it twice restores both.
template <int D>
void swap_state(World<D>& w, Loaded<D>& s) {
  using std::swap;
  swap(w.particles, s.particles);
  swap(w.shapes, s.shapes);
  swap(w.contact_geometry, s.contact_geometry);
  for (std::size_t k = 0; k < w.walls.size(); ++k) {
    swap(w.walls[k].point, s.wall_point[k]);
    swap(w.walls[k].velocity, s.wall_velocity[k]);
    swap(w.walls[k].force, s.wall_force[k]);
    const bool was_turned = w.walls[k].turned();
    swap(w.walls[k].orientation, s.wall_orientation[k]);
    swap(w.walls[k].spin, s.wall_spin[k]);
    swap(w.walls[k].pivot, s.wall_pivot[k]);
    swap(w.walls[k].torque, s.wall_torque[k]);
    const bool pivoted = s.wall_pivoted[k] != 0;
    s.wall_pivoted[k] = w.walls[k].pivoted ? 1 : 0;
    w.walls[k].pivoted = pivoted;
    // A mesh's vertices and a turned shape's normal or axis follow the pose.
    if (w.walls[k].is_mesh() || w.walls[k].turned() || was_turned) w.walls[k].place();
  }
  auto& a = w.neighbors;
  auto& b = s.neighbors;
  swap(a.skin, b.skin);
  swap(a.domain_lo, b.domain_lo);
  swap(a.domain_hi, b.domain_hi);
  swap(a.pairs, b.pairs);
  swap(a.wall_pairs, b.wall_pairs);
  swap(a.x_ref, b.x_ref);
  swap(a.wall_ref, b.wall_ref);
  swap(a.wall_ref_turn, b.wall_ref_turn);
  swap(a.wall_reach, b.wall_reach);
  swap(a.builds, b.builds);
  swap(w.liquid, s.liquid);
  swap(w.time, s.time);
  swap(w.dt, s.dt);
  swap(w.step, s.step);
  const auto rng = w.rng.state();
  w.rng.set_state(s.rng);
  s.rng = rng;
}

}  // namespace

template <int D>
RunPosition load_snapshot(const std::string& path, World<D>& world, std::string* scenario_text) {
  const h5::File f = open_snapshot(path);
  const auto dim = f.read_attr<std::int32_t>("/", "dimension");
  if (dim != D) {
    f.fail(
        fmt::format("attribute 'dimension' on '/' is {}: a {}D snapshot cannot be loaded into a "
                    "{}D run",
                    dim, dim, D));
  }
  Loaded<D> s;
  read_clock(f, s);
  s.particles = read_particles<D>(f, world.materials.size());
  read_shapes(f, s);
  read_walls(f, world.walls, s);
  std::vector<std::uint32_t> elements;
  for (const auto& wall : world.walls) elements.push_back(wall.elements());
  read_neighbors(f, s.particles.size(), elements, s.neighbors);
  read_liquid(f, world.neighbors.bridges, s.particles.size(), s);
  read_rolling(f, s);
  read_contact_geometry(f, s);
  std::string text = f.read_string("/scenario");
  swap_state(world, s);
  // The state as it was written: with rolling springs and liquid bridges if the file has
  // them (a dry file continued by a wet or rolling law hashes without them).
  const bool rolling = world.neighbors.rolling, bridges = world.neighbors.bridges;
  world.neighbors.rolling = s.neighbors.rolling;
  world.neighbors.bridges = s.neighbors.bridges;
  const std::uint64_t h = state_hash(world, f.exists("/particles/order_key"));
  world.neighbors.rolling = rolling;
  world.neighbors.bridges = bridges;
  if (h != s.hash) {
    swap_state(world, s);  // put the caller's world back as it was
    f.fail(
        fmt::format("the loaded state hashes to {:016x}, but attribute 'state_hash' on '/' is "
                    "{:016x}: the file is corrupt or was written by an incompatible build",
                    h, s.hash));
  }
  auto& nl = world.neighbors;
  if (!rolling) {
    nl.pairs.roll.clear();
    nl.wall_pairs.roll.clear();
  } else if (!s.neighbors.rolling) {
    nl.pairs.roll.assign(nl.pairs.size(), Space<D>::zero_rot());
    nl.wall_pairs.roll.assign(nl.wall_pairs.size(), Space<D>::zero_rot());
  }
  if (scenario_text != nullptr) *scenario_text = std::move(text);
  return s.pos;
}

SnapshotInfo read_snapshot_info(const std::string& path) {
  const h5::File f = open_snapshot(path);
  SnapshotInfo info;
  info.dimension = f.read_attr<std::int32_t>("/", "dimension");
  if (info.dimension != 2 && info.dimension != 3)
    f.fail(fmt::format("attribute 'dimension' on '/' is {}, expected 2 or 3", info.dimension));
  info.step = f.read_attr<std::uint64_t>("/", "step");
  info.time = f.read_attr<double>("/", "time");
  info.dt = f.read_attr<double>("/", "dt");
  info.pos.stage = f.read_attr<std::uint32_t>("/", "stage");
  info.pos.stage_step = f.read_attr<std::uint64_t>("/", "stage_step");
  info.state_hash = f.read_attr<std::uint64_t>("/", "state_hash");
  info.grains = f.shape("/particles/x").rows;
  info.pairs = f.shape("/neighbors/pairs/i").rows;
  info.wall_pairs = f.shape("/neighbors/wall_pairs/i").rows;
  info.walls = f.shape("/walls/point").rows;
  info.scenario_text = f.read_string("/scenario");
  if (f.exists("/scenario_path")) info.scenario_path = f.read_string("/scenario_path");
  return info;
}

template RunPosition load_snapshot<2>(const std::string&, World<2>&, std::string*);
template RunPosition load_snapshot<3>(const std::string&, World<3>&, std::string*);

}  // namespace sable
