// The scenario parser: TOML text -> validated ScenarioConfig (schema in docs and config.hpp).
//
// Each table is read by one function that first rejects unknown keys, then reads every key
// with its type and range checked. Cross references (material names, wall names) are checked
// once the tables they point to have been read, so [simulation] comes first (the dimension
// sets the length of every vector), then materials, then what refers to them.
#include <fmt/format.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <utility>

#include "sable/core/error.hpp"
#include "sable/scenario/config.hpp"
#include "sable/scenario/parse_contact.hpp"
#include "sable/scenario/parse_shape.hpp"
#include "sable/scenario/parse_walls.hpp"
#include "sable/scenario/toml_reader.hpp"

namespace sable {

namespace {

using detail::in_quotes;
using detail::kNonNegative;
using detail::kPositive;
using detail::material_ref;
using detail::Range;
using detail::Table;

constexpr Range kPoisson{0.0, 0.5, false, true};
constexpr Range kRestitution{0.0, 1.0, true, false};
constexpr Range kUnitOpenHi{0.0, 1.0, false, true};

// --- [simulation], [domain] -----------------------------------------------------------------

SimulationConfig parse_simulation(const Table& root) {
  SimulationConfig sim;
  const auto t = root.table("simulation");
  if (!t) return sim;
  t->check_keys({"dimension", "solver", "seed", "dt", "dt_safety", "gravity", "thickness", "skin",
                 "overlap_warning", "initial_overlap", "max_speed", "track_orientation",
                 "reorder_every"});
  if (const toml::node* dim = t->find("dimension")) {
    const auto* value = dim->as_integer();
    if (value == nullptr || (value->get() != 2 && value->get() != 3)) {
      t->fail("dimension", "2 or 3");
    }
    sim.dimension = static_cast<int>(value->get());
  }
  sim.solver = t->choice("solver", {"dem", "cd"}, "dem");
  sim.seed = t->unsigned_or("seed", sim.seed);
  sim.dt = t->number("dt", kPositive);
  sim.dt_safety = t->number_or("dt_safety", Range{0.0, kTimeStepError, true, false}, sim.dt_safety);
  sim.gravity = t->vector("gravity", sim.dimension).value_or(sim.gravity);
  if (sim.dimension == 3) t->reject("thickness", "in 3D: thickness applies to 2D only");
  sim.thickness = t->number_or("thickness", kPositive, sim.thickness);
  sim.skin = t->number("skin", kNonNegative);
  sim.overlap_warning = t->number_or("overlap_warning", kPositive, sim.overlap_warning);
  sim.initial_overlap =
      t->number_or("initial_overlap", Range{0.0, 1.0, false, true}, sim.initial_overlap);
  sim.max_speed = t->number_or("max_speed", kPositive, sim.max_speed);
  sim.track_orientation = t->boolean_or("track_orientation", sim.track_orientation);
  if (const toml::node* r = t->find("reorder_every")) {
    const auto* word = r->as_string();
    const auto* count = r->as_integer();
    if (word != nullptr && word->get() == "auto") {
      sim.reorder_every.reset();
    } else if (count != nullptr && count->get() >= 0) {
      sim.reorder_every = static_cast<std::uint64_t>(count->get());
    } else {
      t->fail("reorder_every",
              "a non-negative integer (neighbour builds between sorts, 0: never) or \"auto\"");
    }
  }
  return sim;
}

DomainConfig parse_domain(const Table& root, int dim) {
  const auto t = root.table("domain");
  if (!t) root.fail_missing("domain", "a [domain] table with lo and hi");
  t->check_keys({"lo", "hi"});
  DomainConfig d;
  d.lo = t->required_vector("lo", dim);
  d.hi = t->required_vector("hi", dim);
  detail::check_ordered(*t, "lo", "hi", d.lo, d.hi, dim);
  d.loc = t->loc();
  return d;
}

// --- [[material]], [[material_pair]] ([contact], [cd]: parse_contact.cpp)
// --------------------------------------------

// Contact dynamics treats grains as rigid: young and poisson are then optional (unused).
MaterialConfig parse_material(const Table& t, bool rigid_grains) {
  t.check_keys({"name", "density", "young", "poisson", "restitution", "friction",
                "rolling_friction", "rigid"});
  MaterialConfig mc;
  Material& m = mc.material;
  m.name = t.required_string("name");
  m.rigid = t.boolean_or("rigid", false);
  if (m.rigid || rigid_grains) {
    m.density =
        m.rigid ? t.number_or("density", kPositive, 0.0) : t.required_number("density", kPositive);
    m.young = t.number_or("young", kPositive, 0.0);
    m.poisson = t.number_or("poisson", kPoisson, 0.0);
  } else {
    m.density = t.required_number("density", kPositive);
    m.young = t.required_number("young", kPositive);
    m.poisson = t.required_number("poisson", kPoisson);
  }
  m.restitution = t.number_or("restitution", kRestitution, 1.0);
  m.friction = t.number_or("friction", kNonNegative, 0.0);
  mc.restitution_given = t.has("restitution");
  mc.friction_given = t.has("friction");
  m.rolling_friction = t.number_or("rolling_friction", kNonNegative, 0.0);
  mc.loc = t.loc();
  return mc;
}

std::vector<MaterialConfig> parse_materials(const Table& root, bool rigid_grains) {
  std::vector<MaterialConfig> out;
  for (const Table& t : root.table_array("material")) {
    MaterialConfig mc = parse_material(t, rigid_grains);
    for (const MaterialConfig& prev : out) {
      if (prev.material.name == mc.material.name) {
        t.fail("name", "a unique name (material " + in_quotes(mc.material.name) +
                           " is already defined at " + prev.loc.str() + ")");
      }
    }
    out.push_back(std::move(mc));
  }
  if (out.empty()) root.fail_missing("material", "at least one [[material]] table");
  return out;
}

// Error unless `name` (read from node) names one of `materials`.
void check_material_name(const toml::node& node, const std::string& key, const std::string& file,
                         const std::string& name, const std::vector<MaterialConfig>& materials) {
  std::vector<std::string> known;
  for (const MaterialConfig& m : materials) {
    if (m.material.name == name) return;
    known.push_back(m.material.name);
  }
  detail::fail_value(node, key, file,
                     "the name of a [[material]] (known: " + detail::join_names(known, true) + ")");
}

PairOverrideConfig parse_pair(const Table& t, const std::vector<MaterialConfig>& materials) {
  t.check_keys({"materials", "friction", "restitution", "rolling_friction"});
  const toml::array* names = t.array("materials");
  if (names == nullptr) t.fail_missing("materials", "an array of 2 material names");
  if (names->size() != 2 || !names->is_homogeneous(toml::node_type::string)) {
    t.fail("materials", "an array of 2 material names");
  }
  PairOverrideConfig p;
  for (std::size_t i = 0; i < 2; ++i) {
    const std::string key = t.key_path("materials") + "[" + std::to_string(i) + "]";
    const std::string name = detail::to_string(*names->get(i), key, t.file());
    check_material_name(*names->get(i), key, t.file(), name, materials);
    (i == 0 ? p.a : p.b) = name;
  }
  p.friction = t.number("friction", kNonNegative);
  p.restitution = t.number("restitution", kRestitution);
  p.rolling_friction = t.number("rolling_friction", kNonNegative);
  p.loc = t.loc();
  return p;
}

std::vector<PairOverrideConfig> parse_pairs(const Table& root,
                                            const std::vector<MaterialConfig>& materials) {
  std::vector<PairOverrideConfig> out;
  for (const Table& t : root.table_array("material_pair")) {
    PairOverrideConfig p = parse_pair(t, materials);
    for (const PairOverrideConfig& q : out) {
      if ((q.a == p.a && q.b == p.b) || (q.a == p.b && q.b == p.a)) {
        t.fail("materials", "a pair not given before (also at " + q.loc.str() + ")");
      }
    }
    out.push_back(std::move(p));
  }
  return out;
}

// --- [[grains]] --------------------------------------------------------------------------------

RadiusConfig parse_radius_table(const Table& r) {
  RadiusConfig rc;
  const std::string dist = r.choice("distribution", {"mono", "uniform", "list"}, "");
  if (dist.empty()) r.fail_missing("distribution", "\"mono\", \"uniform\" or \"list\"");
  if (dist == "mono") {
    r.check_keys({"distribution", "value"});
    rc.value = r.required_number("value", kPositive);
  } else if (dist == "uniform") {
    r.check_keys({"distribution", "mean", "spread"});
    rc.kind = RadiusConfig::Kind::kUniform;
    rc.value = r.required_number("mean", kPositive);
    rc.spread = r.number_or("spread", kUnitOpenHi, 0.0);
  } else {
    r.check_keys({"distribution", "values"});
    rc.kind = RadiusConfig::Kind::kList;
    const toml::array* values = r.array("values");
    if (values == nullptr) r.fail_missing("values", "an array of radii");
    if (values->empty()) r.fail("values", "a non-empty array of radii");
    for (std::size_t i = 0; i < values->size(); ++i) {
      const std::string key = r.key_path("values") + "[" + std::to_string(i) + "]";
      rc.values.push_back(detail::to_number(*values->get(i), key, r.file(), kPositive));
    }
  }
  return rc;
}

// radius = number | [numbers] | { distribution = ... }
RadiusConfig parse_radius(const Table& g) {
  const toml::node* node = g.find("radius");
  const std::string key = g.key_path("radius");
  RadiusConfig rc;
  if (node->is_number()) {
    rc.value = detail::to_number(*node, key, g.file(), kPositive);
  } else if (const auto* arr = node->as_array(); arr != nullptr && !arr->empty()) {
    rc.kind = RadiusConfig::Kind::kList;
    for (std::size_t i = 0; i < arr->size(); ++i) {
      const std::string ikey = key + "[" + std::to_string(i) + "]";
      rc.values.push_back(detail::to_number(*arr->get(i), ikey, g.file(), kPositive));
    }
  } else if (node->is_table()) {
    rc = parse_radius_table(*g.table("radius"));
  } else {
    detail::fail_type(*node, key, g.file(),
                      "a number, an array of numbers or a table with a distribution");
  }
  return rc;
}

RegionConfig parse_region(const Table& g, int dim) {
  const auto t = g.table("region");
  if (!t) g.fail_missing("region", "a table { box = {...} } or { cylinder = {...} }");
  t->check_keys({"box", "cylinder"});
  if (t->has("box") == t->has("cylinder")) {
    g.fail("region", "exactly one of box = {...} or cylinder = {...}");
  }
  RegionConfig r;
  if (const auto box = t->table("box")) {
    box->check_keys({"lo", "hi"});
    r.lo = box->required_vector("lo", dim);
    r.hi = box->required_vector("hi", dim);
    detail::check_ordered(*box, "lo", "hi", r.lo, r.hi, dim);
    return r;
  }
  const auto cyl = t->table("cylinder");
  if (dim != 3) t->fail("cylinder", "a box region (a cylinder region needs dimension = 3)");
  cyl->check_keys({"center", "radius", "zlo", "zhi"});
  r.kind = RegionConfig::Kind::kCylinder;
  r.center = cyl->required_vector("center", 2);
  r.radius = cyl->required_number("radius", kPositive);
  r.zlo = cyl->required_number("zlo", detail::kAnyNumber);
  r.zhi = cyl->required_number("zhi", detail::kAnyNumber);
  if (!(r.zhi > r.zlo)) cyl->fail("zhi", "a number > zlo = " + detail::format_number(r.zlo));
  return r;
}

// Keys that only some generators use; any other generator rejects them.
void reject_foreign_grain_keys(const Table& g, const std::string& gen) {
  struct Use {
    std::string_view key;
    std::vector<std::string> generators;
  };
  static const std::vector<Use> kUses = {{"radius", {"lattice", "random", "list"}},
                                         {"region", {"lattice", "random"}},
                                         {"count", {"lattice", "random"}},
                                         {"seed", {"lattice", "random"}},
                                         {"spacing", {"lattice"}},
                                         {"jitter", {"lattice"}},
                                         {"jitter_rng", {"lattice"}},
                                         {"arrangement", {"lattice"}},
                                         {"max_attempts", {"random"}},
                                         {"positions", {"list"}},
                                         {"file", {"file"}}};
  for (const Use& u : kUses) {
    bool used = false;
    for (const auto& name : u.generators) used = used || name == gen;
    if (!used) {
      g.reject(u.key, "to generator = " + in_quotes(gen) + " (only to " +
                          detail::join(u.generators) + ")");
    }
  }
}

void parse_positions(const Table& g, GrainsConfig& gc, int dim) {
  const toml::array* pos = g.array("positions");
  if (pos == nullptr) g.fail_missing("positions", "an array of positions");
  if (pos->empty()) g.fail("positions", "a non-empty array of positions");
  for (std::size_t i = 0; i < pos->size(); ++i) {
    const std::string key = g.key_path("positions") + "[" + std::to_string(i) + "]";
    gc.positions.push_back(detail::to_vector(*pos->get(i), key, g.file(), dim));
  }
  const auto& radii = gc.radius.values;
  if (g.find("radius")->is_array() && radii.size() != gc.positions.size()) {
    g.fail("radius", "one number or an array of " + std::to_string(gc.positions.size()) +
                         " radii (one per position)");
  }
}

void parse_data_file(const Table& g, GrainsConfig& gc) {
  namespace fs = std::filesystem;
  const std::string name = g.required_string("file");
  fs::path p(name);
  if (p.is_relative()) p = fs::path(g.folder()) / p;
  gc.file = p.lexically_normal().string();
  std::error_code ec;
  if (!fs::is_regular_file(p, ec)) {
    g.fail("file", "an existing data file (nothing readable at " + in_quotes(gc.file) + ")");
  }
}

void parse_generator_keys(const Table& g, GrainsConfig& gc, int dim) {
  if (gc.generator == "lattice" || gc.generator == "random") {
    gc.region = parse_region(g, dim);
    if (!g.has("count")) g.fail_missing("count", "an integer >= 1");
    const std::uint64_t count = *g.unsigned_int("count", 1);
    if (count > kMaxGrains)
      g.fail("count", fmt::format("an integer in [1, {}] (the most grains a scenario may ask for)",
                                  kMaxGrains));
    gc.count = static_cast<std::size_t>(count);
    gc.seed = g.unsigned_int("seed");
  }
  if (gc.generator == "lattice") {
    gc.spacing = g.number("spacing", kPositive);
    gc.jitter = g.number_or("jitter", kNonNegative, gc.jitter);
    gc.jitter_rng = g.choice("jitter_rng", {"sable", "numpy-pcg64"}, gc.jitter_rng);
    gc.arrangement = g.choice("arrangement", {"square", "hexagonal"}, gc.arrangement);
  } else if (gc.generator == "random") {
    gc.max_attempts = static_cast<std::size_t>(g.unsigned_or("max_attempts", gc.max_attempts, 1));
    if (gc.max_attempts > kMaxInsertionAttempts)
      g.fail("max_attempts", fmt::format("an integer in [1, {}]", kMaxInsertionAttempts));
  } else if (gc.generator == "list") {
    parse_positions(g, gc, dim);
  } else {
    parse_data_file(g, gc);
  }
}

GrainsConfig parse_grains_entry(const Table& g, const ScenarioConfig& cfg) {
  g.check_keys({"generator", "material", "radius", "region", "count", "spacing", "jitter",
                "jitter_rng", "seed", "positions", "file", "velocity", "fixed", "max_attempts",
                "arrangement", "shape"});
  const int dim = cfg.sim.dimension;
  GrainsConfig gc;
  gc.generator = g.choice("generator", {"lattice", "random", "list", "file"}, "");
  if (gc.generator.empty()) {
    g.fail_missing("generator", "\"lattice\", \"random\", \"list\" or \"file\"");
  }
  reject_foreign_grain_keys(g, gc.generator);
  gc.material = material_ref(g, cfg.materials);
  for (const MaterialConfig& m : cfg.materials) {
    if (m.material.name == gc.material && !(m.material.density > 0.0)) {
      g.fail("material", "a material with a density (rigid " + in_quotes(gc.material) +
                             " has none; grains need a mass)");
    }
  }
  // A data file carries its own radii (reject_foreign_grain_keys refused a radius with it).
  if (gc.generator != "file") {
    if (!g.has("radius")) g.fail_missing("radius", "a number or a table with a distribution");
    gc.radius = parse_radius(g);
  }
  parse_generator_keys(g, gc, dim);
  gc.velocity = g.vector("velocity", dim).value_or(gc.velocity);
  gc.fixed = g.boolean_or("fixed", gc.fixed);
  gc.shape = detail::parse_grain_shape(g, cfg);
  gc.loc = g.loc();
  return gc;
}

// --- [[stage]] ---------------------------------------------------------------------------------

// wall_stress = { box = 1000.0 } or { "box.xlo" = 1000.0, ... }: a box name stands for all of
// its planes; stress in Pa, compression positive.
void parse_wall_stress(const Table& s, StageConfig& st, const std::vector<std::string>& names,
                       bool cd) {
  const auto t = s.table("wall_stress");
  // Without wall_stress the servo keys are errors (below), not silently ignored.
  static const toml::table none;
  for (auto&& [k, v] : t ? t->raw() : none) {
    const std::string name(k.str());
    const std::string key = t->key_path(name);
    if (!detail::contains(names, name) && !detail::contains(names, name + ".xlo"))
      detail::fail_at(k.source(), s.file(),
                      "unknown wall " + key + ": expected a wall or box name (known: " +
                          detail::join_names(names) + ")");
    const auto value = t->number(name, kNonNegative);
    if (!value) detail::fail_at(k.source(), s.file(), key + ": expected a stress in Pa (>= 0)");
    st.wall_stress[name] = *value;
  }
  if (!st.wall_stress.empty()) {
    if (!s.has("servo_max_velocity")) s.fail_missing("servo_max_velocity", "a speed > 0 (m/s)");
    st.servo_max_velocity = *s.number("servo_max_velocity", kPositive);
    // DEM servoes the walls' velocities (servo_gain); contact dynamics moves them as bodies
    // under the target force (servo_wall_mass): each key belongs to one solver.
    const std::string other = cd ? "with simulation.solver = \"cd\" (a DEM servo key)"
                                 : "with simulation.solver = \"dem\" (a contact-dynamics key)";
    s.reject(cd ? "servo_gain" : "servo_wall_mass", other);
    st.servo_gain = s.number("servo_gain", kPositive).value_or(0.0);
    st.servo_wall_mass = s.number("servo_wall_mass", kPositive).value_or(0.0);
    st.stress_tolerance = s.number("stress_tolerance", kPositive);
    if (st.stress_tolerance && !st.kinetic_energy_below)
      s.fail("stress_tolerance", "only with kinetic_energy_below (an until-equilibrium stage)");
    // Zero targets (config.hpp): their error and, when all are 0, the default gain need a scale.
    st.stress_scale = s.number("stress_scale", kPositive).value_or(0.0);
    bool any_zero = false, all_zero = true;
    for (const auto& [name, stress] : st.wall_stress) {
      any_zero = any_zero || stress == 0.0;
      all_zero = all_zero && stress == 0.0;
    }
    if (any_zero && st.stress_tolerance && !s.has("stress_scale"))
      s.fail_missing("stress_scale",
                     "a stress > 0 in Pa: with a 0 Pa target, stress_tolerance is relative to it");
    if (all_zero && !s.has("servo_gain") && !s.has("stress_scale"))
      s.fail_missing("stress_scale",
                     "a stress > 0 in Pa, or servo_gain: every target is 0 Pa, so the default "
                     "gain (servo_max_velocity / largest target) does not exist");
  } else {
    for (const char* k : {"servo_max_velocity", "servo_gain", "stress_tolerance", "stress_scale",
                          "servo_wall_mass"})
      s.reject(k, "to a stage without wall_stress");
  }
}

StageConfig parse_stage(const Table& s, std::size_t index, const std::vector<std::string>& names,
                        const ScenarioConfig& cfg) {
  s.check_keys({"name", "steps", "kinetic_energy_below", "max_steps", "check_interval",
                "wall_velocity", "wall_rotation", "wall_stress", "servo_gain", "servo_max_velocity",
                "stress_tolerance", "stress_scale", "water_content", "liquid_density",
                "liquid_pairs", "kinetic_energy_of", "servo_wall_mass", "viscous_damping"});
  const bool cd = cfg.sim.solver == "cd";
  StageConfig st;
  st.name = s.string("name").value_or("stage" + std::to_string(index));
  if (st.name.empty()) s.fail("name", "a non-empty string");
  const std::string one_of = "exactly one of steps or kinetic_energy_below";
  if (s.has("steps") && s.has("kinetic_energy_below")) {
    s.fail("kinetic_energy_below", one_of + ", found both");
  }
  if (!s.has("steps") && !s.has("kinetic_energy_below")) {
    detail::fail_at(s.raw().source(), s.file(),
                    s.name() + ": expected " + one_of + ", found neither");
  }
  st.steps = s.unsigned_int("steps");
  st.kinetic_energy_below = s.number("kinetic_energy_below", kPositive);
  if (st.kinetic_energy_below) {
    if (!s.has("max_steps")) s.fail_missing("max_steps", "an integer >= 1");
    st.max_steps = *s.unsigned_int("max_steps", 1);
  } else {
    s.reject("max_steps", "to a stage with steps (only with kinetic_energy_below)");
  }
  st.check_interval = s.unsigned_or("check_interval", st.check_interval, 1);
  if (st.kinetic_energy_below)
    st.translation_only =
        s.choice("kinetic_energy_of", {"all", "translation"}, "all") == "translation";
  else
    s.reject("kinetic_energy_of", "to a stage with steps (only with kinetic_energy_below)");
  detail::parse_wall_velocity(s, st, names, cfg.sim.dimension);
  detail::parse_wall_rotation(s, st, cfg);
  parse_wall_stress(s, st, names, cd);
  st.viscous_damping = s.number_or("viscous_damping", kNonNegative, 0.0);
  if (cd && st.viscous_damping > 0.0)
    s.fail("viscous_damping", "0 with solver = \"cd\" (contact dynamics dissipates by itself)");
  st.water_content = s.number("water_content", kPositive);
  if (st.water_content) {
    st.liquid_density = s.number_or("liquid_density", kPositive, st.liquid_density);
    st.liquid_at_contacts_only =
        s.choice("liquid_pairs", {"eligible", "contacts"}, "eligible") == "contacts";
  } else {
    s.reject("liquid_density", "to a stage without water_content");
    s.reject("liquid_pairs", "to a stage without water_content");
  }
  st.loc = s.loc();
  return st;
}

// --- [output] ----------------------------------------------------------------------------------

OutputConfig parse_output(const Table& root) {
  OutputConfig o;
  const auto t = root.table("output");
  if (!t) return o;
  t->check_keys({"dir", "vtk_interval", "csv_interval", "snapshot_interval", "log_interval",
                 "vtk_contacts", "vtk_walls", "vtk_format"});
  o.dir = t->string("dir").value_or(o.dir);
  if (o.dir.empty()) t->fail("dir", "a non-empty directory name");
  o.vtk_interval = t->unsigned_or("vtk_interval", o.vtk_interval);
  o.csv_interval = t->unsigned_or("csv_interval", o.csv_interval);
  o.snapshot_interval = t->unsigned_or("snapshot_interval", o.snapshot_interval);
  o.log_interval = t->unsigned_or("log_interval", o.log_interval);
  o.vtk_contacts = t->boolean_or("vtk_contacts", o.vtk_contacts);
  o.vtk_walls = t->boolean_or("vtk_walls", o.vtk_walls);
  o.vtk_format = parse_vtk_encoding(t->choice("vtk_format", {"binary", "zlib", "ascii"}, "binary"),
                                    "vtk_format");
  return o;
}

// A rolling friction needs the rolling sub-model (it would otherwise be silently ignored),
// and the sub-model a dry law; contact dynamics takes no rolling damping.
void check_rolling(const Table& root, const ScenarioConfig& cfg) {
  const char* key = "rolling_friction";
  if (cfg.contact.rolling == "none") {
    const std::string why =
        "only with contact.rolling = \"epsd\" (the rolling sub-model that uses it)";
    for (const char* array : {"material", "material_pair"})
      for (const Table& t : root.table_array(array))
        if (t.number_or(key, kNonNegative, 0.0) > 0.0) t.fail(key, "0 or absent, " + why);
    return;
  }
  const auto contact = root.table("contact");
  if (cfg.sim.solver == "cd")  // rigid grains: the couple has no spring, hence no damping
    contact->reject(
        "rolling_damping",
        "with solver = \"cd\" (the rolling couple of rigid grains has no spring to damp)");
  if (cfg.contact.cohesion != "none")
    contact->fail("rolling", "\"none\" with cohesion = \"capillary\" (not combined yet)");
}

}  // namespace

std::string detail::material_ref(const Table& t, const std::vector<MaterialConfig>& materials) {
  std::string name = t.required_string("material");
  check_material_name(*t.find("material"), t.key_path("material"), t.file(), name, materials);
  return name;
}

ScenarioConfig parse_scenario(const std::string& text, const std::string& path,
                              const std::string& folder) {
  if (text.size() > kMaxScenarioBytes)
    throw InputError(fmt::format("{}: the scenario is {} bytes; at most {} (64 MiB) are read",
                                 clip(path), text.size(), kMaxScenarioBytes));
  const toml::table doc = detail::parse_document(text, path);
  const Table root(doc, "", path, folder);
  root.check_keys({"simulation", "domain", "material", "material_pair", "contact", "cd", "grains",
                   "wall", "stage", "output"});
  ScenarioConfig cfg;
  cfg.path = path;
  cfg.text = text;
  cfg.sim = parse_simulation(root);
  cfg.domain = parse_domain(root, cfg.sim.dimension);
  cfg.materials = parse_materials(root, cfg.sim.solver == "cd");
  cfg.overrides = parse_pairs(root, cfg.materials);
  cfg.contact = parse_contact(root);
  cfg.cd = parse_cd(root, cfg.sim.solver);
  if (cfg.sim.solver == "cd" && !cfg.sim.dt) {
    root.fail_missing("simulation.dt",
                      "a time step: contact dynamics has no automatic dt (choose "
                      "it so grains move a small fraction of a radius per step)");
  }
  std::uint64_t grains = 0;
  for (const Table& g : root.table_array("grains")) {
    cfg.grains.push_back(parse_grains_entry(g, cfg));
    const GrainsConfig& gc = cfg.grains.back();
    grains += gc.count + gc.positions.size();
    if (grains > kMaxGrains)
      detail::fail_at(g.raw().source(), path,
                      fmt::format("{}: the [[grains]] blocks so far ask for {} grains; a scenario "
                                  "may ask for at most {}",
                                  g.name(), grains, kMaxGrains));
  }
  std::vector<std::string> wall_names;
  cfg.walls = detail::parse_walls(root, cfg, wall_names);
  detail::check_polyhedral_scenario(root, cfg);
  const auto stages = root.table_array("stage");
  if (stages.empty()) root.fail_missing("stage", "at least one [[stage]] table");
  for (std::size_t i = 0; i < stages.size(); ++i) {
    cfg.stages.push_back(parse_stage(stages[i], i, wall_names, cfg));
    if (cfg.stages.back().water_content && cfg.contact.cohesion != "capillary")
      stages[i].fail("water_content", "only with contact.cohesion = \"capillary\"");
  }
  if (cfg.contact.cohesion == "capillary" && (cfg.sim.dimension != 3 || cfg.sim.solver != "dem"))
    root.table("contact")->fail("cohesion",
                                "\"none\" here, or a 3D DEM scenario (dimension = 3, solver = "
                                "\"dem\"): the bridge law is for spheres, and contact dynamics "
                                "has no cohesion yet");
  check_rolling(root, cfg);
  cfg.output = parse_output(root);
  cfg.warnings = scenario_warnings(cfg);
  return cfg;
}

ScenarioConfig load_scenario(const std::string& path) {
  const std::string name = clip(path);
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) {
    throw InputError(name + ": cannot read scenario: no such file");
  }
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw InputError(name + ": cannot read scenario: not a regular file");
  }
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  const auto too_large = [&](const std::string& bytes) {
    return InputError(
        fmt::format("{}: cannot read scenario: the file is {} bytes; at most {} "
                    "(64 MiB) are read",
                    name, bytes, kMaxScenarioBytes));
  };
  if (!ec && size > kMaxScenarioBytes) throw too_large(std::to_string(size));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(name + ": cannot read scenario: the file cannot be opened");
  std::string text;
  if (!ec) text.reserve(static_cast<std::size_t>(size));
  // Read in blocks up to the limit: a file that grew since file_size() is refused too.
  std::array<char, 1 << 16> block;
  while (in.read(block.data(), block.size()) || in.gcount() > 0) {
    text.append(block.data(), static_cast<std::size_t>(in.gcount()));
    if (text.size() > kMaxScenarioBytes)
      throw too_large("over " + std::to_string(kMaxScenarioBytes));
  }
  if (in.bad()) throw InputError(name + ": cannot read scenario: read failed");
  return parse_scenario(text, path);
}

ScenarioConfig parse_stored_scenario(const std::string& text, const std::string& path,
                                     const std::string& scenario_path) {
  // Relative file names start from the scenario's folder while it exists.
  const std::filesystem::path folder = std::filesystem::path(scenario_path).parent_path();
  std::error_code ec;
  const bool there = !scenario_path.empty() && std::filesystem::is_directory(folder, ec);
  try {
    return parse_scenario(text, path + " (embedded scenario)", there ? folder.string() : "");
  } catch (const InputError& e) {
    throw InputError(
        fmt::format("the scenario stored in the snapshot does not parse: {}", e.what()));
  }
}

}  // namespace sable
