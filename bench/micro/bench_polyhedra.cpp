// Micro-benchmarks of polyhedral grains: the narrow phase of one pair, and a step of a heap
// of random polyhedra by each solver. What a polyhedral sample's cost per step and per
// contact is made of (docs/BENCHMARKS.md, "Polyhedral grains").
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <random>
#include <vector>

#include "sable/cd/cd_solver.hpp"
#include "sable/contact/registry.hpp"
#include "sable/dem/dem_solver.hpp"
#include "sable/geometry/polyhedron_contact.hpp"
#include "sable/world/polyhedral_grains.hpp"

namespace {

using Vec = Eigen::Vector3d;

// Hulls of `corners` random points on a sphere of radius r about `centre`.
std::vector<Vec> random_corners(std::mt19937_64& gen, const Vec& centre, double r, int corners) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Vec> points;
  for (int c = 0; c < corners; ++c) {
    Vec d;
    for (int i = 0; i < 3; ++i) d[i] = u(gen);
    points.push_back(centre + r * d.normalized());
  }
  return points;
}

// range(0): corners per grain. Pairs of random hulls at random poses whose bounding spheres
// overlap (the candidates a step tests); time per pair.
void BM_PolyhedronPair(benchmark::State& state) {
  const int corners = static_cast<int>(state.range(0));
  std::mt19937_64 gen(1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  sable::GrainShapes shapes;
  struct Pose {
    Vec x;
    Eigen::Quaterniond q;
  };
  std::vector<Pose> poses;
  for (int k = 0; k < 256; ++k) {
    const sable::ShapePlacement s = shapes.add(random_corners(gen, Vec::Zero(), 1.0, corners));
    Eigen::Quaterniond q(u(gen), u(gen), u(gen), u(gen));
    Vec x;
    for (int i = 0; i < 3; ++i) x[i] = 1.2 * u(gen);
    poses.push_back({x, q.normalized() * s.frame});
  }
  std::size_t a = 0;
  for (auto _ : state) {
    const std::size_t b = (a + 1) % poses.size();
    const auto c = sable::polyhedron_contact(shapes[a].solid, poses[a].x, poses[a].q,
                                             shapes[b].solid, poses[b].x, poses[b].q, 0.01);
    benchmark::DoNotOptimize(c);
    a = b;
  }
}
BENCHMARK(BM_PolyhedronPair)->Arg(8)->Arg(14)->Arg(32);

// A heap of 12 x 12 x 8 random polyhedra (10 corners) falling on a floor, after 100 steps;
// range(0): 0 contact dynamics (tolerance 1e-4), 1 DEM (linear law). Time per step.
void BM_PolyhedraStep(benchmark::State& state) {
  const bool dem = state.range(0) == 1;
  sable::World<3> w;
  w.materials.add({"grain", 2500.0, 1e7, 0.3, 0.3, 0.4, 0.0});
  w.materials.finalize();
  w.model.normal = sable::NormalLaws::id<sable::LinearNormal>();
  w.model.kn = 1e4;
  w.model.kt = 8e3;
  w.neighbors.skin = 1e-3;
  w.neighbors.domain_lo.setConstant(-0.2);
  w.neighbors.domain_hi.setConstant(0.2);
  w.gravity = Vec(0, 0, -9.81);
  w.dt = dem ? 2e-5 : 2e-4;
  sable::Wall<3> floor;
  floor.set_plane(Vec::UnitZ());
  w.walls.push_back(floor);
  std::mt19937_64 gen(3);
  const double r = 0.005, pitch = 2.0 * r + 1e-4;
  for (int k = 0; k < 12 * 12 * 8; ++k) {
    const Vec centre(pitch * (k % 12 - 6), pitch * (k / 12 % 12 - 6),
                     r + pitch * static_cast<double>(k / 144));
    sable::add_polyhedral_grain(w, random_corners(gen, centre, r, 10), 2500.0, 0);
  }
  std::unique_ptr<sable::Solver> s;
  if (dem)
    s = std::make_unique<sable::DemSolver<3>>(w);
  else
    s = std::make_unique<sable::CdSolver<3>>(w, sable::CdSettings{});
  s->initialize();
  for (int k = 0; k < 100; ++k) s->step();
  for (auto _ : state) s->step();
  state.counters["touching"] = static_cast<double>(s->diagnostics().touching);
  state.SetLabel(dem ? "dem" : "cd");
}
BENCHMARK(BM_PolyhedraStep)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace
