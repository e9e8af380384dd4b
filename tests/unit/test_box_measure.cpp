// The state of a sample in a box of plane walls (loading/box_state.hpp), and stress-controlled
// walls with a zero target (loading/servo.hpp): hand-computable cases on worlds built from a
// scenario, no stepping.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <sstream>

#include "polyhedra_helpers.hpp"
#include "sable/core/error.hpp"
#include "sable/loading/box_state.hpp"
#include "sable/loading/servo.hpp"
#include "sable/scenario/build.hpp"
#include "sable/scenario/config.hpp"
#include "sable/world/polyhedral_grains.hpp"

using namespace sable;

namespace {

// n^3 spheres of radius r on a cubic lattice of pitch 2r, filling the box [0, 2nr]^3 exactly
// (every sphere touches its neighbours and the walls, without overlap).
std::string lattice(int n, double r, bool box = true) {
  const double side = 2.0 * n * r;
  std::ostringstream s;
  s.precision(17);
  s << "[simulation]\ndimension = 3\n[domain]\nlo = [0, 0, 0]\nhi = [" << side << ", " << side
    << ", " << side << "]\n[[material]]\nname = \"g\"\ndensity = 2500.0\nyoung = 1e8\n"
    << "poisson = 0.3\nrestitution = 0.3\nfriction = 0.4\n[[grains]]\ngenerator = \"lattice\"\n"
    << "material = \"g\"\nradius = " << r << "\nspacing = " << 2.0 * r
    << "\nregion = { box = { lo = [0, 0, 0], hi = [" << side << ", " << side << ", " << side
    << "] } }\ncount = " << n * n * n << "\n";
  if (box)
    s << "[[wall]]\nname = \"box\"\ntype = \"box\"\nmaterial = \"g\"\nlo = [0, 0, 0]\nhi = ["
      << side << ", " << side << ", " << side << "]\n";
  else
    s << "[[wall]]\nname = \"floor\"\nmaterial = \"g\"\npoint = [0, 0, 0]\nnormal = [0, 0, 1]\n";
  s << "[[stage]]\nsteps = 1\n";
  return s.str();
}

World<3> build(const std::string& text) {
  const ScenarioConfig cfg = parse_scenario(text, "test.toml");
  World<3> w;
  build_model(cfg, w);
  build_grains(cfg, w);
  return w;
}

// Polyhedral grains count their own volumes, not their bounding spheres': two cubes of sides
// 2 and 3 mm (one turned) in the 12 mm box fill (8 + 27) / 1728 of it. 1e-13 relative: the
// hulls' volumes are exact to a few roundings (test_polyhedron_mass.cpp).
TEST(BoxState, PolyhedraCountTheirOwnVolumes) {
  std::string text = lattice(1, 6e-3);  // the box, its grain dropped
  text.erase(text.find("[[grains]]"), text.find("[[wall]]") - text.find("[[grains]]"));
  text.insert(text.find("[domain]"), "dt = 1e-5\n");
  World<3> w = build(text);
  ASSERT_EQ(w.particles.size(), 0u);
  const MaterialIndex m = *w.materials.find("g");
  add_polyhedral_grain(
      w, test::box_points(Eigen::Vector3d(1e-3, 1e-3, 1e-3), Eigen::Vector3d(3e-3, 3e-3, 3e-3)),
      2500.0, m);
  const Eigen::Quaterniond turn(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()));
  add_polyhedral_grain(
      w,
      test::box_points(Eigen::Vector3d(6e-3, 6e-3, 6e-3), Eigen::Vector3d(9e-3, 9e-3, 9e-3), turn,
                       Eigen::Vector3d(7.5e-3, 7.5e-3, 7.5e-3)),
      2500.0, m);
  const auto b = measure_box(w);
  ASSERT_TRUE(b.has_value());
  EXPECT_NEAR(b->grain_volume, 35e-9, 1e-13 * 35e-9);
  EXPECT_NEAR(b->solid_fraction, 35.0 / 1728.0, 1e-13);
}

// A cubic lattice fills pi/6 of its box. The only error is round-off in summing 216 sphere
// volumes and in the box's corners: 1e-13 relative is ~500 ulps, ample.
TEST(BoxState, SolidFractionOfACubicLatticeIsPiOverSix) {
  const World<3> w = build(lattice(6, 1e-3));
  ASSERT_EQ(w.particles.size(), 216u);
  const auto b = measure_box(w);
  ASSERT_TRUE(b.has_value());
  EXPECT_NEAR(b->solid_fraction, std::numbers::pi / 6.0, 1e-13);
  EXPECT_NEAR(b->volume, std::pow(0.012, 3), 1e-13 * std::pow(0.012, 3));
  for (int d = 0; d < 3; ++d) {
    EXPECT_EQ(b->lo[d], 0.0);
    EXPECT_NEAR(b->hi[d], 0.012, 1e-16);
    EXPECT_EQ(b->stress[d], 0.0);  // no force stored yet
  }
}

// A single floor is not a box: no box state (series.csv then has no box columns).
TEST(BoxState, NoBoxWithoutFacingWallsOnEveryAxis) {
  EXPECT_FALSE(measure_box(build(lattice(2, 1e-3, false))).has_value());
}

// The mean wall stress of an axis is the mean of -F.n / A of its two walls, A the product of
// the other two extents; the strain is (L0 - L) / L0, positive in compression. Exact inputs
// (powers of two) give exact results up to one rounding: 1e-15 relative.
TEST(BoxState, StressAndStrainByHand) {
  World<3> w = build(lattice(2, 0.25));  // box [0, 1]^3
  const auto ref = measure_box(w);
  ASSERT_TRUE(ref.has_value());
  // Walls of a box: xlo, xhi, ylo, yhi, zlo, zhi. Move zhi down by 1/8, xhi out by 1/4.
  w.walls[5].point.z() = 0.875;
  w.walls[1].point.x() = 1.25;
  w.walls[4].force = Eigen::Vector3d(0, 0, -3.0);  // pushed down by the grains: compression
  w.walls[5].force = Eigen::Vector3d(0, 0, 5.0);
  const auto b = measure_box(w);
  ASSERT_TRUE(b.has_value());
  EXPECT_NEAR(b->stress.z(), 0.5 * (3.0 + 5.0) / (1.25 * 1.0), 1e-15 * 3.2);
  EXPECT_EQ(b->stress.x(), 0.0);
  const auto eps = box_strain(*b, *ref);
  EXPECT_NEAR(eps.z(), 0.125, 1e-15);
  EXPECT_NEAR(eps.x(), -0.25, 1e-15);  // extension is negative
  EXPECT_EQ(eps.y(), 0.0);
  EXPECT_NEAR(b->solid_fraction,
              8.0 * 4.0 / 3.0 * std::numbers::pi * std::pow(0.25, 3) / (1.25 * 0.875), 1e-15);
}

// A zero target: the error is relative to the given scale, and when every target is 0 the
// default gain is v_max / scale. Without contacts the stability cap does not apply, so the
// wall's speed is exactly gain * sigma (sigma = 0.25 * scale here: a quarter of v_max, outward).
TEST(ServoZeroTarget, ErrorAndDefaultGainUseTheScale) {
  World<3> w = build(lattice(2, 0.25));
  w.walls[5].force = Eigen::Vector3d(0, 0, 25.0);  // zhi, area 1 m^2: sigma = 25 Pa
  const std::vector<ServoTarget> targets{{5, 0.0}};
  EXPECT_NEAR(servo_error(w, targets, 100.0), 0.25, 1e-15);
  EXPECT_THROW(servo_error(w, targets), InputError);  // no scale: no relative error
  servo_walls(w, targets, ServoSettings{0.0, 0.02, 100.0});
  EXPECT_NEAR(w.walls[5].velocity.z(), 0.005, 1e-17);  // +z: away from the grains
  EXPECT_THROW(servo_walls(w, targets, ServoSettings{0.0, 0.02, 0.0}), InputError);
  // A non-zero target is still measured against itself, whatever the scale.
  EXPECT_NEAR(servo_error(w, {{5, 50.0}}, 1e6), 0.5, 1e-15);
}

}  // namespace
