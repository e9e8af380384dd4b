#include "sable/scenario/verify.hpp"

#include <fmt/format.h>

#include "sable/core/error.hpp"
#include "sable/io/snapshot.hpp"
#include "sable/scenario/build.hpp"
#include "sable/scenario/config.hpp"

namespace sable {

namespace {

template <int D>
void load_whole(const std::string& path, const ScenarioConfig& cfg) {
  World<D> w;
  build_model(cfg, w);
  load_snapshot(path, w);
}

}  // namespace

SnapshotIntegrity verify_snapshot(const std::string& path) {
  const SnapshotInfo info = read_snapshot_info(path);
  SnapshotIntegrity out;
  try {
    const ScenarioConfig cfg = parse_stored_scenario(info.scenario_text, path, info.scenario_path);
    if (cfg.sim.dimension != info.dimension)
      throw InputError(fmt::format("the snapshot is {}D, but the scenario stored in it is {}D",
                                   info.dimension, cfg.sim.dimension));
    if (info.dimension == 2)
      load_whole<2>(path, cfg);
    else
      load_whole<3>(path, cfg);
    out.verified = true;
  } catch (const InputError& e) {
    out.problem = e.what();
  }
  return out;
}

}  // namespace sable
