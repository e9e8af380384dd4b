// A small world with a turning mesh wall, built by hand, for the restart and output tests of
// mesh walls (test_mesh_restart.cpp, test_mesh_outputs.cpp).
//
// A paddle (the closed surface of a box: 12 triangles in 3D, a rectangle of 4 segments in 2D)
// turns at kPaddleRate about z through the origin, among rows of grains that rest on a plane
// floor beside its long faces: within a few hundred steps it sweeps into them.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "bed_world.hpp"
#include "sable/dem/dem_solver.hpp"
#include "sable/geometry/surface_mesh.hpp"
#include "sable/world/world.hpp"

namespace sable::test {

inline constexpr double kMeshR = 0.005;      // grain radius (m)
inline constexpr double kPaddleRate = 50.0;  // rad/s
inline constexpr std::size_t kPaddle = 1;    // the paddle's wall index (the floor is 0)

// The grains' centres: rows along x beside the paddle's long faces (3D: on the floor, and
// a second layer on the inner rows; 2D: two rows above the paddle, one below it on the floor).
template <int D>
std::vector<typename Space<D>::Vec> mesh_world_grains() {
  using Vec = typename Space<D>::Vec;
  std::vector<Vec> x;
  for (int i = -4; i <= 4; ++i) {
    const double cx = 0.0105 * i;
    if constexpr (D == 3) {
      const double z0 = 0.98 * kMeshR;
      for (double y : {-0.02, -0.0095, 0.0095, 0.02}) x.push_back(Vec(cx, y, z0));
      for (double y : {-0.0095, 0.0095}) x.push_back(Vec(cx, y, z0 + 0.0105));
    } else {
      for (double y : {-0.0095, 0.0095, 0.02}) x.push_back(Vec(cx, y));
    }
  }
  return x;
}

// `with_grains = false`: the world a resumed run builds before loading a snapshot.
template <int D>
World<D> mesh_world(bool with_grains = true) {
  using Vec = typename Space<D>::Vec;
  World<D> w;
  const Material glass = add_glass_and_steel(w.materials);
  w.dt = 1.0e-5;
  w.gravity[D - 1] = -9.81;
  w.rng.reseed(11);
  Wall<D> floor;
  floor.name = "floor";
  floor.material = 1;
  floor.set_plane(Vec::Unit(D - 1));
  if constexpr (D == 2) floor.point = Vec(0.0, -0.0095 - 0.98 * kMeshR);
  w.walls.push_back(floor);
  Wall<D> paddle;
  paddle.name = "paddle";
  paddle.material = 1;
  if constexpr (D == 3)
    paddle.set_mesh(box_surface<3>(Vec(-0.03, -0.004, 0.002), Vec(0.03, 0.004, 0.03), "paddle"));
  else
    paddle.set_mesh(box_surface<2>(Vec(-0.03, -0.004), Vec(0.03, 0.004), "paddle"));
  Vec up = Vec::Zero();
  if constexpr (D == 3) up.z() = 1.0;
  paddle.set_rotation(Vec::Zero(), up, kPaddleRate);
  w.walls.push_back(paddle);
  w.neighbors.skin = 0.04 * kMeshR;
  w.neighbors.domain_lo = Vec::Constant(-0.06);
  w.neighbors.domain_hi = Vec::Constant(0.06);
  w.neighbors.domain_lo[D - 1] = D == 3 ? 0.0 : -0.02;
  if (!with_grains) return w;
  for (const Vec& x : mesh_world_grains<D>()) {
    const double r = kMeshR * (1.0 + w.rng.uniform(-0.01, 0.01));
    const auto id = w.particles.add(x, r, glass.density, 0, w.thickness);
    const auto k = w.particles.ids.slot(id);
    for (int d = 0; d < D; ++d) w.particles.v[k][d] = w.rng.uniform(-0.01, 0.01);
  }
  return w;
}

// Non-zero forces in `list` (touching contacts), optionally only those with wall `wall`.
template <class List>
std::size_t touching(const List& list, std::size_t wall = ~std::size_t{0}) {
  std::size_t n = 0;
  for (std::size_t k = 0; k < list.force.size(); ++k)
    if ((list.force[k].array() != 0.0).any() && (wall == ~std::size_t{0} || list.wall[k] == wall))
      ++n;
  return n;
}

// A test with a fresh temporary folder of its own (named after the suite, the test and the
// process), removed after it.
class TempDirTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = std::filesystem::temp_directory_path() /
           ("sable_" + std::string(info->test_suite_name()) + "_" + std::to_string(::getpid()) +
            "_" + info->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::filesystem::path dir_;
};

}  // namespace sable::test
