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

// The grains' shape (key `shape`, 3D only): round, the default; random convex polyhedra, one
// per grain; or one convex shape given by its points or by a file's vertices. A polyhedral
// grain is scaled so that its bounding sphere about its centroid has the radius the block's
// radius distribution gives, and sits with its centroid where the generator put the sphere's
// centre: the generators' spheres, which do not overlap, hold polyhedra that do not either.
struct GrainShapeConfig {
  enum class Kind { kSphere, kRandomPolyhedron, kGiven } kind = Kind::kSphere;
  std::size_t vertices = 12;       // random: the points drawn on the unit sphere, in [4, 64]
  Vec3a aspect{1.0, 1.0, 1.0};     // random: the sphere stretched by these along x, y, z, in (0, 1]
  std::vector<Vec3a> points;       // given: the points, when no file
  std::string file;                // given: an STL or OBJ file (read when the grains are built)
  bool random_orientation = true;  // given: each grain turned at random, or as the points stand
  std::string key;                 // "grains[1].shape", for messages
  bool polyhedral() const { return kind != Kind::kSphere; }
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
  GrainShapeConfig shape;
  SourceLoc loc;
};

}  // namespace sable
