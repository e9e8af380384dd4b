// A snapshot written as a share (io/snapshot.hpp: save_snapshot_part, then seal_snapshot), the
// way each process of a decomposed run writes its rows: here one process holds every grain,
// but hands its grains, pairs and wall entries over in REVERSE order with the file rows they
// belong at, so every row must land by its row number, not by its place in memory. The sealed
// file must then load (its state hash, computed from the file, checked by load_snapshot) into
// the state of the World, whose id registry is the share's (the sample's grains, no free
// list, as a gathered World holds it). Every comparison is an exact hash equality: one byte
// out of place changes it. (The MPI tests compare real shares with serial snapshots dataset by
// dataset: tests/mpi/run_check.py.)
#include <gtest/gtest.h>
#include <hdf5.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "bed_world.hpp"
#include "mesh_world.hpp"
#include "sable/dem/dem_solver.hpp"
#include "sable/io/snapshot.hpp"
#include "sable/world/state_hash.hpp"

namespace {

using sable::World;
using sable::test::make_world;

class SnapshotPart : public sable::test::TempDirTest {};

template <class T>
void reverse_rows(std::vector<T>& v) {
  std::reverse(v.begin(), v.end());
}

// rows n-1, ..., 0: the file rows of a list handed over backwards.
std::vector<std::uint64_t> backwards(std::size_t n) {
  std::vector<std::uint64_t> rows(n);
  for (std::size_t k = 0; k < n; ++k) rows[k] = n - 1 - k;
  return rows;
}

// The share of a process that holds all of `w`, its arrays reversed.
template <int D>
sable::SnapshotPart<D> reversed_share(const World<D>& w, const std::string& temp) {
  sable::SnapshotPart<D> part;
  part.world = w;
  auto& pw = part.world;
  pw.particles.for_each_array([](auto& a) { reverse_rows(a); });
  reverse_rows(pw.liquid.film);
  reverse_rows(pw.neighbors.x_ref);
  auto& pl = pw.neighbors.pairs;
  for (auto* a : {&pl.i, &pl.j}) reverse_rows(*a);
  for (auto* a : {&pl.shear, &pl.force}) reverse_rows(*a);
  reverse_rows(pl.roll);
  reverse_rows(pl.bridge);
  auto& wl = pw.neighbors.wall_pairs;
  for (auto* a : {&wl.i, &wl.wall, &wl.element, &wl.feature}) reverse_rows(*a);
  for (auto* a : {&wl.shear, &wl.force}) reverse_rows(*a);
  reverse_rows(wl.roll);
  const auto& p = w.particles;
  part.grains = p.size();
  part.pairs = w.neighbors.pairs.size();
  part.wall_pairs = w.neighbors.wall_pairs.size();
  part.grain_rows = backwards(part.grains);
  part.pair_rows = backwards(part.pairs);
  part.wall_pair_rows = backwards(part.wall_pairs);
  for (std::uint32_t s = 0; s < p.size(); ++s) {
    part.registry_rows.push_back(p.id[s].index);
    part.registry_slots.push_back(s);
    part.registry_generations.push_back(p.id[s].generation);
    part.registry = std::max<std::uint64_t>(part.registry, p.id[s].index + 1u);
  }
  part.films = !w.liquid.film.empty();
  part.root = true;
  part.file_access = H5P_DEFAULT;  // one process: HDF5's own file driver
  part.transfer = H5P_DEFAULT;
  part.temp_path = temp;
  return part;
}

// `w` with the id registry a share writes: each grain's index to its slot, nothing else.
template <int D>
World<D> with_share_registry(World<D> w, std::uint64_t entries) {
  std::vector<std::uint32_t> slots(entries, sable::IdRegistry::kNoSlot), generations(entries, 0);
  for (std::uint32_t s = 0; s < w.particles.size(); ++s) {
    slots[w.particles.id[s].index] = s;
    generations[w.particles.id[s].index] = w.particles.id[s].generation;
  }
  w.particles.ids.restore(slots, generations, {});
  return w;
}

template <int D>
void expect_share_loads(const World<D>& w, World<D> loaded, const std::string& dir) {
  const std::string file = dir + "/share.h5", temp = file + ".tmp-share";
  const sable::SnapshotPart<D> part = reversed_share(w, temp);
  sable::save_snapshot_part(part, sable::RunPosition{1, 3}, "scenario", file);
  sable::seal_snapshot(temp, file, w);
  EXPECT_FALSE(std::filesystem::exists(temp)) << "the temporary is renamed over the snapshot";
  const World<D> want = with_share_registry(w, part.registry);
  const sable::RunPosition pos = sable::load_snapshot(file, loaded);
  EXPECT_EQ(pos, (sable::RunPosition{1, 3}));
  EXPECT_EQ(sable::state_hash(loaded), sable::state_hash(want));
  EXPECT_EQ(sable::read_snapshot_info(file).state_hash, sable::state_hash(want));
}

// A 3D bed after 40 steps (contacts with friction history, a tilted moving wall, a drum, a
// fixed grain, a free list in the registry).
TEST_F(SnapshotPart, ReversedShareOfA3DBedLoadsAsTheBed) {
  World<3> w = make_world<3>();
  sable::DemSolver<3> s(w);
  s.initialize();
  for (int k = 0; k < 40; ++k) s.step();
  ASSERT_GT(w.neighbors.pairs.size(), 2u);
  ASSERT_GT(w.neighbors.wall_pairs.size(), 2u);
  ASSERT_FALSE(w.particles.ids.free_list().empty()) << "the registry is rewritten";
  expect_share_loads(w, make_world<3>(false), dir_.string());
}

// 2D disks with rolling resistance: [N x 1] angles and spins, [P x 1] springs.
TEST_F(SnapshotPart, ReversedShareOfA2DRollingBedLoadsAsTheBed) {
  World<2> w = make_world<2>(true, true);
  sable::DemSolver<2> s(w);
  s.initialize();
  for (int k = 0; k < 40; ++k) s.step();
  ASSERT_GT(w.neighbors.pairs.size(), 2u);
  expect_share_loads(w, make_world<2>(false, true), dir_.string());
}

}  // namespace
