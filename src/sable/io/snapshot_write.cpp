// Writing snapshots (layout: io/snapshot.hpp): a World whole, or one process's share of a
// decomposed run's state (world/snapshot_part.hpp) into the file all processes write
// together, each family of rows (grains, pairs, wall pairs, id registry) at its file rows.
#include <fmt/format.h>

#include <filesystem>
#include <stdexcept>
#include <type_traits>

#include "sable/core/error.hpp"
#include "sable/io/atomic_file.hpp"
#include "sable/io/hdf5_file.hpp"
#include "sable/io/snapshot.hpp"
#include "sable/io/snapshot_hash.hpp"
#include "sable/io/snapshot_pack.hpp"

namespace sable {

namespace {

using snapshot_detail::Pack;

// Where one family of rows goes: the whole dataset (`rows` null: a World written whole) or
// this process's rows of a dataset of `total` rows.
struct Rows {
  const std::vector<std::uint64_t>* rows = nullptr;
  std::uint64_t total = 0;
};

// Writes a per-grain or per-contact array of numbers as a 1-D dataset, at its rows (or whole).
template <class T>
void write_flat(h5::File& f, const std::string& name, const std::vector<T>& v, Rows at = {}) {
  static_assert(std::is_arithmetic_v<T>);
  if (at.rows == nullptr)
    f.write(name, v);
  else
    f.write_rows(name, v.data(), *at.rows, at.total, 0);
}

// Writes an array of doubles, vectors or orientations as rows of doubles (Pack), at its rows
// (or whole: walls, references).
template <class T>
void write_rows(h5::File& f, const std::string& name, const std::vector<T>& v, Rows at = {}) {
  constexpr hsize_t cols = Pack<T>::cols;
  const double* data = reinterpret_cast<const double*>(v.data());
  std::vector<double> flat;
  // A double or a fixed-size Eigen vector is its coefficients in order, without padding:
  // written in place, without a copy (the pair lists' are the largest arrays of a run).
  if constexpr (sizeof(T) != cols * sizeof(double) || std::is_same_v<T, Eigen::Quaterniond>) {
    flat.resize(v.size() * cols);
    for (std::size_t k = 0; k < v.size(); ++k) Pack<T>::put(v[k], flat.data() + k * cols);
    data = flat.data();
  }
  if (at.rows == nullptr)
    f.write(name, data, v.size(), cols);
  else
    f.write_rows(name, data, *at.rows, at.total, cols);
}

// The families of rows of a snapshot: a whole World's, or a process's share's.
struct Families {
  Rows grains, pairs, wall_pairs;
};

template <int D>
Families families_of(const SnapshotPart<D>* part) {
  if (part == nullptr) return {};
  return {{&part->grain_rows, part->grains},
          {&part->pair_rows, part->pairs},
          {&part->wall_pair_rows, part->wall_pairs}};
}

// The header; the state hash only for a World written whole (a share's file is sealed with
// it by seal_snapshot()).
template <int D>
void write_header(h5::File& f, const World<D>& w, const RunPosition& pos,
                  const std::string& scenario_text, const std::string& scenario_path, bool whole) {
  f.write_string("/scenario", scenario_text);
  if (!scenario_path.empty()) f.write_string("/scenario_path", scenario_path);
  const auto rng = w.rng.state();
  f.write("/rng_state", std::vector<std::uint64_t>(rng.begin(), rng.end()));
  f.write_attr_string("/", "format", kSnapshotFormat);
  f.write_attr("/", "version", kSnapshotVersion);
  f.write_attr("/", "dimension", std::int32_t{D});
  f.write_attr("/", "step", w.step);
  f.write_attr("/", "time", w.time);
  f.write_attr("/", "dt", w.dt);
  f.write_attr("/", "stage", pos.stage);
  f.write_attr("/", "stage_step", pos.stage_step);
  if (whole) f.write_attr("/", "state_hash", state_hash(w));
}

template <int D>
void write_particles(h5::File& f, const ParticleStore<D>& p, Rows at) {
  write_rows(f, "/particles/x", p.x, at);
  write_rows(f, "/particles/v", p.v, at);
  write_rows(f, "/particles/w", p.omega, at);
  write_rows(f, "/particles/f", p.f, at);
  write_rows(f, "/particles/t", p.t, at);
  write_rows(f, "/particles/q", p.q, at);
  write_flat(f, "/particles/radius", p.radius, at);
  write_flat(f, "/particles/inv_mass", p.inv_mass, at);
  write_flat(f, "/particles/inv_inertia", p.inv_inertia, at);
  write_flat(f, "/particles/mass", p.mass, at);
  write_flat(f, "/particles/material", p.material, at);
  write_flat(f, "/particles/flags", p.flags, at);
  std::vector<std::uint8_t> shape(p.size());
  std::vector<std::uint32_t> id(2 * p.size());
  for (std::size_t k = 0; k < p.size(); ++k) {
    shape[k] = static_cast<std::uint8_t>(p.shape[k]);
    id[2 * k] = p.id[k].index;
    id[2 * k + 1] = p.id[k].generation;
  }
  write_flat(f, "/particles/shape", shape, at);
  if (at.rows == nullptr)
    f.write("/particles/id", id, 2);
  else
    f.write_rows("/particles/id", id.data(), *at.rows, at.total, 2);
  write_flat(f, "/particles/order_key", p.order_key, at);
}

// The id registry: a World's own, or the whole sample's, each process writing its grains'.
template <int D>
void write_registry(h5::File& f, const ParticleStore<D>& p, const SnapshotPart<D>* part) {
  if (part == nullptr) {
    f.write("/particles/ids/slots", p.ids.slots());
    f.write("/particles/ids/generations", p.ids.generations());
    f.write("/particles/ids/free_list", p.ids.free_list());
    return;
  }
  f.write_rows("/particles/ids/slots", part->registry_slots.data(), part->registry_rows,
               part->registry, 0, IdRegistry::kNoSlot);
  f.write_rows("/particles/ids/generations", part->registry_generations.data(), part->registry_rows,
               part->registry, 0, std::uint32_t{0});
  f.write("/particles/ids/free_list", std::vector<std::uint32_t>{});
}

template <int D>
void write_walls(h5::File& f, const std::vector<Wall<D>>& walls) {
  std::vector<std::string> names;
  std::vector<typename Space<D>::Vec> point, velocity, force, pivot;
  std::vector<typename Space<D>::Orientation> orientation;
  std::vector<typename Space<D>::Rot> spin, torque;
  std::vector<std::uint32_t> pivoted;
  for (const auto& wall : walls) {
    names.push_back(wall.name);
    point.push_back(wall.point);
    velocity.push_back(wall.velocity);
    force.push_back(wall.force);
    orientation.push_back(wall.orientation);
    spin.push_back(wall.spin);
    pivot.push_back(wall.pivot);
    pivoted.push_back(wall.pivoted ? 1 : 0);
    torque.push_back(wall.torque);
  }
  f.write_strings("/walls/names", names);
  write_rows(f, "/walls/point", point);
  write_rows(f, "/walls/velocity", velocity);
  write_rows(f, "/walls/force", force);
  write_rows(f, "/walls/orientation", orientation);
  write_rows(f, "/walls/spin", spin);
  write_rows(f, "/walls/pivot", pivot);
  f.write("/walls/pivoted", pivoted);
  write_rows(f, "/walls/torque", torque);
}

template <int D>
void write_neighbors(h5::File& f, const NeighborList<D>& nl, const Families& at) {
  f.write("/neighbors/domain_lo",
          std::vector<double>(nl.domain_lo.data(), nl.domain_lo.data() + D));
  f.write("/neighbors/domain_hi",
          std::vector<double>(nl.domain_hi.data(), nl.domain_hi.data() + D));
  write_rows(f, "/neighbors/x_ref", nl.x_ref, at.grains);
  write_rows(f, "/neighbors/wall_ref", nl.wall_ref);
  write_rows(f, "/neighbors/wall_ref_turn", nl.wall_ref_turn);
  f.write("/neighbors/wall_reach", nl.wall_reach);
  write_flat(f, "/neighbors/pairs/i", nl.pairs.i, at.pairs);
  write_flat(f, "/neighbors/pairs/j", nl.pairs.j, at.pairs);
  write_rows(f, "/neighbors/pairs/shear", nl.pairs.shear, at.pairs);
  write_rows(f, "/neighbors/pairs/force", nl.pairs.force, at.pairs);
  write_flat(f, "/neighbors/wall_pairs/i", nl.wall_pairs.i, at.wall_pairs);
  write_flat(f, "/neighbors/wall_pairs/wall", nl.wall_pairs.wall, at.wall_pairs);
  write_flat(f, "/neighbors/wall_pairs/element", nl.wall_pairs.element, at.wall_pairs);
  write_flat(f, "/neighbors/wall_pairs/feature", nl.wall_pairs.feature, at.wall_pairs);
  write_rows(f, "/neighbors/wall_pairs/shear", nl.wall_pairs.shear, at.wall_pairs);
  write_rows(f, "/neighbors/wall_pairs/force", nl.wall_pairs.force, at.wall_pairs);
  f.write_attr("/neighbors", "skin", nl.skin);
  f.write_attr("/neighbors", "builds", nl.builds);
}

// Rolling springs (contact/rolling.hpp), only for a law with rolling resistance.
template <int D>
void write_rolling(h5::File& f, const NeighborList<D>& nl, const Families& at) {
  if (!nl.rolling) return;
  // The builder, both solvers and load_snapshot keep one spring per entry; padding here would
  // write springs the state hash did not see (an unloadable file).
  if (nl.pairs.roll.size() != nl.pairs.size() || nl.wall_pairs.roll.size() != nl.wall_pairs.size())
    throw std::logic_error("snapshot: the rolling springs do not match the contact lists");
  write_rows(f, "/neighbors/pairs/roll", nl.pairs.roll, at.pairs);
  write_rows(f, "/neighbors/wall_pairs/roll", nl.wall_pairs.roll, at.wall_pairs);
}

// Capillary bridges and the grains' films, only for a wet contact law (world/liquid.hpp).
template <int D>
void write_liquid(h5::File& f, const World<D>& w, const Families& at, bool films) {
  if (!w.neighbors.bridges) return;
  const auto& pl = w.neighbors.pairs;
  write_flat(f, "/neighbors/pairs/bridge",
             pl.bridge.size() == pl.size() ? pl.bridge
                                           : std::vector<double>(pl.size(), PairList<D>::kNoBridge),
             at.pairs);
  // A share writes its films' rows where the sample has films (SnapshotPart::films).
  if (at.grains.rows == nullptr)
    write_flat(f, "/liquid/film", w.liquid.film);
  else if (films)
    write_flat(f, "/liquid/film", w.liquid.film, at.grains);
  else
    write_flat(f, "/liquid/film", std::vector<double>{});
  f.write_attr("/liquid", "total", w.liquid.total);
  f.write_attr("/liquid", "lost", w.liquid.lost);
}

// Polyhedral grains' shapes (world/polyhedral_grains.hpp): each grain's row of the table, and
// the table, only when the run has polyhedra. /shapes/points holds every shape's body-frame
// points, shape k's in rows [first[k], first[k + 1]).
template <int D>
void write_shapes(h5::File& f, const World<D>& w, Rows at) {
  if (w.shapes.empty()) return;
  write_flat(f, "/particles/shape_index", w.particles.shape_index, at);
  std::vector<std::uint64_t> first{0};
  std::vector<double> points, volume, inertia;
  for (std::size_t k = 0; k < w.shapes.size(); ++k) {
    const PolyhedronShape& s = w.shapes[k];
    for (const Eigen::Vector3d& x : s.points) points.insert(points.end(), {x.x(), x.y(), x.z()});
    first.push_back(first.back() + s.points.size());
    volume.push_back(s.volume);
    inertia.insert(inertia.end(), {s.inertia.x(), s.inertia.y(), s.inertia.z()});
  }
  f.write("/shapes/points", points, 3);
  f.write("/shapes/first", first);
  f.write("/shapes/volume", volume);
  f.write("/shapes/inertia", inertia, 3);
}

// Polyhedral contacts' normals, points and depths (world/contact_geometry.hpp), only when the
// run has polyhedra and the solver has written one row per list entry (a World not stepped
// since its lists were made has none). Outputs of the step, not state: the hash leaves them out.
template <int D>
void write_contact_geometry(h5::File& f, const World<D>& w, const Families& at) {
  const ContactPoints<D>& g = w.contact_geometry;
  if (w.shapes.empty() || !g.matches(w.neighbors.pairs.size(), w.neighbors.wall_pairs.size()))
    return;
  // As read_contact_geometry() reads them: one set of datasets per list.
  auto write = [&](const std::string& list, const EntryGeometry<D>& e, const Rows& rows) {
    const std::string base = "/neighbors/" + list + "/";
    write_rows(f, base + "normal", e.normal, rows);
    write_rows(f, base + "arm", e.arm, rows);
    write_rows(f, base + "depth", e.depth, rows);
  };
  write("pairs", g.pairs, at.pairs);
  write("wall_pairs", g.wall_pairs, at.wall_pairs);
}

template <int D>
void write_state(h5::File& f, const World<D>& w, const SnapshotPart<D>* part) {
  const Families at = families_of(part);
  write_particles(f, w.particles, at.grains);
  write_registry(f, w.particles, part);
  write_shapes(f, w, at.grains);
  write_walls(f, w.walls);
  write_neighbors(f, w.neighbors, at);
  write_liquid(f, w, at, part != nullptr && part->films);
  write_rolling(f, w.neighbors, at);
  write_contact_geometry(f, w, at);
}

}  // namespace

template <int D>
void save_snapshot(const World<D>& world, const RunPosition& pos, const std::string& scenario_text,
                   const std::string& path, const std::string& scenario_path) {
  write_atomic(path, [&](const std::string& tmp) {
    h5::File f = h5::File::create(tmp, fmt::format("snapshot '{}'", path));
    write_header(f, world, pos, scenario_text, scenario_path, true);
    write_state<D>(f, world, nullptr);
    f.close();
  });
}

template <int D>
void save_snapshot_part(const SnapshotPart<D>& part, const RunPosition& pos,
                        const std::string& scenario_text, const std::string& path,
                        const std::string& scenario_path) {
  static_assert(std::is_same_v<hid_t, std::int64_t>, "SnapshotPart keeps hid_t values");
  const h5::File::Collective c{part.file_access, part.transfer, part.root};
  h5::File f = h5::File::create(part.temp_path, fmt::format("snapshot '{}'", path), c);
  write_header(f, part.world, pos, scenario_text, scenario_path, false);
  write_state(f, part.world, &part);
  f.close();
}

template <int D>
void seal_snapshot(const std::string& temp, const std::string& path, const World<D>& like) {
  try {
    h5::File f = h5::File::open(temp, fmt::format("snapshot '{}'", path), true);
    const std::uint64_t hash = state_hash_of_file(f, like);
    f.write_attr("/", "state_hash", hash);
    f.close();
  } catch (const InputError& e) {
    // The file was just written here: failing to read it back is an I/O failure.
    std::error_code ec;
    std::filesystem::remove(temp, ec);
    throw IoError(e.what());
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove(temp, ec);
    throw;
  }
  commit_atomic(temp, path);
}

#define SABLE_SNAPSHOT_WRITE(D)                                                                    \
  template void save_snapshot<D>(const World<D>&, const RunPosition&, const std::string&,          \
                                 const std::string&, const std::string&);                          \
  template void save_snapshot_part<D>(const SnapshotPart<D>&, const RunPosition&,                  \
                                      const std::string&, const std::string&, const std::string&); \
  template void seal_snapshot<D>(const std::string&, const std::string&, const World<D>&);
SABLE_SNAPSHOT_WRITE(2)
SABLE_SNAPSHOT_WRITE(3)
#undef SABLE_SNAPSHOT_WRITE

}  // namespace sable
