// STL files: the triangles of a mesh wall, read from (and written to) the format every CAD
// program exports.
//
// Both encodings are read. Binary: an 80-byte header, a little-endian uint32 triangle count,
// then 50 bytes per triangle (normal, three corners, 3 floats each, and a uint16 attribute).
// ASCII: "solid NAME", then per triangle "facet normal nx ny nz", "outer loop", three "vertex
// x y z" lines, "endloop", "endfacet", and "endsolid NAME" (keywords in any case; several solids
// one after another are read as one mesh). A file is binary when its size is exactly
// 84 + 50 * (the count in bytes 80..83), whatever its first bytes say: many exporters begin a
// binary header with "solid". Otherwise it is ASCII if it begins with "solid" and holds only
// text; other text is refused as no STL, anything else as a binary file of the wrong size.
//
// The stored normals are ignored: a triangle's orientation is its winding (the right-hand
// normal of corners 1, 2, 3 points out of the solid).
#pragma once

#include <string>

#include "sable/core/space.hpp"
#include "sable/geometry/surface_mesh.hpp"

namespace sable {

// The mesh of the STL file `path`, every corner x taken to scale * x + offset, welded and
// checked by build_surface<3> (its messages name `path`). Refuses (InputError naming the file,
// and the triangle, counted from 1, or the line) a file that cannot be read, a truncated
// binary file or one whose size disagrees with its count, an ASCII syntax error, a facet
// without exactly three vertices, a non-finite coordinate (before or after scaling), a scale
// that is not a finite number > 0 or a non-finite offset, and all that build_surface refuses.
SurfaceMesh<3> read_stl(const std::string& path, double scale, const Space<3>::Vec& offset);

// Write `mesh` as ASCII STL, each coordinate with 17 significant digits (read back, every
// double is the same bits), each facet with its unit right-hand normal. Control characters in
// `solid_name` become '_'. The file is replaced atomically; an IoError names it on failure.
void write_stl_ascii(const SurfaceMesh<3>& mesh, const std::string& path,
                     const std::string& solid_name);

// Write `mesh` as binary STL (coordinates and normals as floats: read back, a coordinate is
// the same only where it is a float; the 80-byte header does not begin with "solid"). Refuses
// (IoError) a coordinate beyond float range; replaces the file atomically.
void write_stl_binary(const SurfaceMesh<3>& mesh, const std::string& path);

}  // namespace sable
