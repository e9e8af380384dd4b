// [[wall]] tables and a stage's wall keys (parse_walls.hpp). As in parse.cpp, each table first
// rejects the keys that do not belong to it, then reads every key with its type and range
// checked; messages give file:line:column, the key's full name and what was expected.
#include "sable/scenario/parse_walls.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>

#include "sable/core/error.hpp"

namespace sable::detail {

namespace {

// The most elements (triangles, segments, points) a mesh wall's built-in shape may have: a wall
// of 10^8 triangles is a typing error, not a wall (it would need gigabytes).
constexpr std::uint64_t kMaxMeshElements = 100'000'000;
// The most facets round a built-in cylinder or circle: with one segment and caps, 4 * 10^7
// triangles, below kMaxMeshElements.
constexpr std::uint64_t kMaxFacets = 10'000'000;

const std::string kBoxTurns =
    "a box is independent plane walls (NAME.xlo, NAME.xhi, ...); a turning box is a wall of "
    "type = \"mesh\" with shape = { box = { lo = [...], hi = [...] } }";

// A direction: non-zero, its squared length a normal double (normalising it neither overflows
// nor divides by an underflowed zero).
void check_direction(const Table& t, std::string_view key, const Vec3a& a) {
  const double n2 = a[0] * a[0] + a[1] * a[1] + a[2] * a[2];
  if (!(n2 >= std::numeric_limits<double>::min()) || !std::isfinite(n2))
    t.fail(key, "a non-zero direction (a length between 1e-150 and 1e150)");
}

// rotation = { point = [...], axis = [...], rate = ... }; in 2D no axis (about z).
RotationConfig parse_rotation(const Table& r, int dim) {
  r.check_keys({"point", "axis", "rate"});
  RotationConfig rot;
  rot.point = r.required_vector("point", dim);
  if (dim == 3) {
    rot.axis = r.required_vector("axis", 3);
    check_direction(r, "axis", rot.axis);
  } else {
    r.reject("axis",
             "in 2D (a 2D wall turns about z through point: rate > 0 is counter-clockwise)");
  }
  const toml::node* rate = r.find("rate");
  if (rate == nullptr) r.fail_missing("rate", "a rate in rad/s (a number)");
  if (!rate->is_number()) fail_type(*rate, r.key_path("rate"), r.file(), "a rate in rad/s");
  rot.rate = to_number(*rate, r.key_path("rate"), r.file());
  return rot;
}

// The plane names a box wall expands to: NAME.xlo, NAME.xhi, ... (no z planes in 2D).
std::vector<std::string> box_planes(const std::string& name, int dim) {
  std::vector<std::string> out;
  for (const char* axis : {"x", "y", "z"}) {
    if (static_cast<int>(out.size()) == 2 * dim) break;
    out.push_back(name + "." + axis + "lo");
    out.push_back(name + "." + axis + "hi");
  }
  return out;
}

void parse_wall_geometry(const Table& t, WallConfig& w, int dim) {
  if (w.type == "plane") {
    w.point = t.required_vector("point", dim);
    w.normal = t.required_vector("normal", dim);
    const double len = std::sqrt(w.normal[0] * w.normal[0] + w.normal[1] * w.normal[1] +
                                 w.normal[2] * w.normal[2]);
    if (!(len > 0.0)) t.fail("normal", "a non-zero vector");
    for (double& c : w.normal) c /= len;
  } else if (w.type == "box") {
    w.lo = t.required_vector("lo", dim);
    w.hi = t.required_vector("hi", dim);
    check_ordered(t, "lo", "hi", w.lo, w.hi, dim);
  } else {
    if (dim != 3)
      t.fail("type", "\"plane\", \"box\" or \"mesh\" (a cylinder wall needs dimension = 3)");
    w.center = t.required_vector("center", 2);
    w.radius = t.required_number("radius", kPositive);
  }
}

// --- mesh walls ---------------------------------------------------------------------------

int facet_count(const Table& t) {
  const std::uint64_t f = t.unsigned_or("facets", 32, 3);
  if (f > kMaxFacets) t.fail("facets", fmt::format("an integer in [3, {}]", kMaxFacets));
  return static_cast<int>(f);
}

// shape = { cylinder = { center, axis, radius, length, facets, segments, caps } } (3D).
void parse_cylinder_shape(const Table& c, MeshConfig& m) {
  c.check_keys({"center", "axis", "radius", "length", "facets", "segments", "caps"});
  m.center = c.required_vector("center", 3);
  m.axis = c.vector("axis", 3).value_or(m.axis);
  check_direction(c, "axis", m.axis);
  m.radius = c.required_number("radius", kPositive);
  m.length = c.required_number("length", kPositive);
  m.facets = facet_count(c);
  m.caps = c.boolean_or("caps", m.caps);
  const std::uint64_t segments = c.unsigned_or("segments", 1, 1);
  const auto f = static_cast<std::uint64_t>(m.facets);
  if (segments > kMaxMeshElements || 2 * f * segments + (m.caps ? 2 * f : 0) > kMaxMeshElements)
    c.fail("segments", fmt::format("an integer >= 1 that keeps the cylinder within {} triangles "
                                   "(2 facets segments, + 2 facets with caps)",
                                   kMaxMeshElements));
  m.segments = static_cast<int>(segments);
}

// shape = { circle = { center, radius, facets } } (2D).
void parse_circle_shape(const Table& c, MeshConfig& m) {
  c.check_keys({"center", "radius", "facets"});
  m.center = c.required_vector("center", 2);
  m.radius = c.required_number("radius", kPositive);
  m.facets = facet_count(c);
}

// shape = { box = { lo, hi } }: the closed surface of the box (12 triangles, 4 segments in 2D).
void parse_box_shape(const Table& b, MeshConfig& m, int dim) {
  b.check_keys({"lo", "hi"});
  m.lo = b.required_vector("lo", dim);
  m.hi = b.required_vector("hi", dim);
  check_ordered(b, "lo", "hi", m.lo, m.hi, dim);
}

// shape = { polyline = { points = [[x, y], ...], closed = false } } (2D).
void parse_polyline_shape(const Table& p, MeshConfig& m) {
  p.check_keys({"points", "closed"});
  m.closed = p.boolean_or("closed", m.closed);
  const toml::array* points = p.array("points");
  if (points == nullptr) p.fail_missing("points", "an array of [x, y] points (at least 2)");
  if (points->size() < (m.closed ? 3u : 2u))
    p.fail("points",
           m.closed ? "at least 3 [x, y] points with closed = true" : "at least 2 [x, y] points");
  if (points->size() > kMaxMeshElements)
    p.fail("points", fmt::format("at most {} points", kMaxMeshElements));
  for (std::size_t i = 0; i < points->size(); ++i)
    m.points.push_back(to_vector(
        *points->get(i), p.key_path("points") + "[" + std::to_string(i) + "]", p.file(), 2));
}

// shape = { NAME = {...} }: exactly one built-in shape, those of the dimension.
void parse_mesh_shape(const Table& w, MeshConfig& m, int dim) {
  const auto s = w.table("shape");
  if (dim == 3) {
    s->reject("circle", "in 3D (a 2D shape; in 3D: cylinder = {...})");
    s->reject("polyline",
              "in 3D (a 2D mesh of segments; in 3D: file = \"...\" (STL), cylinder = {...} or "
              "box = {...})");
    s->check_keys({"cylinder", "box"});
  } else {
    s->reject("cylinder", "in 2D (a 3D shape; in 2D: circle = {...})");
    s->check_keys({"circle", "box", "polyline"});
  }
  if (s->raw().size() != 1)
    w.fail("shape", dim == 3 ? "exactly one of cylinder = {...} or box = {...}"
                             : "exactly one of circle = {...}, box = {...} or polyline = {...}");
  m.shape = std::string(s->raw().begin()->first.str());
  const auto body = s->table(m.shape);
  m.key = body->name();
  if (m.shape == "cylinder")
    parse_cylinder_shape(*body, m);
  else if (m.shape == "circle")
    parse_circle_shape(*body, m);
  else if (m.shape == "box")
    parse_box_shape(*body, m, dim);
  else
    parse_polyline_shape(*body, m);
}

// type = "mesh": file = "..." (STL, 3D) with scale and offset, or shape = {...}.
void parse_mesh(const Table& t, MeshConfig& m, int dim) {
  const std::string one =
      "exactly one of file = \"...\" (an STL file) or shape = {...} (a built-in shape)";
  if (t.has("file") && t.has("shape")) t.fail("shape", one + ", found both");
  if (!t.has("file") && !t.has("shape")) t.fail_missing("file", one);
  if (t.has("shape")) {
    const std::string why =
        "to a built-in shape (only to file = \"...\": a shape is given in metres where it stands)";
    t.reject("scale", why);
    t.reject("offset", why);
    parse_mesh_shape(t, m, dim);
    return;
  }
  if (dim != 3)
    t.fail("file",
           "a shape = {...} in 2D (an STL file holds triangles, a 3D surface; a 2D mesh is "
           "shape = { polyline = {...} }, { circle = {...} } or { box = {...} })");
  namespace fs = std::filesystem;
  fs::path p(t.required_string("file"));
  if (p.is_relative()) p = fs::path(t.folder()) / p;
  m.file = p.lexically_normal().string();
  std::error_code ec;
  if (!fs::is_regular_file(p, ec))
    t.fail("file", "an existing STL file (nothing readable at " + in_quotes(m.file) + ")");
  m.scale = t.number_or("scale", kPositive, m.scale);
  m.offset = t.vector("offset", 3).value_or(m.offset);
  m.key = t.key_path("file");
}

// Keys that belong to one wall type; any other type rejects them.
void reject_foreign_wall_keys(const Table& t, const std::string& type) {
  struct Use {
    std::string_view key;
    const char* type;
  };
  static constexpr Use kUses[] = {
      {"point", "plane"},     {"normal", "plane"},    {"lo", "box"},    {"hi", "box"},
      {"center", "cylinder"}, {"radius", "cylinder"}, {"file", "mesh"}, {"shape", "mesh"},
      {"scale", "mesh"},      {"offset", "mesh"}};
  for (const Use& u : kUses)
    if (type != u.type)
      t.reject(u.key, "to type = " + in_quotes(type) + " (only to \"" + u.type + "\")");
}

WallConfig parse_wall(const Table& t, const ScenarioConfig& cfg) {
  t.check_keys({"name", "type", "material", "velocity", "point", "normal", "lo", "hi", "center",
                "radius", "file", "scale", "offset", "shape", "rotation"});
  const int dim = cfg.sim.dimension;
  WallConfig w;
  w.name = t.required_string("name");
  w.type = t.choice("type", {"plane", "box", "cylinder", "mesh"}, w.type);
  reject_foreign_wall_keys(t, w.type);
  w.material = material_ref(t, cfg.materials);
  if (w.type == "mesh") {
    parse_mesh(t, w.mesh, dim);
  } else {
    parse_wall_geometry(t, w, dim);
  }
  w.velocity = t.vector("velocity", dim).value_or(w.velocity);
  if (w.type == "box") t.reject("rotation", "to type = \"box\": " + kBoxTurns);
  if (const auto r = t.table("rotation")) w.rotation = parse_rotation(*r, dim);
  w.loc = t.loc();
  return w;
}

}  // namespace

std::vector<WallConfig> parse_walls(const Table& root, const ScenarioConfig& cfg,
                                    std::vector<std::string>& names) {
  std::vector<WallConfig> out;
  for (const Table& t : root.table_array("wall")) {
    WallConfig w = parse_wall(t, cfg);
    std::vector<std::string> added{w.name};
    if (w.type == "box") {
      for (auto& plane : box_planes(w.name, cfg.sim.dimension)) added.push_back(plane);
    }
    for (const std::string& n : added) {
      for (const std::string& prev : names) {
        if (prev == n) t.fail("name", "a unique wall name (" + in_quotes(n) + " is already used)");
      }
    }
    names.insert(names.end(), added.begin(), added.end());
    out.push_back(std::move(w));
  }
  return out;
}

// wall_velocity = { floor = [...], "box.zhi" = [...] }; an unquoted box.zhi arrives as a
// nested table { box = { zhi = [...] } } and is accepted the same way.
void parse_wall_velocity(const Table& s, StageConfig& st, const std::vector<std::string>& names,
                         int dim) {
  const auto t = s.table("wall_velocity");
  if (!t) return;
  const std::string expected = names.empty()
                                   ? std::string("a wall name (there are no [[wall]] tables)")
                                   : "a wall name (known: " + join_names(names) + ")";
  for (auto&& [k, v] : t->raw()) {
    const std::string name(k.str());
    const std::string key = t->key_path(name);
    if (v.is_table() && contains(names, name + ".xlo")) {
      const Table sub(*v.as_table(), key, s.file());
      for (auto&& [pk, pv] : sub.raw()) {
        const std::string plane = name + "." + std::string(pk.str());
        if (!contains(names, plane)) {
          fail_at(pk.source(), s.file(),
                  "unknown wall " + sub.key_path(pk.str()) + ": expected " + expected);
        }
        st.wall_velocity[plane] = to_vector(pv, sub.key_path(pk.str()), s.file(), dim);
      }
      continue;
    }
    if (!contains(names, name)) {
      fail_at(k.source(), s.file(), "unknown wall " + key + ": expected " + expected);
    }
    st.wall_velocity[name] = to_vector(v, key, s.file(), dim);
  }
}

// wall_rotation = { drum = { point = [...], axis = [...], rate = ... } }: walls that may turn
// (not a box, nor its planes), as a wall's own rotation key.
void parse_wall_rotation(const Table& s, StageConfig& st, const ScenarioConfig& cfg) {
  const auto t = s.table("wall_rotation");
  if (!t) return;
  std::vector<std::string> turnable;
  for (const WallConfig& w : cfg.walls)
    if (w.type != "box") turnable.push_back(w.name);
  for (auto&& [k, v] : t->raw()) {
    const std::string name(k.str());
    const std::string key = t->key_path(name);
    for (const WallConfig& w : cfg.walls) {
      if (w.type != "box") continue;
      if (name == w.name || contains(box_planes(w.name, cfg.sim.dimension), name))
        fail_at(k.source(), s.file(),
                key + ": a box or box plane cannot turn (" + in_quotes(w.name) + ": " + kBoxTurns +
                    ")");
    }
    if (!contains(turnable, name))
      fail_at(k.source(), s.file(),
              "unknown wall " + key + ": expected " +
                  (turnable.empty() ? std::string("a wall name (there are no walls that can turn)")
                                    : "a wall name (known: " + join_names(turnable) + ")"));
    st.wall_rotation[name] = parse_rotation(*t->table(name), cfg.sim.dimension);
  }
}

}  // namespace sable::detail
