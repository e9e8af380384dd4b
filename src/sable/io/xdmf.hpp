// XDMF sidecars: a small XML file beside a snapshot that tells ParaView (its XDMF readers) and
// VisIt how to read the grains straight out of the HDF5 file, without Sable: the positions
// as the geometry of a poly-vertex grid, and the per-grain datasets as point attributes.
// Nothing is copied: every array is a reference `FILE.h5:/particles/...` to the snapshot's
// own datasets (docs/snapshot.md lays them out), so the sidecar is a few kilobytes whatever
// the run's size. The snapshot is named by its path relative to the sidecar's folder (a run
// writes OUT/xdmf/NAME.xmf naming ../snapshots/NAME.h5: a folder of snapshots holds
// snapshots only): the output folder can be moved whole.
#pragma once

#include <cstddef>
#include <string>

namespace sable {

struct XdmfSnapshot {
  std::string h5_name;  // the snapshot's path, relative to the sidecar's folder
  int dimension = 3;
  std::size_t grains = 0;
  double time = 0.0;
};

// The sidecar's text: one uniform grid "grains" at `time`; geometry XYZ (3D) or XY (2D) from
// /particles/x; attributes id (the stable id's index, column 0 of /particles/id), radius,
// mass, material, flags (bit 0: fixed), velocity, angular_velocity (a vector in 3D, a scalar
// in 2D), force.
std::string xdmf_text(const XdmfSnapshot& s);

// Write `xdmf_text(s)` to `path` atomically.
void write_xdmf(const XdmfSnapshot& s, const std::string& path);

}  // namespace sable
