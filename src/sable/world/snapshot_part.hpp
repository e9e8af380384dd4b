// One process's share of a snapshot that the processes of a decomposed run write together
// into one file (parallel HDF5: src/sable/mpi/mpi_snapshot.cpp makes the share,
// io/snapshot.hpp's save_snapshot_part() writes it). The file holds what a serial run's
// snapshot of the same state holds, row for row: the grains in the global order (order_key,
// then id index), each pair list sorted by its grains' global slots, the id registry of the
// whole sample; no process holds more than its own grains to write it.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "sable/world/world.hpp"

namespace sable {

template <int D>
struct SnapshotPart {
  // This process's own grains (no ghosts) in the global order, with their films and list
  // reference positions; the grain entries whose first member is one of them and their wall
  // entries, whose `i` and `j` are GLOBAL slots (rows of the file's grain datasets). Walls,
  // clock, random generator and the lists' scalars as every process holds them.
  World<D> world;
  // Rows over every process, and the file row of each of this process's rows.
  std::uint64_t grains = 0, pairs = 0, wall_pairs = 0;
  std::vector<std::uint64_t> grain_rows, pair_rows, wall_pair_rows;
  // The id registry of the whole sample (as a gathered World's): `registry` entries, every one
  // without a slot (generation 0) but those of this process's grains, at rows `registry_rows`.
  std::uint64_t registry = 0;
  std::vector<std::uint64_t> registry_rows;
  std::vector<std::uint32_t> registry_slots, registry_generations;
  // The grains carry liquid films (wet, or a capillary law's zeros before the wetting): on
  // every process alike, since each writes its films' rows or none does.
  bool films = false;
  // The process that writes the datasets every process holds alike (walls, clock, scenario).
  bool root = false;
  // Parallel HDF5's file-access and transfer property lists (hid_t values) for the processes'
  // communicator, kept open by `lists` (which closes them); the temporary all processes write
  // (the same name on each), renamed over the snapshot once sealed.
  std::int64_t file_access = -1, transfer = -1;
  std::shared_ptr<const void> lists;
  std::string temp_path;
};

}  // namespace sable
