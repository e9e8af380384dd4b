// The scenarios of the stress-control tests (test_servo.cpp for DEM, test_servo_cd.cpp for
// contact dynamics): a loose random packing in a box whose walls are all stress-controlled,
// compacted "until equilibrium", and the check of the end-of-stage snapshot.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <sstream>
#include <string>

#include "sable/io/snapshot.hpp"
#include "sable/loading/servo.hpp"
#include "sable/scenario/build.hpp"
#include "sable/scenario/config.hpp"

namespace sable::test {

struct Compaction {
  int dim = 2;
  std::string out = "unused";  // [output].dir
  double pressure = 1000.0;    // Pa on every wall of the box
  std::string extra_stage_keys;
  // Contact dynamics when dt > 0 (it has no automatic time step); DEM otherwise.
  double dt = 0.0;
  double side = 0.0;  // box side (m); 0: 0.04 in 2D, 0.02 in 3D
  int count = 0;      // grains; 0: 200 in 2D, 250 in 3D
  std::uint64_t max_steps = 400000;
  std::uint64_t check_interval = 500;
  std::string kinetic_energy_below = "1e-8";  // J, translational (rattlers may spin forever)
};

// Radius 1 mm +- 20 %, friction 0.3, 2D thickness 2 mm, walls of the grains' material; the one
// stage "compact" ends when the kinetic energy is below a bound (1e-8 J by default) and every
// wall is within 1 % of the pressure. CD: shuffled NLGS sweeps (seeded: reproducible), tolerance
// 1e-4.
inline std::string compaction_text(const Compaction& c) {
  const bool three = c.dim == 3, cd = c.dt > 0.0;
  const double side = c.side > 0.0 ? c.side : (three ? 0.02 : 0.04);
  std::ostringstream corner;
  corner << "[" << side << ", " << side << (three ? ", " : "");
  if (three) corner << side;
  corner << "]";
  const std::string hi = corner.str();
  const std::string lo = three ? "[0, 0, 0]" : "[0, 0]";
  std::ostringstream s;
  s << "[simulation]\ndimension = " << c.dim << "\n";
  if (cd) s << "solver = \"cd\"\ndt = " << c.dt << "\n";
  s << "seed = 3\n"
    << (three ? "" : "thickness = 0.002\n") << "[domain]\nlo = " << lo << "\nhi = " << hi
    << "\n[[material]]\nname = \"g\"\ndensity = 2500.0\nyoung = 1e8\npoisson = 0.3\n"
    << "restitution = 0.3\nfriction = 0.3\n";
  if (cd) s << "[cd]\nsweep = \"shuffled\"\ntolerance = 1e-4\nmax_iterations = 500\n";
  s << "[[grains]]\ngenerator = \"random\"\nmaterial = \"g\"\n"
    << "radius = { distribution = \"uniform\", mean = 1e-3, spread = 0.2 }\n"
    << "region = { box = { lo = " << lo << ", hi = " << hi
    << " } }\ncount = " << (c.count > 0 ? c.count : (three ? 250 : 200))
    << "\n[[wall]]\nname = \"box\"\ntype = \"box\"\nmaterial = \"g\"\n"
    << "lo = " << lo << "\nhi = " << hi << "\n[[stage]]\nname = \"compact\"\n"
    << "wall_stress = { box = " << c.pressure << " }\nservo_max_velocity = 0.05\n"
    << "kinetic_energy_below = " << c.kinetic_energy_below
    << "\nkinetic_energy_of = \"translation\"\nstress_tolerance = 0.01\nmax_steps = " << c.max_steps
    << "\ncheck_interval = " << c.check_interval << "\n"
    << c.extra_stage_keys << "[output]\ndir = \"" << c.out
    << "\"\ncsv_interval = 0\nlog_interval = 0\n";
  return s.str();
}

// What "compacted" means: near the random loose packing of frictional grains, less what the
// walls cost. Frictional disks (mu = 0.3) pack loosely at about 0.80 in the bulk; the layer
// half a diameter thick along the walls of a box 20 diameters wide holds a tenth of its area
// at about half the density, so about 0.76: the bound 0.74 (measured 0.775 DEM, 0.781 CD at
// these seeds). Frictional spheres pack loosely at about 0.55 in the bulk (Onoda & Liniger
// 1990); a box 10 diameters wide loses about a seventh to its six walls' layers, so about
// 0.47: the bound 0.45 (measured 0.515 DEM, 0.484 CD). The loose start is 0.4 (2D) and 0.13
// (3D).
inline constexpr double kMinSolidFraction2D = 0.74;
inline constexpr double kMinSolidFraction3D = 0.45;

// The end-of-stage-1 snapshot of `text` (run with outputs into `dir`): every wall of the box
// within `tolerance` (relative) of `pressure`, and the box shrunk below 90 % of its initial
// area (the loose packing was compacted; it starts at a solid fraction of about 0.4 in 2D and
// 0.13 in 3D, so any real compaction passes this).
//
// The stress is also measured without the servo's own functions (wall_normal_stress,
// wall_area), so that an error shared by the controller and its check cannot pass: the force
// on each wall is summed from the contact forces its wall contacts carry (the neighbour
// list's, force on the grain: the wall gets minus it), and its area is the box's extent
// between the walls facing the other axes (times the thickness in 2D). The sum must match
// the wall's accumulated force to round-off (1e-9 relative: the same forces summed in another
// order), and the stress the pressure within `tolerance`. The solid fraction (grain volume
// over the box's) must exceed `min_solid_fraction`: kMinSolidFraction2D / 3D below.
template <int D>
void expect_compacted(const std::string& text, const std::filesystem::path& dir, double pressure,
                      double tolerance, double side, double min_solid_fraction) {
  const ScenarioConfig cfg = parse_scenario(text, "test.toml");
  World<D> w;
  build_model(cfg, w);
  load_snapshot((dir / "snapshots" / "end_of_stage_1.h5").string(), w);
  ASSERT_EQ(w.walls.size(), static_cast<std::size_t>(2 * D));
  // Box walls come in pairs lo, hi per axis (box.xlo, box.xhi, box.ylo, ...).
  std::array<double, D> extent{};
  for (int d = 0; d < D; ++d) extent[d] = w.walls[2 * d + 1].point[d] - w.walls[2 * d].point[d];
  const double depth = D == 2 ? w.thickness : 1.0;
  double box = depth;
  for (int d = 0; d < D; ++d) box *= extent[d];
  const auto& wl = w.neighbors.wall_pairs;
  for (std::size_t k = 0; k < w.walls.size(); ++k) {
    const int axis = static_cast<int>(k) / 2;
    typename Space<D>::Vec on_wall = Space<D>::Vec::Zero();
    for (std::size_t c = 0; c < wl.size(); ++c)
      if (wl.wall[c] == k) on_wall -= wl.force[c];
    const double area = box / extent[axis];
    const double stress = -on_wall.dot(w.walls[k].normal()) / area;
    EXPECT_NEAR(stress, pressure, tolerance * pressure) << w.walls[k].name;
    EXPECT_NEAR(stress, wall_normal_stress(w, k), 1e-9 * pressure) << w.walls[k].name;
  }
  EXPECT_LT(box, (D == 3 ? side * side * side : side * side * 0.002) * 0.9);
  double grains = 0.0;
  for (std::size_t i = 0; i < w.particles.size(); ++i) {
    const double r = w.particles.radius[i];
    grains += D == 2 ? std::numbers::pi * r * r * depth : 4.0 / 3.0 * std::numbers::pi * r * r * r;
  }
  EXPECT_GT(grains / box, min_solid_fraction);
}

}  // namespace sable::test
