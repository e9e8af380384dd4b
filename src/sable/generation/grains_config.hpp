// One [[grains]] block as data: what the generators (generate.hpp) take. The scenario parser
// fills it (scenario/config.hpp holds it in ScenarioConfig); generation reads nothing else of
// the scenario, so it sits below the scenario layer.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "sable/core/source_loc.hpp"

namespace sable {

struct RadiusConfig {
  enum class Kind { kMono, kUniform, kList } kind = Kind::kMono;
  double value = 0.0;          // mono radius, or the mean of the uniform distribution
  double spread = 0.0;         // uniform: relative half-width (0.1 = +-10 %)
  std::vector<double> values;  // list: radii drawn in turn (cycled)
};

struct RegionConfig {
  enum class Kind { kBox, kCylinder } kind = Kind::kBox;
  Vec3a lo{0, 0, 0}, hi{0, 0, 0};  // box
  Vec3a center{0, 0, 0};           // cylinder: axis along z through center (x, y)
  double radius = 0.0;
  double zlo = 0.0, zhi = 0.0;
};

struct GrainsConfig {
  std::string generator = "lattice";  // "lattice" | "random" | "list" | "file"
  std::string material;
  RadiusConfig radius;
  RegionConfig region;
  std::size_t count = 0;
  std::optional<double> spacing;     // lattice spacing; default 2 * max radius
  double jitter = 0.0;               // lattice: uniform +-jitter on every coordinate (m)
  std::string jitter_rng = "sable";  // "sable" | "numpy-pcg64" (bit-compatible with numpy)
  // "square" (cubic in 3D) | "hexagonal": rows (layers) offset by half a spacing, rows
  // sqrt(3)/2 spacing apart in 2D (in 3D: hexagonal layers stacked at the square pitch)
  std::string arrangement = "square";
  std::optional<std::uint64_t> seed;  // default: simulation seed
  std::vector<Vec3a> positions;       // generator = "list"
  std::string file;                   // generator = "file": LAMMPS/LIGGGHTS data file
  Vec3a velocity{0, 0, 0};
  bool fixed = false;
  std::size_t max_attempts = 1000;  // random insertion: tries per grain
  SourceLoc loc;
};

}  // namespace sable
