// Fuzz target: a scenario file's bytes through the parser, then what `sable check` and the
// start of `sable run` do with a scenario that parses: the model, and when the scenario is
// small, its grains and the solver's first neighbour lists.
//
// Bad input must end in sable::InputError; any other exception, a crash or a sanitizer report
// is a finding. Grains are generated only for scenarios that ask for few: the parser bounds a
// scenario at kMaxGrains (10^8), which is about memory, not about the few milliseconds an
// input may take here.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "sable/core/error.hpp"
#include "sable/scenario/build.hpp"
#include "sable/scenario/config.hpp"
#include "sable/world/world.hpp"

namespace {

// Grains generated at most, and random insertion's tries at most (count x max_attempts).
constexpr std::uint64_t kSmallGrains = 2000;
constexpr std::uint64_t kSmallTries = 1'000'000;

bool small(const sable::ScenarioConfig& cfg) {
  std::uint64_t grains = 0, tries = 0;
  for (const auto& g : cfg.grains) {
    // A data file, or a shape file, names any path on this machine: not this target's
    // business.
    if (g.generator == "file" || !g.shape.file.empty()) return false;
    grains += g.count + g.positions.size();
    if (g.generator == "random") tries += g.count * g.max_attempts;
  }
  return grains <= kSmallGrains && tries <= kSmallTries;
}

template <int D>
void build(const sable::ScenarioConfig& cfg) {
  sable::World<D> world;
  sable::build_model(cfg, world);
  if (!small(cfg)) return;
  sable::build_grains(cfg, world);
  sable::make_solver(cfg, world)->initialize();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const sable::ScenarioConfig cfg = sable::parse_scenario(text, "fuzz.toml");
    if (cfg.sim.dimension == 2)
      build<2>(cfg);
    else
      build<3>(cfg);
  } catch (const sable::InputError& e) {
    // SABLE_FUZZ_VERBOSE=1: say why each input was refused (to check a corpus reaches deep).
    if (std::getenv("SABLE_FUZZ_VERBOSE") != nullptr)
      std::fprintf(stderr, "refused: %s\n", e.what());
  }
  return 0;
}
