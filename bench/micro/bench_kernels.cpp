// Micro-benchmarks of the hot pieces: the contact kernel, the neighbour build and a full DEM
// step on a dense bed. Speed is measured here, never in tests (docs/BENCHMARKS.md).
#include <benchmark/benchmark.h>

#include "sable/contact/contact_model.hpp"
#include "sable/dem/dem_solver.hpp"

namespace {

// A dense 3D lattice of touching spheres, slightly compressed, in a box of walls.
sable::World<3> dense_bed(int n) {
  sable::World<3> w;
  sable::Material m{"glass", 2500.0, 5e6, 0.45, 0.6, 0.5};
  const auto mi = w.materials.add(m);
  w.materials.finalize();
  const double r = 0.75e-3, s = 1.98 * r;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        w.particles.add({(i + 0.5) * s, (j + 0.5) * s, (k + 0.5) * s}, r, m.density, mi, 1.0);
  for (int d = 0; d < 3; ++d)
    for (int side = 0; side < 2; ++side) {
      sable::Wall<3> wall;
      wall.point = Eigen::Vector3d::Zero();
      wall.point[d] = side == 0 ? 0.0 : n * s;
      wall.normal = Eigen::Vector3d::Zero();
      wall.normal[d] = side == 0 ? 1.0 : -1.0;
      w.walls.push_back(wall);
    }
  w.neighbors.skin = 0.5e-3;
  w.neighbors.domain_lo = Eigen::Vector3d::Zero();
  w.neighbors.domain_hi = Eigen::Vector3d::Constant(n * s);
  w.gravity = {0, 0, -9.81};
  w.dt = 1.8e-5;
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

}  // namespace
