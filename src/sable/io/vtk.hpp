// VTK XML PolyData output (.vtp) for ParaView, and .pvd time-series collections.
//
// Three files describe a moment of a run: the grains (points with per-grain data and a vertex
// cell each so ParaView draws them), the touching contacts (a line between the two centres,
// with the normal and tangential force), and the walls (planes clipped to the neighbour-list
// domain box, cylinders as a triangulated side surface). A 3D run with polyhedral grains adds
// a fourth: their faces as polygons at the grains' poses. 2D runs write z = 0 and the angular
// velocity as (0, 0, w). Every file is replaced atomically (temporary + rename). The arrays are
// raw binary by default, zlib-compressed or ASCII on request (io/vtk_xml.hpp).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "sable/io/vtk_xml.hpp"
#include "sable/world/world.hpp"

namespace sable {

// One point per grain, at its centre (a polyhedron's centroid). PointData: id (stable id
// index), radius (a polyhedron's: its bounding sphere's about the centroid, the radius the
// broad phase uses; its faces are in write_polyhedra_vtp's file), velocity, angular_velocity,
// force, coordination (touching grain and wall contacts), material, fixed.
template <int D>
void write_grains_vtp(const World<D>& world, const std::string& path,
                      VtkEncoding encoding = VtkEncoding::kBinary);

// One line cell per touching grain pair. CellData: normal_force (f.n, n from j to i; positive
// when pushing apart), normal_force_vector, tangential_force (force on grain i), id_i, id_j.
template <int D>
void write_contacts_vtp(const World<D>& world, const std::string& path,
                        VtkEncoding encoding = VtkEncoding::kBinary);

// Planes clipped to world.neighbors.domain_lo..hi (a polygon in 3D, a segment in 2D; a plane
// that misses the box draws nothing), inside-cylinders as 64-sided side surfaces from
// domain_lo.z to domain_hi.z (a circle in 2D). CellData: wall (index), force (on the wall).
template <int D>
void write_walls_vtp(const World<D>& world, const std::string& path,
                     VtkEncoding encoding = VtkEncoding::kBinary);

// One polygon cell per face of every polyhedral grain (round grains are not in this file),
// its corners counterclockwise seen from outside (the loop's right-hand normal points out, as
// the normals ParaView computes from a polygon's winding then do). Each grain's corners are
// written once, posed in the world: q * v + x, the body-frame corner v turned by the grain's
// orientation q and moved to its centroid x. CellData per face: id (the grain's stable id
// index), velocity, angular_velocity, material, fixed (the grain's), normal (the face's
// outward unit normal in the world). A 2D world has no polyhedra: 3D only.
void write_polyhedra_vtp(const World<3>& world, const std::string& path,
                         VtkEncoding encoding = VtkEncoding::kBinary);

// A ParaView .pvd collection of time steps, rewritten atomically after each add.
class PvdSeries {
 public:
  explicit PvdSeries(std::string path);
  // Resuming a run: keep the entries of an existing `path` with time <= `resume_time`, so the
  // series continues without the steps the resumed run will write again.
  PvdSeries(std::string path, double resume_time);

  // Record `file_relative` (relative to the .pvd's directory) at `time` and rewrite the file.
  void add(double time, const std::string& file_relative);

  const std::string& path() const { return path_; }
  const std::vector<std::pair<double, std::string>>& entries() const { return entries_; }

 private:
  void write() const;

  std::string path_;
  std::vector<std::pair<double, std::string>> entries_;
};

}  // namespace sable
