// VTK XML ImageData output (.vti) for fields on a regular grid of points.
//
// A .vti file is the natural container for coarse-grained continuum fields: ParaView reads
// the grid from three numbers per axis (point count, origin, spacing) instead of a list of
// coordinates, and draws scalars, vectors and tensors (tensor glyphs, e.g. stress
// ellipsoids) from named PointData arrays. Points are ordered x fastest, then y, then z, as
// VTK expects. The file is replaced atomically (temporary + rename, io/atomic_file.hpp). The
// arrays are raw binary by default, zlib-compressed or ASCII on request (io/vtk_xml.hpp).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "sable/io/vtk_xml.hpp"

namespace sable {

// One PointData array: `components` values per point, points in VTK order (x fastest).
struct VtiArray {
  std::string name;
  int components = 1;  // 1 scalar, 3 vector, 9 tensor (row-major 3x3)
  std::vector<double> values;
};

struct VtiImage {
  std::array<int, 3> points{1, 1, 1};  // points per axis (>= 1)
  std::array<double, 3> origin{};      // position of point (0, 0, 0) (m)
  std::array<double, 3> spacing{1.0, 1.0, 1.0};
  std::vector<VtiArray> point_data;
  // Which arrays ParaView shows by default (empty: none named).
  std::string scalars, vectors, tensors;
  std::size_t size() const {
    return static_cast<std::size_t>(points[0]) * static_cast<std::size_t>(points[1]) *
           static_cast<std::size_t>(points[2]);
  }
};

// The .vti text. Throws InputError if a count is < 1 or an array does not hold
// components x size() values, naming the array.
std::string vti_text(const VtiImage& image, VtkEncoding encoding = VtkEncoding::kBinary);

// Write `image` to `path` atomically.
void write_vti(const VtiImage& image, const std::string& path,
               VtkEncoding encoding = VtkEncoding::kBinary);

}  // namespace sable
