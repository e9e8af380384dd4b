// Micro-benchmark of the contact-dynamics core: one NLGS sweep on Siconos' Capsules-i122-1617
// problem (296 contacts, shared/data/fc3d), per local solver. Reported: time per contact per
// sweep. The data directory is found beside the repository (from this file's path) or in
// $SABLE_FC3D_DATA; without it the benchmark is skipped.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "sable/cd/fc_problem.hpp"

namespace {

std::filesystem::path capsules_file() {
  if (const char* env = std::getenv("SABLE_FC3D_DATA"))
    return std::filesystem::path(env) / "Capsules-i122-1617.dat";
  return std::filesystem::path(__FILE__).parent_path() / ".." / ".." / ".." / "shared" / "data" /
         "fc3d" / "Capsules-i122-1617.dat";
}

// range(0): 0 bi-potential, 1 exact local solver. The problem is first brought near its
// solution (30 sweeps, the regime where NLGS spends its time), then each benchmark iteration is
// one forward sweep continuing from there.
void BM_NlgsSweepCapsules(benchmark::State& state) {
  const auto file = capsules_file();
  if (!std::filesystem::exists(file)) {
    state.SkipWithError(("missing " + file.string()).c_str());
    return;
  }
  sable::cd::MatrixProblem<3> p = sable::cd::read_fc3d(file.string());
  sable::cd::NlgsSettings s;
  s.local =
      state.range(0) == 0 ? sable::cd::LocalSolver::kBipotential : sable::cd::LocalSolver::kExact;
  std::vector<std::size_t> order(p.size());
  sable::Rng rng(1);
  sable::cd::fill_sweep_order(order, s.order, 0, rng);
  for (int k = 0; k < 30; ++k) sable::cd::nlgs_sweep<3>(p, order, s, {});
  for (auto _ : state) {
    const auto st = sable::cd::nlgs_sweep<3>(p, order, s, {});
    benchmark::DoNotOptimize(st);
  }
  const auto n = static_cast<double>(p.size());
  state.counters["per_contact"] = benchmark::Counter(
      n, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.SetLabel(std::string(sable::cd::to_string(s.local)));
}
BENCHMARK(BM_NlgsSweepCapsules)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

}  // namespace
