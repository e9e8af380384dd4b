// Grains are generated around bodies: the lattice and random insertion skip every position
// where a grain would overlap a wall beyond the scenario's initial overlap, sit behind a plane,
// or lie inside a closed mesh (the rotating-cylinder study pours grains around a cylinder
// already in place). Exact checks: no generated grain violates the rule, and the count asked
// for is still met.
#include <gtest/gtest.h>

#include <string>

#include "sable/scenario/build.hpp"
#include "sable/scenario/config.hpp"

namespace sable {
namespace {

// A 3D box of grains (generator `gen`) with a closed, faceted horizontal cylinder through its
// middle (radius 4 mm, length 16 mm, 32 facets) and a tilted plane cutting one corner.
std::string scenario(const std::string& gen, int count) {
  return "[simulation]\ndimension = 3\ndt = 1e-6\n[domain]\nlo = [0, 0, 0]\nhi = [0.02, 0.02, "
         "0.02]\n[[material]]\nname = \"g\"\ndensity = 2500.0\nyoung = 5e6\npoisson = 0.3\n"
         "[[grains]]\ngenerator = \"" +
         gen +
         "\"\nmaterial = \"g\"\nradius = 0.5e-3\nregion = { box = { lo = [0, 0, 0], hi = "
         "[0.02, 0.02, 0.02] } }\ncount = " +
         std::to_string(count) +
         "\nseed = 3\n[[wall]]\nname = \"body\"\ntype = \"mesh\"\nmaterial = \"g\"\nshape = { "
         "cylinder = { center = [0.01, 0.01, 0.01], axis = [1, 0, 0], radius = 0.004, length = "
         "0.016, facets = 32 } }\n[[wall]]\nname = \"cut\"\ntype = \"plane\"\nmaterial = "
         "\"g\"\npoint = [0.004, 0, 0]\nnormal = [1, 1, 0]\n[[stage]]\nsteps = 1\n";
}

void expect_clear_of_walls(const std::string& gen, int count) {
  const ScenarioConfig cfg = parse_scenario(scenario(gen, count), "insertion.toml");
  World<3> w;
  build_model(cfg, w);
  build_grains(cfg, w);
  ASSERT_EQ(w.particles.size(), static_cast<std::size_t>(count)) << gen;
  const auto& body = *w.walls[0].mesh();
  ASSERT_TRUE(body.closed());
  int near_body = 0;
  for (std::size_t k = 0; k < w.particles.size(); ++k) {
    const Eigen::Vector3d& x = w.particles.x[k];
    const double r = w.particles.radius[k];
    Eigen::Vector3d n;
    // initial_overlap (default) of the radius at most: what check_initial_state accepts.
    const double allowed = r * (1.0 - cfg.sim.initial_overlap);
    EXPECT_GE(w.walls[0].distance(x, n), allowed) << gen << " grain " << k;
    EXPECT_FALSE(body.encloses(x)) << gen << " grain " << k << " inside the body";
    EXPECT_GE(w.walls[1].distance(x, n), allowed) << gen << " grain " << k << " behind the plane";
    near_body += w.walls[0].distance(x, n) < 4 * r ? 1 : 0;
  }
  EXPECT_GT(near_body, 20) << gen;  // grains were placed right around the body
}

TEST(InsertionAroundWalls, LatticeSkipsTheBodyAndThePlane) {
  expect_clear_of_walls("lattice", 3000);
}

TEST(InsertionAroundWalls, RandomInsertionSkipsTheBodyAndThePlane) {
  expect_clear_of_walls("random", 2000);
}

// The winding-number test of MeshShape::encloses: inside and outside the faceted cylinder,
// near its caps and its facets (margins of 1e-6 m against a 4 mm radius: no round-off doubt).
TEST(InsertionAroundWalls, ClosedMeshKnowsItsInside) {
  const ScenarioConfig cfg = parse_scenario(scenario("lattice", 1), "insertion.toml");
  World<3> w;
  build_model(cfg, w);
  const auto& body = *w.walls[0].mesh();
  const Eigen::Vector3d c(0.01, 0.01, 0.01);
  const double inner = 0.004 * std::cos(3.14159265358979323846 / 32);
  EXPECT_TRUE(body.encloses(c));
  EXPECT_TRUE(body.encloses(c + Eigen::Vector3d(0.008 - 1e-6, 0, 0)));
  EXPECT_FALSE(body.encloses(c + Eigen::Vector3d(0.008 + 1e-6, 0, 0)));
  EXPECT_TRUE(body.encloses(c + Eigen::Vector3d(0.003, 0, inner - 1e-6)));
  EXPECT_FALSE(body.encloses(c + Eigen::Vector3d(0.003, 0, 0.004 + 1e-6)));
  EXPECT_FALSE(body.encloses(Eigen::Vector3d(0, 0, 0)));
}

}  // namespace
}  // namespace sable
