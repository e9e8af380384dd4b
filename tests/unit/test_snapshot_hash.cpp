// The state hash of a snapshot streamed from its file (io/snapshot_hash.hpp), as process 0 of a
// decomposed run computes it after a collective write: it must be the bits state_hash gives
// for the whole state in memory.
//
// Each world is saved, then hashed from the file against `like`, a copy of the world with its
// grains and lists emptied (nothing per grain or per contact left in it), in blocks of 1, 7
// and 65536 rows: one row at a time, blocks that end inside each dataset, and every dataset
// in one block. Every comparison is an exact equality of 64-bit hashes: the hash covers every
// bit of the state, so any tolerance would hide a misplaced byte.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "bed_world.hpp"
#include "mesh_world.hpp"
#include "sable/core/error.hpp"
#include "sable/dem/dem_solver.hpp"
#include "sable/io/hdf5_file.hpp"
#include "sable/io/snapshot.hpp"
#include "sable/io/snapshot_hash.hpp"
#include "sable/world/liquid.hpp"
#include "sable/world/state_hash.hpp"

namespace {

using sable::World;
using sable::test::make_world;
using sable::test::mesh_world;

class SnapshotHash : public sable::test::TempDirTest {};

// `w` with every per-grain and per-contact array emptied: its walls, clock, generator, and
// the flags that choose what is hashed stay. A hash of the file against it equal to
// state_hash(w) can only have taken the grains and contacts from the file.
template <int D>
World<D> emptied(const World<D>& w) {
  World<D> like = w;
  like.particles = sable::ParticleStore<D>();
  like.neighbors.pairs = sable::PairList<D>();
  like.neighbors.wall_pairs = sable::WallPairList<D>();
  like.neighbors.x_ref.clear();
  like.liquid.film.clear();
  return like;
}

// Saves `w` to `file` and expects the hash streamed from it, in blocks of 1, 7 and 65536
// rows, to be state_hash(w) bit for bit (and the file's own attribute to be it too).
template <int D>
void expect_file_hash(const World<D>& w, const std::string& file) {
  ASSERT_GT(w.particles.size(), 7u) << "blocks of 7 rows should split the grains";
  ASSERT_GT(w.neighbors.pairs.size() + w.neighbors.wall_pairs.size(), 7u);
  sable::save_snapshot(w, sable::RunPosition{1, 3}, "scenario", file);
  const World<D> like = emptied(w);
  const std::uint64_t want = sable::state_hash(w);
  ASSERT_NE(sable::state_hash(like), want) << "the emptied world alone must not give the hash";
  {
    const auto f = sable::h5::File::open(file, "snapshot '" + file + "'");
    for (const std::size_t block : {std::size_t{1}, std::size_t{7}, std::size_t{65536}})
      EXPECT_EQ(sable::state_hash_of_file(f, like, block), want) << "blocks of " << block;
  }
  EXPECT_EQ(sable::read_snapshot_info(file).state_hash, want);
  EXPECT_EQ(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL), 0) << "leaked HDF5 handles";
}

// `steps` DEM steps of `w` from a fresh start.
template <int D>
void run(World<D>& w, int steps) {
  sable::DemSolver<D> s(w);
  s.initialize();
  for (int k = 0; k < steps; ++k) s.step();
}

// Contacts that carry a friction history (a non-zero shear), as a snapshot must carry it.
template <class List>
std::size_t sheared(const List& list) {
  return static_cast<std::size_t>(std::count_if(
      list.shear.begin(), list.shear.end(), [](const auto& s) { return s.squaredNorm() > 0.0; }));
}

// A dry bed after 40 steps (touching, sheared contacts with walls and between grains, a
// fixed grain, a reused id and a free id entry), in 2D (angles and spins as [N x 1] rows)
// and in 3D (quaternions stored w, x, y, z): the streamed hash is state_hash's, exactly.
TEST_F(SnapshotHash, DemBed2D) {
  World<2> w = make_world<2>();
  run(w, 40);
  ASSERT_GT(sheared(w.neighbors.pairs), 0u);
  expect_file_hash(w, path("bed2.h5"));
}

TEST_F(SnapshotHash, DemBed3D) {
  World<3> w = make_world<3>();
  run(w, 40);
  ASSERT_GT(sheared(w.neighbors.pairs), 0u);
  ASSERT_GT(sheared(w.neighbors.wall_pairs), 0u);
  ASSERT_FALSE(w.particles.q.empty());
  expect_file_hash(w, path("bed3.h5"));
}

// Rolling resistance: the lists' springs (a [P x 1] angle per contact in 2D, a vector in
// 3D) are hashed from the file, exactly.
TEST_F(SnapshotHash, RollingBeds) {
  World<2> w2 = make_world<2>(true, true);
  run(w2, 40);
  ASSERT_TRUE(std::any_of(w2.neighbors.pairs.roll.begin(), w2.neighbors.pairs.roll.end(),
                          [](double th) { return th != 0.0; }));
  expect_file_hash(w2, path("rolling2.h5"));
  World<3> w3 = make_world<3>(true, true);
  run(w3, 40);
  ASSERT_TRUE(std::any_of(w3.neighbors.wall_pairs.roll.begin(), w3.neighbors.wall_pairs.roll.end(),
                          [](const auto& th) { return th.squaredNorm() > 0.0; }));
  expect_file_hash(w3, path("rolling3.h5"));
}

// A wet bed (capillary cohesion, 3D only): bridges, and films left by bridges torn apart as
// the top layer is thrown upwards. Bridges and films come from the file, the liquid totals
// from `like`; the hash is state_hash's, exactly.
TEST_F(SnapshotHash, WetBed) {
  World<3> w = make_world<3>();
  w.model.cohesion = sable::CohesionModel::kCapillary;
  w.neighbors.bridges = true;
  sable::DemSolver<3> s(w);
  s.initialize();
  sable::wet_grains(w, 0.01, 1000.0);
  for (std::size_t k = 0; k < w.particles.size(); ++k)
    if (w.particles.x[k].z() > 4.0 * sable::test::kBedR) w.particles.v[k].z() = 1.0;
  for (int k = 0; k < 300; ++k) s.step();
  const auto& bridge = w.neighbors.pairs.bridge;
  const auto& film = w.liquid.film;
  ASSERT_TRUE(std::any_of(bridge.begin(), bridge.end(), [](double b) { return b > 0.0; }));
  ASSERT_TRUE(std::any_of(film.begin(), film.end(), [](double v) { return v > 0.0; }));
  expect_file_hash(w, path("wet.h5"));
}

// A turning mesh wall (mesh_world.hpp's paddle, in 2D and 3D) in contact: the wall pairs'
// elements and features come from the file; the paddle's pose, its reference turn and the
// walls' reaches from `like`. The hash is state_hash's, exactly.
TEST_F(SnapshotHash, MeshWalls) {
  World<2> w2 = mesh_world<2>();
  run(w2, 150);
  ASSERT_GT(sable::test::touching(w2.neighbors.wall_pairs, sable::test::kPaddle), 0u);
  expect_file_hash(w2, path("mesh2.h5"));
  World<3> w3 = mesh_world<3>();
  run(w3, 150);
  ASSERT_TRUE(w3.walls[sable::test::kPaddle].turned());
  ASSERT_GT(sable::test::touching(w3.neighbors.wall_pairs, sable::test::kPaddle), 0u);
  expect_file_hash(w3, path("mesh3.h5"));
}

// Walls that turn or are pivoted (a plane and a cylinder, no mesh): their orientations, spins,
// pivots, torques and reference turns are hashed from `like`, the grains from the file; the
// hash is state_hash's, exactly.
TEST_F(SnapshotHash, TurningAndPivotedWalls) {
  World<2> w2 = make_world<2>();
  w2.walls[1].set_rotation(w2.walls[1].point, Eigen::Vector2d::Zero(),
                           0.5);  // the ramp turns slowly
  run(w2, 40);
  ASSERT_TRUE(w2.walls[1].turned());
  expect_file_hash(w2, path("turning2.h5"));
  World<3> w3 = make_world<3>();
  w3.walls[1].set_rotation(w3.walls[1].point, {0.0, 0.0, 1.0}, 0.0);  // pivoted, still
  w3.walls[2].set_rotation(w3.walls[2].point, {0.0, 0.0, 1.0}, 2.0);  // the drum turns
  run(w3, 40);
  ASSERT_TRUE(w3.walls[2].turned());
  ASSERT_TRUE(w3.walls[1].moves_about() && !w3.walls[1].turned());
  expect_file_hash(w3, path("turning3.h5"));
}

// The hash can fail: one velocity component of one grain moved by one unit in the last place
// (the dataset rewritten in the file) gives another hash, for every block size. Exact
// inequality: a one-bit change must show.
TEST_F(SnapshotHash, OneChangedVelocityChangesTheHash) {
  World<3> w = make_world<3>();
  run(w, 40);
  const std::string file = path("changed.h5");
  sable::save_snapshot(w, {}, "scenario", file);
  {
    auto f = sable::h5::File::open(file, "snapshot", /*writable=*/true);
    std::vector<double> v = f.read<double>("/particles/v", 3);
    v[3 * 5 + 1] = std::nextafter(v[3 * 5 + 1], 1.0);
    ASSERT_GE(H5Ldelete(f.id(), "/particles/v", H5P_DEFAULT), 0);
    f.write("/particles/v", v, 3);
    f.close();
  }
  const World<3> like = emptied(w);
  const auto f = sable::h5::File::open(file, "snapshot");
  for (const std::size_t block : {std::size_t{1}, std::size_t{7}, std::size_t{65536}})
    EXPECT_NE(sable::state_hash_of_file(f, like, block), sable::state_hash(w))
        << "blocks of " << block;
  World<3> moved = w;
  moved.particles.v[5].y() = std::nextafter(moved.particles.v[5].y(), 1.0);
  EXPECT_EQ(sable::state_hash_of_file(f, like, 7), sable::state_hash(moved))
      << "the changed file holds exactly the moved velocity";
}

// An optional dataset the file lacks hashes as load_snapshot restores it: no
// '/particles/order_key' as the slots' order (row k is k), no wall-pair elements and features
// (with a mesh wall) as 0. Exact equality with state_hash of the world so restored.
TEST_F(SnapshotHash, AbsentOptionalDatasetsHashAsLoadRestoresThem) {
  World<3> w = mesh_world<3>();
  run(w, 150);
  const std::string file = path("old.h5");
  sable::save_snapshot(w, {}, "scenario", file);
  {
    auto f = sable::h5::File::open(file, "snapshot", /*writable=*/true);
    for (const char* name :
         {"/particles/order_key", "/neighbors/wall_pairs/element", "/neighbors/wall_pairs/feature"})
      ASSERT_GE(H5Ldelete(f.id(), name, H5P_DEFAULT), 0) << name;
    f.close();
  }
  World<3> restored = w;
  for (std::size_t k = 0; k < restored.particles.size(); ++k) restored.particles.order_key[k] = k;
  auto& wl = restored.neighbors.wall_pairs;
  std::fill(wl.element.begin(), wl.element.end(), 0u);
  std::fill(wl.feature.begin(), wl.feature.end(), 0u);
  ASSERT_NE(sable::state_hash(restored), sable::state_hash(w));
  const auto f = sable::h5::File::open(file, "snapshot");
  for (const std::size_t block : {std::size_t{1}, std::size_t{7}, std::size_t{65536}})
    EXPECT_EQ(sable::state_hash_of_file(f, emptied(w), block), sable::state_hash(restored))
        << "blocks of " << block;
}

// h5::File::read_block: every block of rows is the same values as the whole dataset read at
// once (exact: the same stored doubles), and rows past the end, or a dataset of another
// shape, are an InputError naming the file and the dataset.
TEST_F(SnapshotHash, ReadBlockReadsRowsAndRefusesRowsPastTheEnd) {
  World<3> w = make_world<3>();
  run(w, 5);
  const std::string file = path("blocks.h5");
  sable::save_snapshot(w, {}, "scenario", file);
  const auto f = sable::h5::File::open(file, "snapshot 'blocks.h5'");
  const std::vector<double> x = f.read<double>("/particles/x", 3);
  const std::size_t n = x.size() / 3;
  for (std::size_t first = 0; first < n; first += 5) {
    const std::size_t count = std::min<std::size_t>(5, n - first);
    std::vector<double> block(3 * count);
    f.read_block("/particles/x", 3, first, count, block.data());
    EXPECT_TRUE(std::equal(block.begin(), block.end(), x.begin() + 3 * first)) << first;
  }
  std::vector<double> out(3 * 2);
  try {
    f.read_block("/particles/x", 3, n - 1, 2, out.data());
    ADD_FAILURE() << "rows past the end should be refused";
  } catch (const sable::InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("blocks.h5"), std::string::npos) << msg;
    EXPECT_NE(msg.find("'/particles/x' has " + std::to_string(n) + " rows"), std::string::npos)
        << msg;
  }
  EXPECT_THROW(f.read_block("/particles/x", 2, 0, 1, out.data()), sable::InputError);
  EXPECT_THROW(f.read_block("/particles/nothing", 0, 0, 1, out.data()), sable::InputError);
}

}  // namespace
