// Exact restart of a run with a turning mesh wall, and the snapshot's checks of mesh entries.
//
// A paddle mesh turns through a bed of grains (mesh_world.hpp). The run is saved after N
// steps and continued; a world rebuilt without grains (as a resume rebuilds it from the
// scenario) loads the snapshot and continues without re-initializing its solver. Both must
// end bit-identical: state hashes, and the paddle's force, torque, orientation, pose and
// per-element forces, through neighbour-list rebuilds.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "mesh_world.hpp"
#include "sable/core/error.hpp"
#include "sable/io/snapshot.hpp"
#include "sable/world/element_forces.hpp"
#include "sable/world/state_hash.hpp"

namespace {

namespace fs = std::filesystem;
using sable::World;
using sable::test::kPaddle;

class MeshRestart : public sable::test::TempDirTest {};

template <int D>
bool same_orientation(const World<D>& a, const World<D>& b) {
  const auto& qa = a.walls[kPaddle].orientation;
  const auto& qb = b.walls[kPaddle].orientation;
  if constexpr (D == 3)
    return qa.coeffs() == qb.coeffs();
  else
    return qa == qb;
}

template <int D>
void check_mesh_restart(const std::string& file) {
  using Vec = typename sable::Space<D>::Vec;
  constexpr int kBefore = 150, kAfter = 250;
  World<D> a = sable::test::mesh_world<D>();
  sable::DemSolver<D> sa(a);
  sa.initialize();
  for (int s = 0; s < kBefore; ++s) sa.step();
  // The paddle has turned and carries contacts (and so a torque) when the snapshot is taken.
  ASSERT_TRUE(a.walls[kPaddle].turned());
  ASSERT_GT(sable::test::touching(a.neighbors.wall_pairs, kPaddle), 0u);
  ASSERT_NE(sable::Space<D>::rot_norm2(a.walls[kPaddle].torque), 0.0);
  sable::save_snapshot(a, {}, "scenario", file);

  World<D> b = sable::test::mesh_world<D>(false);
  sable::load_snapshot(file, b);
  ASSERT_EQ(sable::state_hash(b), sable::state_hash(a));
  ASSERT_TRUE(same_orientation(a, b));
  ASSERT_TRUE(b.walls[kPaddle].mesh()->vertices() == a.walls[kPaddle].mesh()->vertices())
      << "the loaded pose places the vertices where the run has them";

  const std::uint64_t builds = a.neighbors.builds;
  sable::DemSolver<D> sb(b);  // resumed: no initialize()
  std::size_t elements_touched = 0;
  for (int s = 0; s < kAfter; ++s) {
    sa.step();
    sb.step();
    std::vector<bool> seen(a.walls[kPaddle].elements(), false);
    const auto& wl = a.neighbors.wall_pairs;
    for (std::size_t k = 0; k < wl.size(); ++k)
      if (wl.wall[k] == kPaddle && wl.force[k] != Vec::Zero()) seen[wl.element[k]] = true;
    elements_touched = std::max<std::size_t>(
        elements_touched, static_cast<std::size_t>(std::count(seen.begin(), seen.end(), true)));
  }
  EXPECT_GT(a.neighbors.builds, builds) << "the continuation should rebuild the lists";
  EXPECT_GT(elements_touched, 1u) << "contacts with several of the paddle's elements";
  EXPECT_EQ(sable::state_hash(b), sable::state_hash(a));
  const auto& pa = a.walls[kPaddle];
  const auto& pb = b.walls[kPaddle];
  EXPECT_TRUE(pa.force == pb.force);
  EXPECT_TRUE(pa.torque == pb.torque);
  EXPECT_TRUE(same_orientation(a, b));
  EXPECT_TRUE(pa.point == pb.point);
  EXPECT_TRUE(pa.pivot == pb.pivot);
  EXPECT_TRUE(sable::element_forces(a, kPaddle) == sable::element_forces(b, kPaddle));
  EXPECT_TRUE(pa.force != Vec::Zero());
  EXPECT_EQ(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL), 0) << "leaked HDF5 handles";
}

TEST_F(MeshRestart, TurningMeshRestartIsBitIdentical3D) {
  check_mesh_restart<3>(path("mesh3.h5"));
}
TEST_F(MeshRestart, TurningPolylineRestartIsBitIdentical2D) {
  check_mesh_restart<2>(path("mesh2.h5"));
}

// The uint32 values of dataset `name`.
std::vector<std::uint32_t> read_u32(const std::string& file, const std::string& name) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t d = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
  const hid_t space = H5Dget_space(d);
  std::vector<std::uint32_t> out(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
  if (!out.empty()) H5Dread(d, H5T_NATIVE_UINT32, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data());
  H5Sclose(space);
  H5Dclose(d);
  H5Fclose(f);
  return out;
}

// Overwrites the values of dataset `name` in place.
void write_u32(const std::string& file, const std::string& name,
               const std::vector<std::uint32_t>& values) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  const hid_t d = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
  EXPECT_GE(H5Dwrite(d, H5T_NATIVE_UINT32, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), 0);
  H5Dclose(d);
  H5Fclose(f);
}

// Guards: a wall-list row naming an element beyond its mesh's count (it would index the
// mesh's arrays out of bounds) is refused with the file, the dataset and the row named; the
// world is left untouched.
TEST_F(MeshRestart, ElementBeyondTheMeshIsRefused) {
  World<3> a = sable::test::mesh_world<3>();
  sable::DemSolver<3> sa(a);
  sa.initialize();
  for (int s = 0; s < 150; ++s) sa.step();
  const std::string good = path("good.h5");
  sable::save_snapshot(a, {}, "scenario", good);
  const auto& wl = a.neighbors.wall_pairs;
  // A paddle row that ends its (grain, wall) run: a larger element keeps the rows sorted.
  std::size_t row = wl.size();
  for (std::size_t k = 0; k < wl.size(); ++k)
    if (wl.wall[k] == kPaddle &&
        (k + 1 == wl.size() || wl.i[k + 1] != wl.i[k] || wl.wall[k + 1] != wl.wall[k]))
      row = k;
  ASSERT_LT(row, wl.size()) << "no paddle entry in the wall list";
  const std::uint32_t count = a.walls[kPaddle].elements();
  ASSERT_EQ(count, 12u);

  const std::string bad = path("bad.h5");
  fs::copy_file(good, bad);
  const std::string dataset = "/neighbors/wall_pairs/element";
  std::vector<std::uint32_t> element = read_u32(bad, dataset);
  ASSERT_EQ(element.size(), wl.size());
  element[row] = count;
  write_u32(bad, dataset, element);

  World<3> w = sable::test::mesh_world<3>(false);
  const std::uint64_t before = sable::state_hash(w);
  std::string msg;
  try {
    sable::load_snapshot(bad, w);
    ADD_FAILURE() << "no InputError loading " << bad;
  } catch (const sable::InputError& e) {
    msg = e.what();
  }
  EXPECT_NE(msg.find(bad), std::string::npos) << msg;
  EXPECT_NE(msg.find("'" + dataset + "' row " + std::to_string(row) + " is 12"), std::string::npos)
      << msg;
  EXPECT_NE(msg.find("wall 1 has 12 elements"), std::string::npos) << msg;
  EXPECT_EQ(sable::state_hash(w), before);

  sable::load_snapshot(good, w);  // the good file loads into the same world
  EXPECT_EQ(sable::state_hash(w), sable::state_hash(a));
  EXPECT_EQ(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL), 0) << "leaked HDF5 handles";
}

// The state hash covers a wall's orientation, spin, pivot and torque only for a wall given a
// rotation, and the list's elements and features only with a mesh wall: the worlds of older
// scenarios (planes and cylinders that never turn) keep their hashes.
TEST(MeshStateHash, NewWallFieldsHashOnlyWhereTheyMatter) {
  World<3> w = sable::test::mesh_world<3>();
  sable::DemSolver<3> s(w);
  s.initialize();
  for (int k = 0; k < 20; ++k) s.step();
  const std::uint64_t h = sable::state_hash(w);
  World<3> plain = w;  // the floor never turns: its torque is not hashed
  plain.walls[0].torque.x() += 1.0;
  EXPECT_EQ(sable::state_hash(plain), h);
  World<3> turned = w;  // the paddle turns: its torque is
  turned.walls[kPaddle].torque.x() += 1.0;
  EXPECT_NE(sable::state_hash(turned), h);
  World<3> element = w;  // with a mesh wall the list's elements are hashed
  ASSERT_GT(element.neighbors.wall_pairs.size(), 0u);
  element.neighbors.wall_pairs.element[0] ^= 1u;
  EXPECT_NE(sable::state_hash(element), h);

  World<3> planes = w;  // without one they are not (always 0 there)
  planes.walls.pop_back();
  const std::uint64_t hp = sable::state_hash(planes);
  planes.neighbors.wall_pairs.element[0] ^= 1u;
  planes.neighbors.wall_pairs.feature[0] ^= 1u;
  EXPECT_EQ(sable::state_hash(planes), hp);
}

}  // namespace
