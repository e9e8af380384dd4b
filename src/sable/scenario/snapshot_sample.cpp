#include "sable/scenario/snapshot_sample.hpp"

#include <fmt/format.h>

#include "sable/core/error.hpp"
#include "sable/io/snapshot.hpp"
#include "sable/scenario/build.hpp"
#include "sable/scenario/config.hpp"
#include "sable/world/world.hpp"

namespace sable {

template <int D>
Sample<D> load_sample(const std::string& path) {
  const SnapshotInfo info = read_snapshot_info(path);
  if (info.dimension != D)
    throw InputError(fmt::format("{}: a {}D snapshot, but a {}D analysis was asked for", path,
                                 info.dimension, D));
  // The scenario text inside the snapshot gives materials, walls and the contact law; the
  // grains themselves come from the snapshot, so generators are not re-run.
  ScenarioConfig cfg;
  try {
    cfg = parse_stored_scenario(info.scenario_text, path, info.scenario_path);
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}", path, e.what()));
  }
  World<D> w;
  build_model(cfg, w);
  load_snapshot(path, w);
  Sample<D> s = make_sample(
      w, cfg.sim.solver == "cd" ? ForceGeometry::kContactDynamics : ForceGeometry::kSoft);
  s.source = path;
  return s;
}

SampleLoaders snapshot_loaders() {
  return {load_sample<2>, load_sample<3>};
}

template Sample<2> load_sample(const std::string&);
template Sample<3> load_sample(const std::string&);

}  // namespace sable
