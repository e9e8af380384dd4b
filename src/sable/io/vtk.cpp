#include "sable/io/vtk.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <optional>
#include <sstream>

#include "sable/core/error.hpp"
#include "sable/geometry/grain_shapes.hpp"
#include "sable/io/atomic_file.hpp"
#include "sable/io/vtk_xml.hpp"
#include "sable/world/element_forces.hpp"

namespace sable {

namespace {

using P3 = std::array<double, 3>;
using Buf = fmt::memory_buffer;

std::string xml_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string xml_unescape(const std::string& s) {
  static const std::pair<const char*, char> kEntities[] = {
      {"&amp;", '&'}, {"&lt;", '<'}, {"&gt;", '>'}, {"&quot;", '"'}, {"&apos;", '\''}};
  std::string out;
  for (std::size_t k = 0; k < s.size();) {
    bool replaced = false;
    for (const auto& [entity, c] : kEntities) {
      if (s.compare(k, std::char_traits<char>::length(entity), entity) == 0) {
        out += c;
        k += std::char_traits<char>::length(entity);
        replaced = true;
        break;
      }
    }
    if (!replaced) out += s[k++];
  }
  return out;
}

struct CellCounts {
  std::size_t points = 0, verts = 0, lines = 0, polys = 0;
};

void begin_piece(VtkXmlWriter& s, const CellCounts& c) {
  s.text(
      "<PolyData>\n<Piece NumberOfPoints=\"{}\" NumberOfVerts=\"{}\" NumberOfLines=\"{}\" "
      "NumberOfStrips=\"0\" NumberOfPolys=\"{}\">\n",
      c.points, c.verts, c.lines, c.polys);
}

void end_piece(VtkXmlWriter& s) {
  s.text("</Piece>\n</PolyData>\n");
}

void real_array(VtkXmlWriter& s, const char* name, int comps, const std::vector<double>& values) {
  s.real_array(name, comps, values.size(), [&](std::size_t k) { return values[k]; });
}

template <class I>
void int_array(VtkXmlWriter& s, const char* name, const std::vector<I>& values) {
  s.int_array<I>(name, values.size(), [&](std::size_t k) { return values[k]; });
}

void points_section(VtkXmlWriter& s, std::size_t count, const auto& value) {
  s.text("<Points>\n");
  s.real_array("Points", 3, count, value);
  s.text("</Points>\n");
}

// A Verts, Lines or Polys section of `cells` cells of `size` points each, point k of the
// connectivity being point k (the grains' vertices and the contacts' segments).
void uniform_cells_section(VtkXmlWriter& s, const char* tag, std::size_t cells, std::size_t size) {
  s.text("<{}>\n", tag);
  s.int_array<std::int64_t>("connectivity", cells * size, [](std::size_t k) { return k; });
  s.int_array<std::int64_t>("offsets", cells, [&](std::size_t c) { return (c + 1) * size; });
  s.text("</{}>\n", tag);
}

// A Verts, Lines or Polys section: the cells' point indices one after the other, and where
// each cell ends in them.
void cells_section(VtkXmlWriter& s, const char* tag, const std::vector<std::int64_t>& connectivity,
                   const std::vector<std::int64_t>& offsets) {
  s.text("<{}>\n", tag);
  int_array(s, "connectivity", connectivity);
  int_array(s, "offsets", offsets);
  s.text("</{}>\n", tag);
}

// A Verts, Lines or Polys section from each cell's point indices.
void cells_section(VtkXmlWriter& s, const char* tag,
                   const std::vector<std::vector<std::int64_t>>& cells) {
  std::vector<std::int64_t> connectivity, offsets;
  for (const auto& cell : cells) {
    connectivity.insert(connectivity.end(), cell.begin(), cell.end());
    offsets.push_back(static_cast<std::int64_t>(connectivity.size()));
  }
  cells_section(s, tag, connectivity, offsets);
}

void append3(std::vector<double>& out, const P3& p) {
  out.insert(out.end(), p.begin(), p.end());
}

template <class V>
bool nonzero(const V& f) {
  return (f.array() != 0.0).any();
}

// Touching contacts (non-zero last force) per grain, grain-grain and grain-wall.
template <int D>
std::vector<std::int32_t> coordination(const World<D>& w) {
  const std::size_t n = w.particles.size();
  std::vector<std::int32_t> z(n, 0);
  const auto& pl = w.neighbors.pairs;
  for (std::size_t k = 0; k < pl.size(); ++k) {
    if (!nonzero(pl.force[k]) || pl.i[k] >= n || pl.j[k] >= n) continue;
    ++z[pl.i[k]];
    ++z[pl.j[k]];
  }
  const auto& wl = w.neighbors.wall_pairs;
  for (std::size_t k = 0; k < wl.size(); ++k)
    if (nonzero(wl.force[k]) && wl.i[k] < n) ++z[wl.i[k]];
  return z;
}

}  // namespace

template <int D>
void write_grains_vtp(const World<D>& world, const std::string& path, VtkEncoding encoding) {
  using S = Space<D>;
  const auto& p = world.particles;
  const std::size_t n = p.size();
  const std::vector<std::int32_t> z = coordination(world);
  // Per-grain vectors as 3D points, read in place (a 2D vector gets z = 0, a 2D spin is the
  // z component): component k of the flattened array.
  const auto vec3 = [](const auto& v) {
    return [&v](std::size_t k) { return S::to_array(v[k / 3])[k % 3]; };
  };
  const auto spin3 = [&](std::size_t k) { return S::rot_to_array(p.omega[k / 3])[k % 3]; };
  write_pieces_atomic(path, [&](const PutText& put) {
    write_vtk_xml(put, encoding, "PolyData", [&](VtkXmlWriter& s) {
      begin_piece(s, {n, n, 0, 0});
      s.text("<PointData Scalars=\"radius\" Vectors=\"velocity\">\n");
      s.int_array<std::int64_t>("id", n, [&](std::size_t k) { return p.id[k].index; });
      real_array(s, "radius", 1, p.radius);
      s.real_array("velocity", 3, 3 * n, vec3(p.v));
      s.real_array("angular_velocity", 3, 3 * n, spin3);
      s.real_array("force", 3, 3 * n, vec3(p.f));
      int_array(s, "coordination", z);
      s.int_array<std::int32_t>("material", n, [&](std::size_t k) { return p.material[k]; });
      s.int_array<std::uint8_t>("fixed", n, [&](std::size_t k) { return p.fixed(k) ? 1 : 0; });
      s.text("</PointData>\n");
      points_section(s, 3 * n, vec3(p.x));
      uniform_cells_section(s, "Verts", n, 1);
      end_piece(s);
    });
  });
}

template <int D>
void write_contacts_vtp(const World<D>& world, const std::string& path, VtkEncoding encoding) {
  using S = Space<D>;
  using Vec = typename S::Vec;
  const auto& p = world.particles;
  const auto& pl = world.neighbors.pairs;
  std::vector<double> xyz, fn, fn_vec, ft_vec, bridge;
  std::vector<std::int64_t> id_i, id_j;
  const bool wet = pl.bridge.size() == pl.size() && world.neighbors.bridges;
  // A polyhedral contact acts at the point its solver stored, off the line of centres: it is
  // drawn as two segments, x_i to the point to x_j, along the stored normal.
  const auto& g = world.contact_geometry;
  const bool through = !world.shapes.empty() && g.pairs.size() == pl.size();
  for (std::size_t k = 0; k < pl.size(); ++k) {
    const std::uint32_t i = pl.i[k], j = pl.j[k];
    if (!nonzero(pl.force[k]) || i >= p.size() || j >= p.size()) continue;
    const Vec d = p.x[i] - p.x[j];
    const double dist = d.norm();
    const Vec n = through ? Vec(-g.pairs.normal[k]) : dist > 0.0 ? Vec(d / dist) : Vec(Vec::Zero());
    const Vec& f = pl.force[k];
    const double f_n = f.dot(n);
    append3(xyz, S::to_array(p.x[i]));
    if (through) append3(xyz, S::to_array(Vec(p.x[i] + g.pairs.arm[k])));
    append3(xyz, S::to_array(p.x[j]));
    fn.push_back(f_n);
    append3(fn_vec, S::to_array(Vec(f_n * n)));
    append3(ft_vec, S::to_array(Vec(f - f_n * n)));
    id_i.push_back(p.id[i].index);
    id_j.push_back(p.id[j].index);
    if (wet) bridge.push_back(pl.bridge[k]);
  }
  const std::size_t lines = fn.size();  // one line per contact, from x_i to x_j
  const std::size_t per_line = through ? 3 : 2;
  write_pieces_atomic(path, [&](const PutText& put) {
    write_vtk_xml(put, encoding, "PolyData", [&](VtkXmlWriter& s) {
      begin_piece(s, {per_line * lines, 0, lines, 0});
      s.text("<CellData Scalars=\"normal_force\">\n");
      real_array(s, "normal_force", 1, fn);
      real_array(s, "normal_force_vector", 3, fn_vec);
      real_array(s, "tangential_force", 3, ft_vec);
      int_array(s, "id_i", id_i);
      int_array(s, "id_j", id_j);
      // Wet law: the liquid-bridge volume of each bond (m^3; -1 where there is none).
      if (wet) real_array(s, "bridge_volume", 1, bridge);
      s.text("</CellData>\n");
      points_section(s, xyz.size(), [&](std::size_t k) { return xyz[k]; });
      uniform_cells_section(s, "Lines", lines, per_line);
      end_piece(s);
    });
  });
}

namespace {

// Wall outlines as 3D points and cells (lines in 2D, polygons in 3D) with their wall index.
struct WallMesh {
  std::vector<double> xyz;
  std::vector<std::vector<std::int64_t>> cells;
  std::vector<std::int32_t> wall;
  // Per cell, its mesh element (-1 for a plane's or a cylinder's cells): element.size() is
  // kept equal to cells.size(); `first` is where the current wall's cells begin.
  std::vector<std::int32_t> element;
  std::size_t first = 0;

  std::int64_t point(const P3& p) {
    append3(xyz, p);
    return static_cast<std::int64_t>(xyz.size() / 3 - 1);
  }
};

// Corners of the intersection of a plane with the box lo..hi, ordered around the polygon so
// that its right-hand normal is the wall normal (3D), or the two ends of the segment (2D).
template <int D>
std::vector<typename Space<D>::Vec> clip_plane(const Wall<D>& wall,
                                               const typename Space<D>::Vec& lo,
                                               const typename Space<D>::Vec& hi) {
  using Vec = typename Space<D>::Vec;
  const double diag = (hi - lo).norm();
  std::vector<Vec> pts;
  if (!((hi - lo).array() > 0.0).all()) return pts;
  const double tol = 1e-12 * diag;
  auto corner = [&](int mask) {
    Vec c;
    for (int d = 0; d < D; ++d) c[d] = (mask >> d) & 1 ? hi[d] : lo[d];
    return c;
  };
  auto add = [&](const Vec& c) {
    for (const Vec& q : pts)
      if ((q - c).norm() <= 1e-9 * diag) return;
    pts.push_back(c);
  };
  for (int m = 0; m < (1 << D); ++m) {
    for (int d = 0; d < D; ++d) {
      if ((m >> d) & 1) continue;
      const Vec a = corner(m), c = corner(m | (1 << d));
      const double sa = (a - wall.point).dot(wall.normal()),
                   sc = (c - wall.point).dot(wall.normal());
      if (std::abs(sa) <= tol) add(a);
      if (std::abs(sc) <= tol) add(c);
      if ((sa < -tol && sc > tol) || (sa > tol && sc < -tol)) add(a + (c - a) * (sa / (sa - sc)));
    }
  }
  if (pts.size() < static_cast<std::size_t>(D)) return {};
  Vec centre = Vec::Zero();
  for (const Vec& q : pts) centre += q / static_cast<double>(pts.size());
  std::vector<double> key(pts.size());
  if constexpr (D == 2) {
    const Vec t(-wall.normal().y(), wall.normal().x());
    for (std::size_t k = 0; k < pts.size(); ++k) key[k] = (pts[k] - centre).dot(t);
  } else {
    const Vec n = wall.normal().normalized();
    const Vec u = n.unitOrthogonal(), v = n.cross(u);
    for (std::size_t k = 0; k < pts.size(); ++k)
      key[k] = std::atan2((pts[k] - centre).dot(v), (pts[k] - centre).dot(u));
  }
  std::vector<std::size_t> order(pts.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t c) { return key[a] < key[c]; });
  std::vector<Vec> out;
  for (std::size_t k : order) out.push_back(pts[k]);
  if constexpr (D == 2) return {out.front(), out.back()};
  return out;
}

// A 64-sided inside-cylinder: triangles facing the axis in 3D, a closed polyline in 2D.
template <int D>
void cylinder_cells(const Wall<D>& wall, const World<D>& world, std::int32_t index,
                    WallMesh& mesh) {
  constexpr int kSides = 64;
  constexpr double kTwoPi = 6.283185307179586476925;
  const auto c = Space<D>::to_array(wall.point);
  std::vector<std::int64_t> bottom, top;
  for (int s = 0; s < kSides; ++s) {
    const double a = kTwoPi * s / kSides;
    const double radius = std::get<CylinderShape<D>>(wall.shape).radius;
    const double x = c[0] + radius * std::cos(a), y = c[1] + radius * std::sin(a);
    if constexpr (D == 3) {
      bottom.push_back(mesh.point({x, y, world.neighbors.domain_lo.z()}));
      top.push_back(mesh.point({x, y, world.neighbors.domain_hi.z()}));
    } else {
      bottom.push_back(mesh.point({x, y, 0.0}));
    }
  }
  if constexpr (D == 2) {
    bottom.push_back(bottom.front());
    mesh.cells.push_back(bottom);
    mesh.wall.push_back(index);
    return;
  }
  for (int s = 0; s < kSides; ++s) {
    const int t = (s + 1) % kSides;
    mesh.cells.push_back({bottom[s], top[t], bottom[t]});
    mesh.cells.push_back({bottom[s], top[s], top[t]});
    mesh.wall.push_back(index);
    mesh.wall.push_back(index);
  }
}

// A mesh wall's elements at its current pose, one cell each (their forces: write_walls_vtp).
template <int D>
void mesh_cells(const MeshShape<D>& m, std::int32_t index, WallMesh& mesh) {
  const auto first = static_cast<std::int64_t>(mesh.xyz.size() / 3);
  for (const auto& x : m.vertices()) mesh.point(Space<D>::to_array(x));
  for (const auto& e : m.surface().elements) {
    std::vector<std::int64_t> cell;
    for (std::uint32_t v : e) cell.push_back(first + v);
    mesh.cells.push_back(cell);
    mesh.wall.push_back(index);
    mesh.element.push_back(static_cast<std::int32_t>(mesh.element.size() - mesh.first));
  }
}

}  // namespace

template <int D>
void write_walls_vtp(const World<D>& world, const std::string& path, VtkEncoding encoding) {
  using S = Space<D>;
  WallMesh mesh;
  for (std::size_t k = 0; k < world.walls.size(); ++k) {
    const Wall<D>& wall = world.walls[k];
    const auto index = static_cast<std::int32_t>(k);
    if (std::holds_alternative<CylinderShape<D>>(wall.shape)) {
      cylinder_cells(wall, world, index, mesh);
      continue;
    }
    mesh.element.resize(mesh.cells.size(), -1);
    mesh.first = mesh.cells.size();
    if (const auto* m = wall.mesh()) {
      mesh_cells(*m, index, mesh);
      continue;
    }
    std::vector<std::int64_t> cell;
    for (const auto& q : clip_plane(wall, world.neighbors.domain_lo, world.neighbors.domain_hi))
      cell.push_back(mesh.point(S::to_array(q)));
    if (cell.empty()) continue;
    mesh.cells.push_back(cell);
    mesh.wall.push_back(index);
  }
  mesh.element.resize(mesh.cells.size(), -1);
  // Per cell the wall's total force, and the force on the cell itself: a mesh element's own
  // (the grains' contacts kept in its list entries), a plane's or a cylinder's whole force.
  std::vector<double> force, cell_force;
  std::vector<std::vector<typename S::Vec>> per_element(world.walls.size());
  for (std::size_t w = 0; w < world.walls.size(); ++w) per_element[w] = element_forces(world, w);
  for (std::size_t c = 0; c < mesh.wall.size(); ++c) {
    const auto w = static_cast<std::size_t>(mesh.wall[c]);
    append3(force, S::to_array(world.walls[w].force));
    const auto e = static_cast<std::size_t>(mesh.element[c]);
    append3(cell_force, S::to_array(mesh.element[c] < 0         ? world.walls[w].force
                                    : e < per_element[w].size() ? per_element[w][e]
                                                                : S::zero()));
  }
  const std::size_t ncells = mesh.cells.size();
  write_pieces_atomic(path, [&](const PutText& put) {
    write_vtk_xml(put, encoding, "PolyData", [&](VtkXmlWriter& s) {
      begin_piece(s, {mesh.xyz.size() / 3, 0, D == 2 ? ncells : 0, D == 3 ? ncells : 0});
      s.text("<CellData Scalars=\"wall\" Vectors=\"force\">\n");
      int_array(s, "wall", mesh.wall);
      real_array(s, "force", 3, force);
      int_array(s, "element", mesh.element);
      real_array(s, "cell_force", 3, cell_force);
      s.text("</CellData>\n");
      points_section(s, mesh.xyz.size(), [&](std::size_t k) { return mesh.xyz[k]; });
      cells_section(s, D == 2 ? "Lines" : "Polys", mesh.cells);
      end_piece(s);
    });
  });
}

namespace {

// The faces of the polyhedral grains at their poses: each grain's corners once, then its faces
// as loops of those points, each with the grain's slot (its per-grain data) and its normal.
struct PolyhedronFaces {
  std::vector<double> xyz;
  std::vector<std::int64_t> connectivity, offsets;
  std::vector<std::uint32_t> owner;  // per face, the grain's slot
  std::vector<double> normal;        // per face, 3 components

  explicit PolyhedronFaces(const World<3>& world) {
    const auto& p = world.particles;
    for (std::size_t k = 0; k < p.size(); ++k) {
      if (!p.polyhedron(k)) continue;
      const ConvexPolyhedron& solid = world.shapes[p.shape_index[k]].solid;
      const auto first = static_cast<std::int64_t>(xyz.size() / 3);
      for (const Eigen::Vector3d& v : solid.vertices()) {
        const Eigen::Vector3d x = p.q[k] * v + p.x[k];
        xyz.insert(xyz.end(), x.data(), x.data() + 3);
      }
      for (std::size_t f = 0; f < solid.face_count(); ++f) {
        // The body-frame loops run counterclockwise seen from outside; a rotation keeps that.
        for (std::uint32_t c : solid.face(f)) connectivity.push_back(first + c);
        offsets.push_back(static_cast<std::int64_t>(connectivity.size()));
        owner.push_back(static_cast<std::uint32_t>(k));
        const Eigen::Vector3d n = p.q[k] * solid.normals()[f];
        normal.insert(normal.end(), n.data(), n.data() + 3);
      }
    }
  }
};

}  // namespace

void write_polyhedra_vtp(const World<3>& world, const std::string& path, VtkEncoding encoding) {
  const auto& p = world.particles;
  const PolyhedronFaces faces(world);
  const std::size_t nfaces = faces.owner.size();
  // Each face carries its grain's data, read in place through the face's owner.
  const auto grain3 = [&](const std::vector<Eigen::Vector3d>& v) {
    return [&faces, &v](std::size_t k) { return v[faces.owner[k / 3]][k % 3]; };
  };
  const auto grain = [&](std::size_t f) { return faces.owner[f]; };
  write_pieces_atomic(path, [&](const PutText& put) {
    write_vtk_xml(put, encoding, "PolyData", [&](VtkXmlWriter& s) {
      begin_piece(s, {faces.xyz.size() / 3, 0, 0, nfaces});
      s.text("<CellData Scalars=\"id\" Vectors=\"velocity\" Normals=\"normal\">\n");
      s.int_array<std::int64_t>("id", nfaces, [&](std::size_t f) { return p.id[grain(f)].index; });
      s.real_array("velocity", 3, 3 * nfaces, grain3(p.v));
      s.real_array("angular_velocity", 3, 3 * nfaces, grain3(p.omega));
      s.int_array<std::int32_t>("material", nfaces,
                                [&](std::size_t f) { return p.material[grain(f)]; });
      s.int_array<std::uint8_t>("fixed", nfaces,
                                [&](std::size_t f) { return p.fixed(grain(f)) ? 1 : 0; });
      real_array(s, "normal", 3, faces.normal);
      s.text("</CellData>\n");
      points_section(s, faces.xyz.size(), [&](std::size_t k) { return faces.xyz[k]; });
      cells_section(s, "Polys", faces.connectivity, faces.offsets);
      end_piece(s);
    });
  });
}

// --- PvdSeries

PvdSeries::PvdSeries(std::string path) : path_(std::move(path)) {}

namespace {

// The value of attribute `name` in one XML start tag, or nullopt.
std::optional<std::string> xml_attr(const std::string& tag, const std::string& name) {
  const std::string key = " " + name + "=\"";
  const auto start = tag.find(key);
  if (start == std::string::npos) return std::nullopt;
  const auto from = start + key.size();
  const auto end = tag.find('"', from);
  if (end == std::string::npos) return std::nullopt;
  return xml_unescape(tag.substr(from, end - from));
}

}  // namespace

PvdSeries::PvdSeries(std::string path, double resume_time) : path_(std::move(path)) {
  std::ifstream in(path_);
  if (!in) return;  // nothing written yet: start a new series
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  for (auto pos = text.find("<DataSet"); pos != std::string::npos;
       pos = text.find("<DataSet", pos + 1)) {
    const std::string tag = text.substr(pos, text.find('>', pos) - pos);
    const auto time = xml_attr(tag, "timestep");
    const auto file = xml_attr(tag, "file");
    if (!time || !file) throw InputError(fmt::format("'{}': unreadable DataSet entry", path_));
    char* end = nullptr;
    const double t = std::strtod(time->c_str(), &end);
    if (end == time->c_str())
      throw InputError(fmt::format("'{}': bad timestep \"{}\"", path_, *time));
    if (t <= resume_time) entries_.emplace_back(t, *file);
  }
  write();
}

void PvdSeries::add(double time, const std::string& file_relative) {
  entries_.emplace_back(time, file_relative);
  write();
}

void PvdSeries::write() const {
  Buf b;
  fmt::format_to(std::back_inserter(b),
                 "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" "
                 "byte_order=\"LittleEndian\">\n<Collection>\n");
  // Times with 17 digits: a resumed series compares them exactly with the snapshot time.
  for (const auto& [t, file] : entries_) {
    fmt::format_to(std::back_inserter(b),
                   "  <DataSet timestep=\"{:.17g}\" group=\"\" part=\"0\" file=\"{}\"/>\n", t,
                   xml_escape(file));
  }
  fmt::format_to(std::back_inserter(b), "</Collection>\n</VTKFile>\n");
  write_text_atomic(path_, fmt::to_string(b));
}

template void write_grains_vtp<2>(const World<2>&, const std::string&, VtkEncoding);
template void write_grains_vtp<3>(const World<3>&, const std::string&, VtkEncoding);
template void write_contacts_vtp<2>(const World<2>&, const std::string&, VtkEncoding);
template void write_contacts_vtp<3>(const World<3>&, const std::string&, VtkEncoding);
template void write_walls_vtp<2>(const World<2>&, const std::string&, VtkEncoding);
template void write_walls_vtp<3>(const World<3>&, const std::string&, VtkEncoding);

}  // namespace sable
