// What the machine's caches and memory give a loop over the grains, on one thread and on two:
// the arithmetic and the arrays of the DEM step's opening loop (dem/grain_loops_impl.hpp,
// kick_and_drift: half kick, drift, the largest displacements from the two lists' reference
// positions), on arrays of its own, hot in the caches from the pass before. It moves the
// bytes the real loop moves and does nothing else. Two threads near twice one here mean the
// memory system does not stop a grain loop of the pour bed's size from scaling; `swap` hands
// each thread the other's half every other pass, as when two loops cut the grains
// differently, to see what fetching lines the other core wrote last costs.
#include <benchmark/benchmark.h>
#include <omp.h>

#include <Eigen/Core>
#include <algorithm>
#include <cstddef>
#include <vector>

namespace {

struct Grains {
  std::vector<Eigen::Vector3d> x, v, w, f, t, outer, inner;
  std::vector<double> inv_mass, inv_inertia;
  explicit Grains(std::size_t n)
      : x(n), v(n), w(n), f(n), t(n), outer(n), inner(n), inv_mass(n), inv_inertia(n) {
    for (std::size_t k = 0; k < n; ++k) {
      const double s = 1e-3 * static_cast<double>(k % 977);
      x[k] = {s, 2 * s, 3 * s};
      outer[k] = x[k];
      inner[k] = x[k];
      v[k] = {1e-3, 0, -1e-3};
      w[k] = {0, 1e-2, 0};
      f[k] = {0, 0, 1e-6};
      t[k] = {1e-9, 0, 0};
      inv_mass[k] = 1.0 / 4.4e-6;
      inv_inertia[k] = 1.0 / 1e-12;
    }
  }
};

// Bytes the loop moves per grain: read inv_mass, f, inv_inertia, t, outer, inner (8 + 24 + 8
// + 24 + 24 + 24); read and write back v, w, x (3 x 2 x 24).
constexpr double kBytesPerGrain = 112.0 + 144.0;

// range(0): grains; range(1): threads; range(2): swap (1) or not (0). The 20,000 grains of the pour
// bed hold 5 MB of these arrays (the step's contacts hold more); 400,000 hold 100 MB, past any
// cache.
void BM_GrainStream(benchmark::State& state) {
  const auto n = static_cast<std::ptrdiff_t>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  Grains g(static_cast<std::size_t>(n));
  const Eigen::Vector3d gravity(0, 0, -9.81);
  const double h = 0.9e-5, dt = 1.8e-5;
  const bool swap = state.range(2) != 0;
  long pass = 0;
  // The velocities grow by about 1e-4 m/s per pass: after the benchmark's passes every value
  // is still a finite, normal double, so no pass runs slower on denormals.
  for (auto _ : state) {
    double outer2 = 0.0, inner2 = 0.0;
#pragma omp parallel num_threads(threads) reduction(max : outer2, inner2)
    {
      const int team = omp_get_num_threads();
      int b = omp_get_thread_num();
      if (swap && (pass & 1)) b = team - 1 - b;
      const std::ptrdiff_t k0 = n * b / team, k1 = n * (b + 1) / team;
      // Raw pointers, as the real loop's GrainPass holds them (in registers, not reloaded).
      Eigen::Vector3d *x = g.x.data(), *v = g.v.data(), *w = g.w.data();
      const Eigen::Vector3d *f = g.f.data(), *t = g.t.data();
      const Eigen::Vector3d *outer = g.outer.data(), *inner = g.inner.data();
      const double *inv_mass = g.inv_mass.data(), *inv_inertia = g.inv_inertia.data();
      double o2 = 0.0, n2 = 0.0;
      for (std::ptrdiff_t k = k0; k < k1; ++k) {
        if (inv_mass[k] != 0.0) {
          v[k] += h * (f[k] * inv_mass[k] + gravity);
          w[k] += h * inv_inertia[k] * t[k];
          x[k] += dt * v[k];
        }
        o2 = std::max(o2, (x[k] - outer[k]).squaredNorm());
        n2 = std::max(n2, (x[k] - inner[k]).squaredNorm());
      }
      outer2 = std::max(outer2, o2);
      inner2 = std::max(inner2, n2);
    }
    ++pass;
    benchmark::DoNotOptimize(outer2);
    benchmark::DoNotOptimize(inner2);
  }
  const double grains = static_cast<double>(state.iterations()) * static_cast<double>(n);
  state.counters["grain_steps_per_s"] = benchmark::Counter(grains, benchmark::Counter::kIsRate);
  state.counters["bytes_per_s"] =
      benchmark::Counter(grains * kBytesPerGrain, benchmark::Counter::kIsRate);
}
// Swapping needs two threads: one thread runs swap = 0 only.
BENCHMARK(BM_GrainStream)
    ->Args({20000, 1, 0})
    ->Args({400000, 1, 0})
    ->ArgsProduct({{20000, 400000}, {2}, {0, 1}})
    ->ArgNames({"grains", "threads", "swap"})
    ->UseRealTime()
    ->Unit(benchmark::kMicrosecond);

}  // namespace
