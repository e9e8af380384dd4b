// The scenario as data: what a TOML file says, validated, before any grain exists.
//
// The parser (parse.cpp) fills these plain structs and rejects bad input with the file, line,
// column and what was expected. build.hpp turns a ScenarioConfig into a World<D>. Vectors are
// 3-arrays whatever the dimension: a 2D scenario gives 2 components and the parser pads z = 0.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "sable/core/material.hpp"
#include "sable/core/source_loc.hpp"
#include "sable/generation/grains_config.hpp"
#include "sable/io/vtk_xml.hpp"

namespace sable {

// Bounds on a DEM time step, in critical times (build.hpp: check_time_step): above the first
// `check` and `run` warn, above the second they refuse. Measured on head-on
// collisions with e = 0.6 (docs/contact-laws.md, "Time step"): up to 0.3 the restitution
// stays within 10 % of e, as at the default 0.2; from 0.4 to 0.6 it strays by up to 20 %; at
// 0.7 by 50 %, and at 0.8 a collision gains energy.
inline constexpr double kTimeStepWarning = 0.3;
inline constexpr double kTimeStepError = 0.7;

struct SimulationConfig {
  int dimension = 3;
  std::string solver = "dem";  // "dem" now; "cd" with the contact-dynamics issue
  std::uint64_t seed = 0;
  std::optional<double> dt;  // fixed time step (s); absent = automatic
  double dt_safety = 0.2;    // automatic dt = dt_safety * critical time (see docs)
  Vec3a gravity{0.0, 0.0, 0.0};
  double thickness = 1.0;         // 2D only: out-of-plane depth (m) for masses
  std::optional<double> skin;     // neighbour-list skin (m); absent = 0.5 * min radius... see build
  double overlap_warning = 0.05;  // warn when an overlap exceeds this fraction of the radius
  // The largest overlap two grains, or a grain and a wall, may start with, as a fraction of
  // the smaller radius (scenario/initial_state.hpp); above it `check` and `run` refuse.
  double initial_overlap = 0.01;
  double max_speed = 1.0e3;       // m/s; a faster grain is a runaway and stops the run
  bool track_orientation = true;  // integrate the grains' orientations (see docs/scenario.md)
  // Neighbour builds between cell-order sorts (0: never); absent ("auto"): World's default.
  std::optional<std::uint64_t> reorder_every;
};

// Contact dynamics (solver = "cd"): Moreau-Jean time stepping and the NLGS contact solver.
struct CdConfig {
  double theta = 0.5;                        // in [0.5, 1]: weight of end-of-step smooth forces
  double tolerance = 1e-4;                   // NLGS stops when the criterion falls below it
  std::uint64_t max_iterations = 1000;       // NLGS sweeps per step at most
  std::string criterion = "natural";         // "natural" | "quad" | "maxm"
  std::string local_solver = "bipotential";  // "bipotential" | "exact"
  std::string sweep = "forward";             // "forward" | "alternating" | "shuffled" | "coloured"
  std::uint64_t colour_block = 256;          // "coloured": contacts per block
  double relaxation = 1.0;                   // in (0, 2)
  bool warm_start = true;                    // start each step from the last step's impulses
  std::uint64_t newton_iterations = 0;       // Newton steps where the NLGS stops short (0: none)
  double overlap_recovery = 0.0;             // in [0, 1]: share of an overlap removed per step
  std::string residual_checks = "every_sweep";  // "every_sweep" | "spaced" (cd/nlgs.hpp)
  SourceLoc loc;
};

struct DomainConfig {
  Vec3a lo{0, 0, 0};
  Vec3a hi{0, 0, 0};
  SourceLoc loc;
};

struct MaterialConfig {
  Material material;
  bool friction_given = false;     // the file sets `friction` (else the default 0)
  bool restitution_given = false;  // the file sets `restitution` (else the default 1)
  SourceLoc loc;
};

struct PairOverrideConfig {
  std::string a, b;
  std::optional<double> friction;
  std::optional<double> restitution;
  std::optional<double> rolling_friction;
  SourceLoc loc;
};

struct ContactConfig {
  std::string normal = "hertz";        // registry name: "hertz" | "linear"
  std::string tangential = "history";  // registry name: "history" | "none"
  bool attractive_damping = false;     // allow the damped normal force to pull (LIGGGHTS does)
  bool keep_spring_length = true;      // false: only project the spring (LIGGGHTS 3.8)
  double kn = 0.0;                     // linear law normal stiffness (N/m)
  double kt = 0.0;                     // linear law tangential stiffness (N/m)
  // Cohesion sub-model: "none" | "capillary" (liquid bridges, contact/capillary.hpp).
  std::string cohesion = "none";
  double surface_tension = 0.0728;         // N/m (water, 20 C)
  double contact_angle_deg = 0.0;          // degrees; 0 = perfectly wetting (the paper's)
  double capillary_c = 0.9;                // constant c of the decay length (eq. 6)
  std::string ruptured_liquid = "grains";  // "grains" | "lost" (world/liquid.hpp)
  // Rolling sub-model: "none" | "epsd" (contact/rolling.hpp); eta_r, a fraction of critical.
  std::string rolling = "none";
  double rolling_damping = 0.3;
  SourceLoc loc;
};

// A wall's turning (Wall::set_rotation): `rate` (rad/s) about the line through `point` along
// `axis` (3D, right-hand rule; any non-zero length); in 2D about z through `point`, positive
// counter-clockwise. rate = 0: not turning, but `point` is the pivot the torque is taken about.
struct RotationConfig {
  Vec3a point{0, 0, 0};
  Vec3a axis{0, 0, 1};
  double rate = 0.0;
};

// The surface of a mesh wall (type = "mesh"): an STL file (3D) or one built-in shape
// (geometry/surface_mesh.hpp), made when the world is built (scenario/build.cpp).
struct MeshConfig {
  std::string file;       // the STL file, relative paths resolved against the scenario's folder
  double scale = 1.0;     // file only: each corner x is read as scale * x + offset
  Vec3a offset{0, 0, 0};  // file only (m)
  std::string shape;      // without a file: "cylinder" (3D), "circle" (2D), "box", "polyline" (2D)
  Vec3a center{0, 0, 0};  // cylinder, circle
  Vec3a axis{0, 0, 1};    // cylinder
  double radius = 0.0;    // cylinder, circle (m)
  double length = 0.0;    // cylinder (m)
  int facets = 32;        // cylinder, circle: sides round the axis
  int segments = 1;       // cylinder: rows of facets along the length
  bool caps = true;       // cylinder: closed ends
  Vec3a lo{0, 0, 0}, hi{0, 0, 0};  // box
  std::vector<Vec3a> points;       // polyline: its corners in order
  bool closed = false;             // polyline: a last segment back to the first point
  // The scenario key that gives the surface, for messages: "wall[0].file" or
  // "wall[0].shape.cylinder".
  std::string key;
};

struct WallConfig {
  std::string name;
  std::string type = "plane";  // "plane" | "box" | "cylinder" | "mesh"
  std::string material;
  Vec3a point{0, 0, 0}, normal{0, 0, 0};  // plane
  Vec3a lo{0, 0, 0}, hi{0, 0, 0};         // box: expands to planes NAME.xlo, NAME.xhi, ...
  Vec3a center{0, 0, 0};                  // cylinder (inside), axis along z
  double radius = 0.0;
  MeshConfig mesh;  // mesh
  Vec3a velocity{0, 0, 0};
  std::optional<RotationConfig> rotation;  // turning from the start (not a box)
  SourceLoc loc;
};

struct StageConfig {
  std::string name;
  std::optional<std::uint64_t> steps;          // run exactly this many steps
  std::optional<double> kinetic_energy_below;  // or run until KE < bound (J) ...
  std::uint64_t max_steps = 0;                 // ... but at most this many steps (required then)
  std::uint64_t check_interval = 100;          // steps between kinetic-energy checks
  // kinetic_energy_of = "translation": the bound applies to the translational energy only
  // (spinning rattlers of a static packing never stop; "all" is the default).
  bool translation_only = false;
  // Background viscous damping rate nu (1/s): every free grain feels -m nu v and -I nu w
  // (DEM; LIGGGHTS' fix viscous). A numerical aid to reach static equilibrium: it vanishes at
  // rest, so it does not change a static state; 0 (default) leaves the dynamics untouched.
  double viscous_damping = 0.0;
  std::map<std::string, Vec3a> wall_velocity;  // set at stage start: wall name -> velocity
  // Set at stage start (Wall::set_rotation): wall name (not a box or its planes) -> turning.
  std::map<std::string, RotationConfig> wall_rotation;
  // Stress control (loading/servo.hpp): wall or box name -> target normal stress (Pa); the
  // walls move at most servo_max_velocity (required with wall_stress), with servo_gain (m/s per
  // Pa; 0: max velocity / largest target). stress_tolerance (relative) adds "every target
  // within it" to a kinetic_energy_below stage's end condition: "until equilibrium".
  // Zero targets (a sample released to p = 0) are valid: stress_scale (Pa) is then the stress
  // their error is relative to (a wall is within stress_tolerance once it carries less than
  // stress_tolerance * stress_scale; required with stress_tolerance when a target is 0), and
  // when every target is 0 the default gain is max velocity / stress_scale (so stress_scale or
  // servo_gain is required then). Non-zero targets are measured against themselves.
  std::map<std::string, double> wall_stress;
  double servo_gain = 0.0;
  double servo_max_velocity = 0.0;
  // Contact dynamics moves the walls as bodies under target * area instead (no servo_gain):
  // servo_wall_mass (kg) overrides their automatic mass (loading/servo.hpp); 0: automatic.
  double servo_wall_mass = 0.0;
  std::optional<double> stress_tolerance;
  // Wetting (world/liquid.hpp), at the start of the stage: gravimetric water content (kg
  // of liquid per kg of grains) distributed as bridges over the eligible pairs, or over the
  // touching pairs only (liquid_pairs = "contacts").
  std::optional<double> water_content;
  double liquid_density = 1000.0;  // kg/m^3
  bool liquid_at_contacts_only = false;
  double stress_scale = 0.0;  // Pa; 0: not given
  SourceLoc loc;
};

struct OutputConfig {
  std::string dir = "out";
  std::uint64_t vtk_interval = 0;       // steps between VTK frames; 0 = at the end of stages only
  std::uint64_t csv_interval = 1000;    // steps between CSV rows
  std::uint64_t snapshot_interval = 0;  // steps between snapshots; 0 = at the end of stages only
  std::uint64_t log_interval = 1000;    // steps between log lines (non-terminal)
  bool vtk_contacts = true;
  bool vtk_walls = true;
  VtkEncoding vtk_format = VtkEncoding::kBinary;  // how the .vtp arrays are stored (vtk_xml.hpp)
};

struct ScenarioConfig {
  std::string path;  // file the scenario came from (for messages)
  std::string text;  // its full text, stored in snapshots
  SimulationConfig sim;
  DomainConfig domain;
  std::vector<MaterialConfig> materials;
  std::vector<PairOverrideConfig> overrides;
  ContactConfig contact;
  CdConfig cd;
  std::vector<GrainsConfig> grains;
  std::vector<WallConfig> walls;
  std::vector<StageConfig> stages;
  OutputConfig output;
  // Legal but surprising choices the parser noticed; printed once by `check` and `run`.
  std::vector<std::string> warnings;
};

// The warnings of ScenarioConfig::warnings (scenario_warnings.cpp).
std::vector<std::string> scenario_warnings(const ScenarioConfig& cfg);

// Largest scenario read: 64 MiB, a thousand times the largest example (a list of a million
// grain positions is about 40 MB). load_scenario() refuses a larger file before reading it.
inline constexpr std::size_t kMaxScenarioBytes = std::size_t{64} << 20;
// Most grains a scenario may ask for, all [[grains]] blocks together: 10^8. At about 0.5 KB a
// grain with its contact lists that is some 50 GB, beyond the machines Sable runs on, while a
// count of 10^12 (a typo, a fuzzer) would otherwise run the generators out of memory.
inline constexpr std::uint64_t kMaxGrains = 100'000'000;
// Most tries per grain of random insertion (max_attempts): 10^6, a thousand times the default.
inline constexpr std::uint64_t kMaxInsertionAttempts = 1'000'000;

// Parse and validate. Throws InputError naming file:line:column, the key and what was expected.
// `folder`: where files named by relative paths are looked for ("" for the folder of `path`).
ScenarioConfig parse_scenario(const std::string& text, const std::string& path,
                              const std::string& folder = "");

// The scenario a snapshot `path` stores (`text`), parsed; throws InputError "the scenario
// stored in the snapshot does not parse: ..." (the caller names the file).
// The scenario stored in snapshot `path`. Files it names by relative paths are looked for in
// the folder of `scenario_path` (where the run's scenario was, as the snapshot records it)
// when that folder exists, else in the snapshot's folder.
ScenarioConfig parse_stored_scenario(const std::string& text, const std::string& path,
                                     const std::string& scenario_path = "");
ScenarioConfig load_scenario(const std::string& path);

}  // namespace sable
