// Micro-benchmarks of the hot pieces: the contact kernel, the neighbour build and a full DEM
// step on a dense bed. Speed is measured here, never in tests; docs/BENCHMARKS.md records the
// numbers.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "sable/cd/cd_solver.hpp"
#include "sable/contact/contact_lanes.hpp"
#include "sable/contact/registry.hpp"
#include "sable/dem/dem_solver.hpp"

namespace {

// A dense 3D lattice of touching spheres, slightly compressed, in a box of walls; with
// `shuffled`, the grains' slots in a random order (as after a long flow), else row by row.
sable::World<3> dense_bed(int n, bool shuffled = false) {
  sable::World<3> w;
  sable::Material m{"glass", 2500.0, 5e6, 0.45, 0.6, 0.5};
  const auto mi = w.materials.add(m);
  w.materials.finalize();
  const double r = 0.75e-3, s = 1.98 * r;
  std::vector<Eigen::Vector3d> x;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) x.emplace_back((i + 0.5) * s, (j + 0.5) * s, (k + 0.5) * s);
  if (shuffled) std::shuffle(x.begin(), x.end(), std::mt19937_64(12345));
  for (const auto& c : x) w.particles.add(c, r, m.density, mi, 1.0);
  for (int d = 0; d < 3; ++d)
    for (int side = 0; side < 2; ++side) {
      sable::Wall<3> wall;
      wall.point = Eigen::Vector3d::Zero();
      wall.point[d] = side == 0 ? 0.0 : n * s;
      Eigen::Vector3d normal = Eigen::Vector3d::Zero();
      normal[d] = side == 0 ? 1.0 : -1.0;
      wall.set_plane(normal);
      w.walls.push_back(wall);
    }
  w.neighbors.skin = 0.5e-3;
  w.neighbors.domain_lo = Eigen::Vector3d::Zero();
  w.neighbors.domain_hi = Eigen::Vector3d::Constant(n * s);
  w.gravity = {0, 0, -9.81};
  w.dt = 1.8e-5;
  w.reorder_every = 0;  // slots as generated; BM_*StepOrder choose their own
  return w;
}

void BM_HertzKernel(benchmark::State& state) {
  sable::ContactGeometry<3> g{{0, 0, 1}, 1e-6, {1e-3, 2e-3, -1e-2}, 0.375e-3, 2e-6};
  sable::PairParams p =
      sable::MaterialTable::mix({"a", 2500, 5e6, 0.45, 0.6, 0.5}, {"a", 2500, 5e6, 0.45, 0.6, 0.5});
  sable::ContactModel model;
  Eigen::Vector3d shear(1e-7, 0, 0);
  for (auto _ : state) {
    auto f = sable::contact_force<3, sable::HertzNormal>(g, p, model, 1e-5, shear);
    benchmark::DoNotOptimize(f);
    shear *= 0.5;
  }
}
BENCHMARK(BM_HertzKernel);

// The same law on a batch of 64 contacts in lanes (contact/contact_lanes.hpp), per copy:
// 0 baseline SSE2, 1 AVX2, 2 AVX-512 (skipped where the machine lacks it). Contacts of 1.5 mm
// grains at overlaps up to 1e-5 m and 0.01 m/s, springs restored before each batch; items =
// contacts, so the rate's inverse is the time per contact.
void BM_HertzLanes(benchmark::State& state) {
  const auto level = static_cast<sable::SimdLevel>(state.range(0));
  if (level > sable::best_simd_level()) {
    state.SkipWithError("this machine lacks that instruction set");
    return;
  }
  const sable::PairParams p =
      sable::MaterialTable::mix({"a", 2500, 5e6, 0.45, 0.6, 0.5}, {"a", 2500, 5e6, 0.45, 0.6, 0.5});
  const sable::ContactModel model;
  sable::ContactLanes lanes;
  constexpr int n = sable::ContactLanes::kWidth;
  double sx[n], sy[n], sz[n];
  for (int l = 0; l < n; ++l) {
    const double a = 0.1 * l, r = 0.75e-3, overlap = 1e-5 * (l + 1) / n;
    lanes.dx[l] = (2 * r - overlap) * std::cos(a);
    lanes.dy[l] = (2 * r - overlap) * std::sin(a);
    lanes.dz[l] = 0.0;
    lanes.dist2[l] = (2 * r - overlap) * (2 * r - overlap);
    lanes.rsum[l] = 2 * r;
    lanes.ra[l] = lanes.rb[l] = r;
    lanes.inv_mass_a[l] = lanes.inv_mass_b[l] = 1.0 / 4.4e-6;
    lanes.dvx[l] = 1e-2 * std::sin(a);
    lanes.dvy[l] = -2e-2;
    lanes.dvz[l] = 1e-2;
    lanes.wax[l] = lanes.way[l] = lanes.waz[l] = 1.0;
    lanes.wbx[l] = lanes.wby[l] = lanes.wbz[l] = -1.0;
    lanes.set_params(l, p);
    sx[l] = 0.0;
    sy[l] = 0.0;
    sz[l] = l % 2 == 0 ? 1e-7 : 1e-5;  // sticking and sliding
  }
  for (auto _ : state) {
    std::copy(sx, sx + n, lanes.sx);
    std::copy(sy, sy + n, lanes.sy);
    std::copy(sz, sz + n, lanes.sz);
    sable::contact_lanes_hertz(level, lanes, n, model, 1e-5);
    benchmark::DoNotOptimize(lanes.fx[0]);
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * n);
}
BENCHMARK(BM_HertzLanes)->Arg(0)->Arg(1)->Arg(2);

void BM_NeighborBuild(benchmark::State& state) {
  auto w = dense_bed(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    w.neighbors.build(w.particles, w.walls);
    benchmark::DoNotOptimize(w.neighbors.pairs.size());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<long>(w.particles.size()));
}
BENCHMARK(BM_NeighborBuild)->Arg(20)->Arg(30);

void BM_DemStep(benchmark::State& state) {
  auto w = dense_bed(static_cast<int>(state.range(0)));
  sable::DemSolver<3> solver(w);
  solver.initialize();
  for (auto _ : state) solver.step();
  state.SetItemsProcessed(state.iterations() * static_cast<long>(w.particles.size()));
  state.counters["grain_steps_per_s"] = benchmark::Counter(
      static_cast<double>(state.iterations()) * static_cast<double>(w.particles.size()),
      benchmark::Counter::kIsRate);
}
BENCHMARK(BM_DemStep)->Arg(20)->Arg(27);

// The grains' slot order (world/reorder.hpp): a DEM step on the dense bed of n^3 grains with
// its slots row by row (order 0), shuffled (1), or shuffled then sorted by neighbour cell at
// the first neighbour build (2). A shuffled bed is what a long flow leaves without reordering:
// every partner's data a cache miss once the bed outgrows the caches.
void BM_DemStepOrder(benchmark::State& state) {
  const int order = static_cast<int>(state.range(1));
  auto w = dense_bed(static_cast<int>(state.range(0)), order != 0);
  w.reorder_every = order == 2 ? 1000000 : 0;  // build 0 only: the steps themselves never reorder
  sable::DemSolver<3> solver(w);
  solver.initialize();
  for (auto _ : state) solver.step();
  state.counters["grain_steps_per_s"] = benchmark::Counter(
      static_cast<double>(state.iterations()) * static_cast<double>(w.particles.size()),
      benchmark::Counter::kIsRate);
}
BENCHMARK(BM_DemStepOrder)
    ->ArgsProduct({{13, 27, 50}, {0, 1, 2}})
    ->ArgNames({"n", "order"})
    ->Unit(benchmark::kMillisecond);

// The same orders for a contact-dynamics step (rigid grains, dt 1e-4 s, exact local solver).
// The bed first takes 5 steps solved to 1e-4 (at most 100 sweeps each), so that the timed
// steps start from a warm, nearly converged state; each timed step then runs exactly 10 NLGS
// sweeps (tolerance 0). Fixed sweeps near the solution measure the contact build and the
// sweeps' memory traffic: from a cold start the iterates of one sweep order take the exact
// local solver's costly sliding branch far more often than another's, and that, not the
// memory, would decide the time.
void BM_CdStepOrder(benchmark::State& state) {
  const int order = static_cast<int>(state.range(1));
  auto w = dense_bed(static_cast<int>(state.range(0)), order != 0);
  w.reorder_every = order == 2 ? 1000000 : 0;  // build 0 only
  w.dt = 1e-4;
  sable::CdSettings settings;
  settings.nlgs.local = sable::cd::LocalSolver::kExact;
  settings.nlgs.max_iterations = 100;
  sable::CdSolver<3> warm(w, settings);
  warm.initialize();
  for (int k = 0; k < 5; ++k) warm.step();
  settings.nlgs.tolerance = 0.0;
  settings.nlgs.max_iterations = 10;
  sable::CdSolver<3> solver(w, settings);
  solver.initialize();
  for (auto _ : state) solver.step();
  state.counters["grain_steps_per_s"] = benchmark::Counter(
      static_cast<double>(state.iterations()) * static_cast<double>(w.particles.size()),
      benchmark::Counter::kIsRate);
  state.counters["contacts"] = static_cast<double>(w.neighbors.pairs.size());
}
BENCHMARK(BM_CdStepOrder)
    ->ArgsProduct({{13, 27}, {0, 1, 2}})
    ->ArgNames({"n", "order"})
    ->Unit(benchmark::kMillisecond);

}  // namespace
