// What a run does with the output folder it is given (docs/reliability.md, "Output folders").
//
// A run owns these entries of its folder: series.csv, grains.pvd, contacts.pvd, walls.pvd,
// polyhedra.pvd, vtk/, snapshots/ and xdmf/ (the snapshots' XDMF sidecars). Nothing else in
// the folder is read, changed or removed.
// - A fresh run refuses a folder that already holds any of them (another run's snapshots
//   left beside this run's would be taken for its own), unless `overwrite`, which deletes
//   exactly those entries first.
// - A resumed run continues the folder's series (series.csv and the .pvd files keep their
//   entries up to the resume point). Snapshots (with their sidecars) and VTK frames of
//   steps after the resume point belong to a continuation this run replaces: it refuses them,
//   unless `overwrite`, which deletes exactly those files. The snapshot being resumed is never
//   deleted.
// - Either way, temporaries of an interrupted atomic write (`NAME.tmp-PID`, io/atomic_file.hpp)
//   whose process no longer runs are deleted: they are never complete files.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

namespace sable {

struct OutputFolderRequest {
  std::string dir;
  // The step of the snapshot being resumed (nullopt: a fresh run) and its path.
  std::optional<std::uint64_t> resume_step;
  std::string resume_file;
  bool overwrite = false;
};

// Check and tidy `req.dir` as above; `log` receives one line per action taken. Throws
// InputError (refusal: names the folder, what is in it, and the two ways out) or IoError.
void prepare_output_folder(const OutputFolderRequest& req,
                           const std::function<void(const std::string&)>& log);

// The step a snapshot or VTK frame file name carries (`step_0000000100.h5`,
// `crash_step_...`, `interrupted_step_...`, `grains_0000000100.vtp` and the other frames:
// contacts_, walls_, polyhedra_), or nullopt.
std::optional<std::uint64_t> step_in_file_name(const std::string& name);

}  // namespace sable
