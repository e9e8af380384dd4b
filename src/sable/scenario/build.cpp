#include "sable/scenario/build.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <numbers>

#include "sable/cd/cd_solver.hpp"
#include "sable/core/error.hpp"
#include "sable/dem/dem_solver.hpp"
#include "sable/generation/generate.hpp"
#include "sable/generation/shape_draws.hpp"
#include "sable/geometry/surface_mesh.hpp"
#include "sable/io/obj.hpp"
#include "sable/io/stl.hpp"
#include "sable/scenario/initial_state.hpp"
#include "sable/world/critical_time.hpp"
#include "sable/world/polyhedral_grains.hpp"

namespace sable {
namespace {

// Names were checked by the parser, so the lookup cannot fail here.
template <int D>
MaterialIndex material_index(const World<D>& w, const std::string& name) {
  return *w.materials.find(name);
}

// A mesh wall's surface as the scenario describes it: the STL file (3D) or the built-in shape.
template <int D>
SurfaceMesh<D> mesh_surface(const MeshConfig& m) {
  using S = Space<D>;
  if constexpr (D == 3) {
    if (!m.file.empty()) return read_stl(m.file, m.scale, S::from_array(m.offset));
    if (m.shape == "cylinder")
      return cylinder_surface(S::from_array(m.center), S::from_array(m.axis), m.radius, m.length,
                              m.facets, m.segments, m.caps, m.key);
  } else {
    if (m.shape == "circle")
      return circle_surface(S::from_array(m.center), m.radius, m.facets, m.key);
    if (m.shape == "polyline") {
      std::vector<typename S::Vec> points;
      std::vector<typename SurfaceMesh<2>::Element> segments;
      for (const Vec3a& p : m.points) points.push_back(S::from_array(p));
      const auto n = static_cast<std::uint32_t>(points.size());
      for (std::uint32_t k = 0; k + 1 < n; ++k) segments.push_back({k, k + 1});
      if (m.closed) segments.push_back({n - 1, 0});
      return build_surface<2>(std::move(points), std::move(segments), m.key);
    }
  }
  if (m.shape == "box") return box_surface<D>(S::from_array(m.lo), S::from_array(m.hi), m.key);
  // The parser accepts no other; a MeshConfig built by hand may hold anything.
  throw InputError(
      fmt::format("{}: no mesh file and no {}D built-in shape \"{}\"", m.key, D, clip(m.shape)));
}

// The mesh wall's surface, made now (the file read, every element checked); an error names the
// scenario's [[wall]] table and then, from the mesh, the file or shape and the element.
template <int D>
void set_mesh(const WallConfig& wc, Wall<D>& wall) {
  try {
    wall.set_mesh(mesh_surface<D>(wc.mesh));
  } catch (const InputError& e) {
    const std::string key = wc.mesh.file.empty() ? std::string() : wc.mesh.key + ": ";
    throw InputError(
        fmt::format("{}: [[wall]] {}: {}{}", wc.loc.str(), clip(wc.name), key, e.what()));
  }
}

template <int D>
void add_walls(const WallConfig& wc, World<D>& w) {
  using S = Space<D>;
  Wall<D> wall;
  wall.name = wc.name;
  wall.material = material_index(w, wc.material);
  wall.velocity = S::from_array(wc.velocity);
  if (wc.type == "plane") {
    wall.point = S::from_array(wc.point);
    wall.shape = PlaneShape<D>(S::from_array(wc.normal).normalized());
  } else if (wc.type == "cylinder") {
    wall.shape = CylinderShape<D>(wc.radius);
    wall.point = S::from_array({wc.center[0], wc.center[1], 0.0});
  } else if (wc.type == "mesh") {
    set_mesh(wc, wall);
  } else {  // box: one plane per face, normals pointing inwards (the parser gives no rotation)
    static constexpr const char* axes = "xyz";
    for (int d = 0; d < D; ++d) {
      for (int side = 0; side < 2; ++side) {
        Wall<D> face = wall;
        face.name = fmt::format("{}.{}{}", wc.name, axes[d], side == 0 ? "lo" : "hi");
        face.point = S::from_array(side == 0 ? wc.lo : wc.hi);
        typename S::Vec normal = S::zero();
        normal[d] = side == 0 ? 1.0 : -1.0;
        face.shape = PlaneShape<D>(normal);
        w.walls.push_back(face);
      }
    }
    return;
  }
  if (const auto& r = wc.rotation)
    wall.set_rotation(S::from_array(r->point), S::from_array(r->axis), r->rate);
  w.walls.push_back(std::move(wall));
}

// The registry's rows for the names the parser accepted. A ContactConfig built by hand may
// carry any name: an unknown one is an error here, never a silent default.
[[noreturn]] void unknown_sub_model(const ContactConfig& c, std::string_view category,
                                    const std::string& name) {
  std::string names;
  for (std::string_view n : sub_model_names(category))
    names += (names.empty() ? "\"" : ", \"") + std::string(n) + "\"";
  throw InputError(fmt::format("{}: contact.{} = \"{}\" is not a registered {} model (one of {})",
                               c.loc.str(), category, clip(name), category, names));
}

NormalModel normal_law_named(const ContactConfig& c) {
  const auto row = NormalLaws::find(c.normal);
  if (!row) unknown_sub_model(c, "normal", c.normal);
  return *row;
}

template <class Enum>
Enum sub_model(const ContactConfig& c, std::string_view category, const std::string& name) {
  const auto code = sub_model_code(category, name);
  if (!code) unknown_sub_model(c, category, name);
  return static_cast<Enum>(*code);
}

}  // namespace

template <int D>
void build_model(const ScenarioConfig& cfg, World<D>& w) {
  using S = Space<D>;
  for (const auto& m : cfg.materials) w.materials.add(m.material);
  for (const auto& o : cfg.overrides) {
    PairOverride po;
    po.a = material_index(w, o.a);
    po.b = material_index(w, o.b);
    po.friction = o.friction;
    po.restitution = o.restitution;
    po.rolling_friction = o.rolling_friction;
    w.materials.add_override(po);
  }
  w.materials.finalize();
  const auto& c = cfg.contact;
  w.model.normal = normal_law_named(c);
  w.model.tangential = sub_model<TangentialModel>(c, "tangential", c.tangential);
  w.model.attractive_damping = c.attractive_damping;
  w.model.keep_spring_length = c.keep_spring_length;
  w.model.kn = c.kn;
  w.model.kt = c.kt;
  w.model.cohesion = sub_model<CohesionModel>(c, "cohesion", c.cohesion);
  w.model.capillary.surface_tension = c.surface_tension;
  w.model.capillary.contact_angle = c.contact_angle_deg * std::numbers::pi / 180.0;
  w.model.capillary.c = c.capillary_c;
  w.model.capillary.ruptured =
      c.ruptured_liquid == "lost" ? RupturedLiquid::kLost : RupturedLiquid::kGrains;
  w.neighbors.bridges = w.model.cohesion == CohesionModel::kCapillary;
  w.model.rolling = sub_model<RollingModel>(c, "rolling", c.rolling);
  w.model.rolling_damping = c.rolling_damping;
  w.neighbors.rolling = w.model.rolling != RollingModel::kNone;
  for (const auto& wc : cfg.walls) add_walls(wc, w);
  w.gravity = S::from_array(cfg.sim.gravity);
  w.thickness = cfg.sim.thickness;
  w.overlap_warning = cfg.sim.overlap_warning;
  w.max_speed = cfg.sim.max_speed;
  w.track_orientation = cfg.sim.track_orientation;
  w.reorder_every = cfg.sim.reorder_every.value_or(kReorderAuto);
  w.rng.reseed(cfg.sim.seed);
  w.neighbors.domain_lo = S::from_array(cfg.domain.lo);
  w.neighbors.domain_hi = S::from_array(cfg.domain.hi);
}

namespace {

// Every grain needs a finite, positive mass and moment of inertia, and finite inverses: a
// density of 1e-310 kg/m^3 passes "> 0" but gives an infinite inverse mass.
template <int D>
void check_masses(const ScenarioConfig& cfg, const World<D>& w) {
  const auto& p = w.particles;
  for (std::size_t k = 0; k < p.size(); ++k) {
    const bool ok = std::isfinite(p.mass[k]) && p.mass[k] >= std::numeric_limits<double>::min() &&
                    std::isfinite(p.inv_mass[k]) && std::isfinite(p.inv_inertia[k]);
    if (!ok)
      throw InputError(fmt::format(
          "{}: material '{}' (density {} kg/m^3) gives grain id {} of radius {} m the mass {} "
          "kg, which is not a usable number; check the density and the radius",
          cfg.path, w.materials[p.material[k]].name, w.materials[p.material[k]].density,
          p.id[k].index, p.radius[k], p.mass[k]));
  }
}

// A generated grain may not overlap a wall by more than the initial overlap the scenario
// allows (the check of check_initial_state: a scenario it accepts generates the same grains)
// nor sit behind a plane or inside a closed mesh (a body the grains are poured around).
template <int D>
Blocked wall_blocker(const ScenarioConfig& cfg, const World<D>& w) {
  if (w.walls.empty()) return {};
  return [&cfg, &w](const Vec3a& xa, double r) {
    const typename Space<D>::Vec x = Space<D>::from_array(xa);
    typename Space<D>::Vec n;
    for (const auto& wall : w.walls) {
      const auto* m = wall.mesh();
      if (m && !m->near(x, r)) continue;  // the exact tests cost O(elements)
      if (wall.distance(x, n) < r * (1.0 - cfg.sim.initial_overlap)) return true;
      if (m && m->encloses(x)) return true;
    }
    return false;
  };
}

// The vertices of a block's shape file (OBJ by its extension, else STL: the parser took no
// other), or none when the shape gives its points.
std::vector<Eigen::Vector3d> shape_file_points(const GrainShapeConfig& shape) {
  if (shape.file.empty()) return {};
  std::string ext = std::filesystem::path(shape.file).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".obj") return read_obj_vertices(shape.file);
  return read_stl(shape.file, 1.0, Eigen::Vector3d::Zero()).vertices;
}

// The draws of a block's shapes, the shape file read; an error names the block and the key.
ShapeDraws block_shape_draws(const GrainsConfig& block, std::uint64_t seed) {
  const GrainShapeConfig& shape = block.shape;
  try {
    return ShapeDraws(shape, seed, shape_file_points(shape), clip(shape.file));
  } catch (const InputError& e) {
    // A file's messages name the file (and line); the shape's own points name their key.
    throw InputError(fmt::format("{}: {}{}", block.loc.str(),
                                 shape.file.empty() ? "" : shape.key + ".file: ", e.what()));
  }
}

// A block of polyhedral grains (3D): on each generated sphere, a polyhedron whose bounding
// sphere about its centroid is that sphere (its unit shape times the radius), turned as the
// draws say. Random polyhedra add a row of the shape table per grain; a given shape a row per
// distinct radius, which its grains share.
void add_polyhedral_block(const GrainsConfig& block, std::uint64_t seed,
                          const std::vector<GrainSeed>& seeds, MaterialIndex mat, World<3>& w) {
  ShapeDraws draws = block_shape_draws(block, seed);
  const double density = w.materials[mat].density;
  std::map<double, ShapePlacement> rows;
  std::vector<Eigen::Vector3d> corners;
  try {
    for (const GrainSeed& g : seeds) {
      draws.next();
      ShapePlacement placed;
      if (const auto row = rows.find(g.radius); row != rows.end()) {
        placed = row->second;
      } else {
        corners = draws.unit();
        for (Eigen::Vector3d& c : corners) c *= g.radius;
        placed = w.shapes.add(corners, block.shape.key.c_str());
        if (!draws.random_shapes()) rows.emplace(g.radius, placed);
      }
      // A body point b stands at x + turn frame b: `frame` takes the body frame to the unit
      // shape's axes (GrainShapes::add), the draw's turn those to the world.
      add_polyhedral_grain(w, placed.index, Space<3>::from_array(g.x), draws.turn() * placed.frame,
                           density, mat, block.fixed);
      if (!block.fixed) w.particles.v.back() = Space<3>::from_array(block.velocity);
    }
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}", block.loc.str(), e.what()));
  }
}

}  // namespace

template <int D>
void build_grains(const ScenarioConfig& cfg, World<D>& w) {
  using S = Space<D>;
  std::vector<GrainSeed> all;
  const Blocked blocked = wall_blocker(cfg, w);
  for (std::size_t b = 0; b < cfg.grains.size(); ++b) {
    const GrainsConfig& block = cfg.grains[b];
    // Each block gets its own stream: adding a block does not change the grains of the others.
    const std::uint64_t seed = block.seed.value_or(cfg.sim.seed + 0x9e3779b97f4a7c15ULL * (b + 1));
    const auto seeds = generate_grains(block, D, seed, all, blocked);
    const MaterialIndex mat = material_index(w, block.material);
    const Material& m = w.materials[mat];
    if (block.shape.polyhedral()) {
      if constexpr (D == 3)
        add_polyhedral_block(block, seed, seeds, mat, w);
      else  // the parser refuses a shape in 2D; a GrainsConfig made by hand may hold one
        throw InputError(
            fmt::format("{}: {}: polyhedral grains are 3D only", block.loc.str(), block.shape.key));
    } else {
      for (const auto& g : seeds) {
        w.particles.add(S::from_array(g.x), g.radius, m.density, mat, cfg.sim.thickness,
                        block.fixed);
        if (!block.fixed) w.particles.v.back() = S::from_array(block.velocity);
      }
    }
    all.insert(all.end(), seeds.begin(), seeds.end());
  }
  check_masses(cfg, w);
  w.neighbors.skin = scenario_skin(cfg, w);
  w.dt = scenario_time_step(cfg, w);
  check_initial_state(cfg, w);
}

template <int D>
double scenario_time_step(const ScenarioConfig& cfg, const World<D>& w) {
  return cfg.sim.dt ? *cfg.sim.dt : automatic_time_step(cfg, w);
}

template <int D>
double scenario_skin(const ScenarioConfig& cfg, const World<D>& w) {
  double rmax = 0.0;
  for (double r : w.particles.radius) rmax = std::max(rmax, r);
  return cfg.sim.skin.value_or(0.5 * rmax);
}

template <int D>
double automatic_time_step(const ScenarioConfig& cfg, const World<D>& w) {
  const double t_crit = critical_time(w);
  if (w.particles.size() == 0)
    throw InputError(
        fmt::format("{}: simulation.dt is required when the scenario has no grains", cfg.path));
  const double dt = cfg.sim.dt_safety * t_crit;
  if (!(std::isfinite(dt) && dt >= std::numeric_limits<double>::min()))
    throw InputError(fmt::format(
        "{}: the automatic time step is {} s (critical time {} s): the materials' density, "
        "young and poisson give no usable time step; check them, or set simulation.dt",
        cfg.path, dt, t_crit));
  return dt;
}

template <int D>
std::optional<std::string> check_time_step(const ScenarioConfig& cfg, const World<D>& w) {
  if (cfg.sim.solver == "cd" || w.particles.size() == 0) return std::nullopt;  // no stiffness
  const double ratio = w.dt / critical_time(w);
  const std::string_view crit = critical_time_name(w);
  if (ratio > kTimeStepError)
    throw InputError(fmt::format(
        "{}: simulation.dt = {:.4g} s is {:.3g} times {} of the smallest grain ({:.4g} s); above "
        "{} times the explicit integration is unstable or its contacts badly wrong: choose dt "
        "<= {:.4g} s (the automatic dt is {} of it)",
        cfg.path, w.dt, ratio, crit, w.dt / ratio, kTimeStepError, kTimeStepWarning * w.dt / ratio,
        cfg.sim.dt_safety));
  if (ratio > kTimeStepWarning)
    return fmt::format(
        "simulation.dt = {:.4g} s is {:.3g} times {} of the smallest grain ({:.4g} s); above {} "
        "times a collision's restitution strays by up to 20 % from the material's (docs/"
        "contact-laws.md, \"Time step\"); the automatic dt is {} of it",
        w.dt, ratio, crit, w.dt / ratio, kTimeStepWarning, cfg.sim.dt_safety);
  return std::nullopt;
}

template <int D>
std::vector<std::size_t> walls_named(const World<D>& w, const std::string& key) {
  std::vector<std::size_t> out;
  for (std::size_t k = 0; k < w.walls.size(); ++k) {
    const std::string& n = w.walls[k].name;
    if (n == key ||
        (n.size() > key.size() && n.compare(0, key.size(), key) == 0 && n[key.size()] == '.'))
      out.push_back(k);
  }
  return out;
}

template <int D>
std::unique_ptr<Solver> make_solver(const ScenarioConfig& cfg, World<D>& world, Domain<D>* domain) {
  if (domain && domain->distributed()) {
    if (cfg.sim.solver == "cd")
      throw InputError(fmt::format(
          "{}: [simulation] solver = \"cd\": contact dynamics does not run on several MPI "
          "processes yet (its Gauss-Seidel sweep is sequential; docs/ARCHITECTURE.md, "
          "\"Domain decomposition\"): run it on one process, with --threads for a coloured "
          "sweep",
          cfg.path));
    if (cfg.contact.cohesion == "capillary" && cfg.contact.ruptured_liquid == "lost")
      throw InputError(fmt::format(
          "{}: [contact] ruptured_liquid = \"lost\": the liquid lost by ruptured bridges is "
          "one running sum over the sample, which does not run on several MPI processes yet "
          "(docs/ARCHITECTURE.md, \"Domain decomposition\"): run it on one process, or keep "
          "ruptured_liquid = \"grains\"",
          cfg.path));
  }
  if (cfg.sim.solver != "cd") {
    auto dem = std::make_unique<DemSolver<D>>(world);
    dem->set_domain(domain);
    return dem;
  }
  const CdConfig& c = cfg.cd;
  CdSettings s;
  s.theta = c.theta;
  s.warm_start = c.warm_start;
  s.overlap_recovery = c.overlap_recovery;
  s.nlgs.tolerance = c.tolerance;
  s.nlgs.max_iterations = static_cast<int>(std::min<std::uint64_t>(c.max_iterations, 1u << 30));
  s.nlgs.relaxation = c.relaxation;
  s.nlgs.spaced_checks = c.residual_checks == "spaced";
  s.newton_iterations = static_cast<int>(std::min<std::uint64_t>(c.newton_iterations, 1u << 30));
  s.nlgs.local =
      c.local_solver == "exact" ? cd::LocalSolver::kExact : cd::LocalSolver::kBipotential;
  s.nlgs.order = c.sweep == "alternating" ? cd::SweepOrder::kAlternating
                 : c.sweep == "shuffled"  ? cd::SweepOrder::kShuffled
                 : c.sweep == "coloured"  ? cd::SweepOrder::kColoured
                                          : cd::SweepOrder::kForward;
  s.colour_block = static_cast<std::size_t>(std::min<std::uint64_t>(c.colour_block, 1u << 30));
  s.nlgs.criterion = c.criterion == "quad"   ? cd::Criterion::kQuad
                     : c.criterion == "maxm" ? cd::Criterion::kMaxm
                                             : cd::Criterion::kNatural;
  return std::make_unique<CdSolver<D>>(world, s);
}

template std::unique_ptr<Solver> make_solver<2>(const ScenarioConfig&, World<2>&, Domain<2>*);
template std::unique_ptr<Solver> make_solver<3>(const ScenarioConfig&, World<3>&, Domain<3>*);
template void build_model<2>(const ScenarioConfig&, World<2>&);
template void build_model<3>(const ScenarioConfig&, World<3>&);
template void build_grains<2>(const ScenarioConfig&, World<2>&);
template void build_grains<3>(const ScenarioConfig&, World<3>&);
template double scenario_time_step<2>(const ScenarioConfig&, const World<2>&);
template double scenario_time_step<3>(const ScenarioConfig&, const World<3>&);
template double scenario_skin<2>(const ScenarioConfig&, const World<2>&);
template double scenario_skin<3>(const ScenarioConfig&, const World<3>&);
template double automatic_time_step<2>(const ScenarioConfig&, const World<2>&);
template double automatic_time_step<3>(const ScenarioConfig&, const World<3>&);
template std::optional<std::string> check_time_step<2>(const ScenarioConfig&, const World<2>&);
template std::optional<std::string> check_time_step<3>(const ScenarioConfig&, const World<3>&);
template std::vector<std::size_t> walls_named<2>(const World<2>&, const std::string&);
template std::vector<std::size_t> walls_named<3>(const World<3>&, const std::string&);

}  // namespace sable
