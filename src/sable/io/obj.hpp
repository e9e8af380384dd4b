// Wavefront OBJ files, as far as a grain's shape needs them: the vertices.
//
// A line `v x y z` is a vertex; further numbers on it (a weight w, or the r g b colours some
// exporters add) are read as numbers and not used. Every other line (faces `f`, normals `vn`,
// texture coordinates `vt`, groups, materials, comments after `#`) is skipped: the shape of a
// convex grain is the convex hull of its vertices, whatever faces the file joins them by.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace sable {

// The vertices of the OBJ file `path`, in the file's order. Throws InputError naming the file,
// and the line (counted from 1) for a `v` line without three numbers, or with a number that is
// not finite; naming the file when it cannot be read or holds no `v` line.
std::vector<Eigen::Vector3d> read_obj_vertices(const std::string& path);

}  // namespace sable
