#include "sable/scenario/snapshot_sample.hpp"

#include <fmt/format.h>

#include "sable/core/error.hpp"
#include "sable/io/snapshot.hpp"
#include "sable/scenario/build.hpp"
#include "sable/scenario/config.hpp"
#include "sable/world/world.hpp"

namespace sable {

ScenarioConfig snapshot_scenario(const std::string& path) {
  const SnapshotInfo info = read_snapshot_info(path);
  try {
    return parse_stored_scenario(info.scenario_text, path, info.scenario_path);
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}", path, e.what()));
  }
}

template <int D>
ScenarioConfig load_world(const std::string& path, World<D>& w, RunPosition* pos) {
  const int dimension = read_snapshot_info(path).dimension;
  if (dimension != D)
    throw InputError(
        fmt::format("{}: a {}D snapshot, where a {}D one was expected", path, dimension, D));
  // The scenario text inside the snapshot gives materials, walls and the contact law; the
  // grains themselves come from the snapshot, so generators are not re-run.
  ScenarioConfig cfg = snapshot_scenario(path);
  build_model(cfg, w);
  const RunPosition p = load_snapshot(path, w);
  if (pos) *pos = p;
  return cfg;
}

template <int D>
Sample<D> load_sample(const std::string& path) {
  World<D> w;
  const ScenarioConfig cfg = load_world(path, w);
  const ForceGeometry geometry =
      cfg.sim.solver == "cd" ? ForceGeometry::kContactDynamics : ForceGeometry::kSoft;
  Sample<D> s;
  try {
    s = make_sample(w, geometry);
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}", path, e.what()));  // make_sample knows no file
  }
  s.source = path;
  return s;
}

SampleLoaders snapshot_loaders() {
  return {load_sample<2>, load_sample<3>};
}

template ScenarioConfig load_world(const std::string&, World<2>&, RunPosition*);
template ScenarioConfig load_world(const std::string&, World<3>&, RunPosition*);
template Sample<2> load_sample(const std::string&);
template Sample<3> load_sample(const std::string&);

}  // namespace sable
