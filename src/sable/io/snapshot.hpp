// Snapshots: the complete dynamic state of a run in one HDF5 file, for bit-identical resume.
//
// A snapshot holds every particle array, the id registry, the walls' moving state, the
// neighbour lists with their contact history and last forces, the clock, the random generator,
// where the run is in its stage sequence, and the scenario text it was started from. Resuming
// is: build the World from the scenario (materials, walls, contact model), then load_snapshot
// overwrites the dynamic state; the solver is NOT re-initialized, and stepping continues
// exactly as the uninterrupted run would have, bit for bit.
//
// Layout (version 1), dimension D, N grains, W walls, P pairs, Q wall pairs:
//   /                     attributes format = "sable-snapshot", version, dimension, step, time,
//                         dt, stage, stage_step, state_hash
//   /scenario             string: the scenario text
//   /scenario_path        string, optional: the scenario file's absolute path (its folder is
//                         where relative file names in it start)
//   /rng_state            [4] uint64
//   /particles/{x,v,f}    [N x D] double        /particles/{w,t}  [N x 1] (2D) or [N x 3]
//   /particles/q          [N x 1] angle (2D) or [N x 4] quaternion w, x, y, z (3D)
//   /particles/{radius,inv_mass,inv_inertia,mass} [N] double
//   /particles/{material [N] uint16, flags [N] uint8, shape [N] uint8, id [N x 2] uint32}
//   /particles/ids/{slots,generations,free_list}   [*] uint32 (IdRegistry raw state)
//   /walls/names [W] string, /walls/{point,velocity,force,pivot} [W x D] double,
//   /walls/orientation [W x 1] angle (2D) or [W x 4] quaternion, /walls/{spin,torque} [W x 1]
//   (2D) or [W x 3], /walls/pivoted [W] uint32 (optional as a group: older files)
//   /neighbors            attributes skin, builds; domain_lo, domain_hi [D]; x_ref, wall_ref
//   /neighbors/pairs/{i,j [P] uint32, shear,force [P x D]}
//   /neighbors/wall_pairs/{i,wall [Q] uint32, shear,force [Q x D]}, element, feature [Q]
//   uint32 (optional: 0 without meshes); /neighbors/wall_ref_turn as orientations (optional)
//   /neighbors/wall_reach [W] double (optional: the whole skin for every wall)
// Writes go to a temporary file renamed over the target, so an interrupted write never
// replaces a good snapshot with a broken one.
#pragma once

#include <cstdint>
#include <string>

#include "sable/world/snapshot_part.hpp"
#include "sable/world/state_hash.hpp"
#include "sable/world/world.hpp"

namespace sable {

inline constexpr const char* kSnapshotFormat = "sable-snapshot";
inline constexpr std::uint32_t kSnapshotVersion = 1;

// Where a run is in its scenario's sequence of stages.
struct RunPosition {
  std::uint32_t stage = 0;
  std::uint64_t stage_step = 0;
  friend bool operator==(const RunPosition&, const RunPosition&) = default;
};

// `scenario_path`: where the scenario file was (absolute), stored beside its text so that the
// files it names by relative paths (meshes, grain data) are found from its folder when the
// snapshot is analysed or verified elsewhere ("" stores none).
template <int D>
void save_snapshot(const World<D>& world, const RunPosition& pos, const std::string& scenario_text,
                   const std::string& path, const std::string& scenario_path = "");

// A decomposed run's snapshot (collective: every process calls it with its share): each
// process writes its rows of the file `part.temp_path`, which then holds what save_snapshot()
// of the gathered World would write, but the state hash. `path` is the snapshot's final name
// (for messages). Every process must then have returned before process 0 seals the file.
template <int D>
void save_snapshot_part(const SnapshotPart<D>& part, const RunPosition& pos,
                        const std::string& scenario_text, const std::string& path,
                        const std::string& scenario_path = "");
// Process 0, after save_snapshot_part() on every process: the state hash, computed from the
// file a block of rows at a time (io/snapshot_hash.hpp; `like` is this process's World, for
// what every process holds alike), then `temp` renamed over `path`. On failure `temp` is
// removed and `path` left as it was.
template <int D>
void seal_snapshot(const std::string& temp, const std::string& path, const World<D>& like);

// Overwrite the dynamic state of `world` (already built from the snapshot's scenario) with the
// snapshot's. Throws InputError naming the file and the offending dataset or attribute if the
// file is missing, not HDF5, not a Sable snapshot, of the other dimension, damaged, or does
// not fit the world (wall count or names, material indices). On error `world` is unchanged.
template <int D>
RunPosition load_snapshot(const std::string& path, World<D>& world,
                          std::string* scenario_text = nullptr);

// The header of a snapshot, for `sable info` and for choosing the dimension before loading.
struct SnapshotInfo {
  int dimension = 0;
  std::uint64_t step = 0;
  double time = 0.0, dt = 0.0;
  std::size_t grains = 0, pairs = 0, wall_pairs = 0, walls = 0;
  RunPosition pos;
  std::uint64_t state_hash = 0;
  std::string scenario_text;
  std::string scenario_path;  // "" when the file stores none
};

SnapshotInfo read_snapshot_info(const std::string& path);

}  // namespace sable
