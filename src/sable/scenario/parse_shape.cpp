#include "sable/scenario/parse_shape.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <optional>

#include "sable/core/error.hpp"
#include "sable/generation/shape_draws.hpp"

namespace sable::detail {

namespace {

// Random polyhedra: at least a tetrahedron; at most 64 corners, since the narrow phase's
// cost grows with the faces and edges it tests (separating axes) and 64 points on a sphere
// make 124 faces.
constexpr std::int64_t kMinVertices = 4;
constexpr std::int64_t kMaxVertices = 64;

constexpr Range kAspect{0.0, 1.0, true, false};

// polyhedron = { vertices = N, aspect = [a, b, c] }
void parse_random_polyhedron(const Table& p, GrainShapeConfig& s) {
  p.check_keys({"vertices", "aspect"});
  s.kind = GrainShapeConfig::Kind::kRandomPolyhedron;
  if (const toml::node* n = p.find("vertices")) {
    const std::string expected =
        fmt::format("an integer in [{}, {}] (the points drawn on the sphere, each a corner)",
                    kMinVertices, kMaxVertices);
    const auto* count = n->as_integer();
    if (count == nullptr) fail_type(*n, p.key_path("vertices"), p.file(), expected);
    if (count->get() < kMinVertices || count->get() > kMaxVertices)
      fail_value(*n, p.key_path("vertices"), p.file(), expected);
    s.vertices = static_cast<std::size_t>(count->get());
  }
  if (const toml::node* a = p.find("aspect")) {
    const std::string key = p.key_path("aspect");
    s.aspect = to_vector(*a, key, p.file(), 3);
    for (std::size_t k = 0; k < 3; ++k)
      to_number(*a->as_array()->get(k), key + "[" + std::to_string(k) + "]", p.file(), kAspect);
  }
}

// points = [[x, y, z], ...]: at least 4, spanning a solid that the shape table takes.
void parse_points(const Table& t, GrainShapeConfig& s) {
  const toml::array* points = t.array("points");
  const std::string key = t.key_path("points");
  if (points->size() < 4)
    t.fail("points", "an array of at least 4 points [x, y, z] spanning a solid");
  std::vector<Eigen::Vector3d> given;
  for (std::size_t i = 0; i < points->size(); ++i) {
    s.points.push_back(
        to_vector(*points->get(i), key + "[" + std::to_string(i) + "]", t.file(), 3));
    given.emplace_back(s.points.back()[0], s.points.back()[1], s.points.back()[2]);
  }
  try {
    unit_shape(given, key);
  } catch (const InputError& e) {
    fail_at(t.find("points")->source(), t.file(), e.what());
  }
}

// file = "rock.stl" | "rock.obj": relative to the scenario's folder.
void parse_shape_file(const Table& t, GrainShapeConfig& s) {
  namespace fs = std::filesystem;
  fs::path p(t.required_string("file"));
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext != ".stl" && ext != ".obj")
    t.fail("file", "an STL file (.stl) or an OBJ file (.obj) of the shape's vertices");
  if (p.is_relative()) p = fs::path(t.folder()) / p;
  s.file = p.lexically_normal().string();
  std::error_code ec;
  if (!fs::is_regular_file(p, ec))
    t.fail("file", "an existing shape file (nothing readable at " + in_quotes(s.file) + ")");
}

}  // namespace

GrainShapeConfig parse_grain_shape(const Table& g, const ScenarioConfig& cfg) {
  GrainShapeConfig s;
  s.key = g.key_path("shape");
  const toml::node* node = g.find("shape");
  if (node == nullptr) return s;
  if (cfg.sim.dimension != 3)
    g.reject("shape", "in 2D (grains are disks there; polyhedral grains are 3D only)");
  const std::string expected =
      "\"sphere\" or a table { polyhedron = {...} }, { points = [...] } or { file = \"...\" }";
  if (node->is_string()) {
    if (node->as_string()->get() != "sphere") fail_value(*node, s.key, g.file(), expected);
    return s;
  }
  if (!node->is_table()) fail_type(*node, s.key, g.file(), expected);
  const Table t = *g.table("shape");
  t.check_keys({"polyhedron", "points", "file", "orientation"});
  const int given =
      (t.has("polyhedron") ? 1 : 0) + (t.has("points") ? 1 : 0) + (t.has("file") ? 1 : 0);
  if (given != 1)
    g.fail("shape", std::string("a table with exactly one of polyhedron = {...}, points = [...] "
                                "or file = \"...\", found ") +
                        (given == 0 ? "none" : "several"));
  if (const auto p = t.table("polyhedron")) {
    t.reject("orientation",
             "to polyhedron = {...} (random polyhedra are turned at random; only to points = "
             "[...] and file = \"...\")");
    parse_random_polyhedron(*p, s);
    return s;
  }
  s.kind = GrainShapeConfig::Kind::kGiven;
  s.random_orientation = t.choice("orientation", {"random", "aligned"}, "random") == "random";
  if (t.has("points"))
    parse_points(t, s);
  else
    parse_shape_file(t, s);
  return s;
}

void check_polyhedral_scenario(const Table& root, const ScenarioConfig& cfg) {
  const auto poly = std::find_if(cfg.grains.begin(), cfg.grains.end(),
                                 [](const GrainsConfig& g) { return g.shape.polyhedral(); });
  if (poly == cfg.grains.end()) return;
  const std::string& key = poly->shape.key;
  const auto blocks = root.table_array("grains");
  for (std::size_t k = 0; k < cfg.grains.size(); ++k)
    if (!cfg.grains[k].shape.polyhedral())
      fail_at(blocks[k].raw().source(), root.file(),
              fmt::format("{}: expected a polyhedral shape = {{...}}, as {} has: contact "
                          "dynamics steps a world of polyhedral grains or of round ones, not both",
                          blocks[k].name(), key));
  const auto walls = root.table_array("wall");
  for (std::size_t k = 0; k < cfg.walls.size(); ++k)
    if (cfg.walls[k].type != "plane" && cfg.walls[k].type != "box")
      walls[k].fail("type", "\"plane\" or \"box\" with polyhedral grains (" + key +
                                "): they touch plane walls only");
  if (cfg.sim.solver != "cd") {  // DEM: the manifold law (dem/polyhedral_dem.hpp)
    const std::string why =
        " with polyhedral grains (" + key +
        ") and DEM: a linear spring per contact point (docs/contact-laws.md, \"Polyhedral "
        "grains\"); a Hertz law needs a curvature, which corners and edges do not have";
    if (cfg.contact.normal != "linear") {
      if (const auto c = root.table("contact"); c && c->has("normal"))
        c->fail("normal", "\"linear\"" + why);
      const auto at = static_cast<std::size_t>(poly - cfg.grains.begin());
      fail_at(blocks[at].find("shape")->source(), root.file(),
              fmt::format("{}: expected [contact] normal = \"linear\"{}", key, why));
    }
    if (cfg.contact.cohesion != "none")
      root.table("contact")->fail("cohesion", "\"none\" with polyhedral grains (" + key +
                                                  "): no cohesion law applies to them yet");
  }
  if (cfg.contact.rolling != "none")
    root.table("contact")->fail("rolling", "\"none\" with polyhedral grains (" + key +
                                               "): their faces resist rolling, and no rolling "
                                               "law applies to them");
}

}  // namespace sable::detail
