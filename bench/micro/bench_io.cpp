// One VTK frame (grains, contacts, walls) of a real packing, in each encoding of
// io/vtk_xml.hpp: the time to write it and its size. The packing is a snapshot named by
// SABLE_BENCH_SNAPSHOT (bench/vtk_frame.sh makes the 20,000-grain pour bed's); without it
// the benchmark is skipped. The files go to $TMPDIR (or /tmp) and are rewritten each pass,
// as a run rewrites its frames: the time includes the page cache's writes, not the disk's.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

#include "sable/io/vtk.hpp"
#include "sable/scenario/snapshot_sample.hpp"

namespace {

namespace fs = std::filesystem;

// The snapshot's world, loaded once for every benchmark (nullptr without the variable).
const sable::World<3>* bench_world() {
  static const std::unique_ptr<sable::World<3>> world = [] {
    const char* path = std::getenv("SABLE_BENCH_SNAPSHOT");
    if (path == nullptr) return std::unique_ptr<sable::World<3>>();
    auto w = std::make_unique<sable::World<3>>();
    sable::load_world(path, *w);
    return w;
  }();
  return world.get();
}

// range(0): the encoding (0 binary, 1 zlib, 2 ascii).
void BM_VtkFrame(benchmark::State& state) {
  const sable::World<3>* w = bench_world();
  if (w == nullptr) {
    state.SkipWithError("set SABLE_BENCH_SNAPSHOT to a 3D snapshot (bench/vtk_frame.sh)");
    return;
  }
  const auto enc = static_cast<sable::VtkEncoding>(state.range(0));
  const char* tmp = std::getenv("TMPDIR");
  const fs::path dir = fs::path(tmp ? tmp : "/tmp") / "sable_bench_vtk";
  fs::create_directories(dir);
  const std::string g = (dir / "grains.vtp").string(), c = (dir / "contacts.vtp").string(),
                    wl = (dir / "walls.vtp").string();
  for (auto _ : state) {
    sable::write_grains_vtp(*w, g, enc);
    sable::write_contacts_vtp(*w, c, enc);
    sable::write_walls_vtp(*w, wl, enc);
  }
  state.SetLabel(std::string(sable::vtk_encoding_name(enc)));
  state.counters["grains"] = static_cast<double>(w->particles.size());
  state.counters["grains_MB"] = static_cast<double>(fs::file_size(g)) / 1e6;
  state.counters["contacts_MB"] = static_cast<double>(fs::file_size(c)) / 1e6;
  fs::remove_all(dir);
}

}  // namespace

BENCHMARK(BM_VtkFrame)->DenseRange(0, 2)->Unit(benchmark::kMillisecond)->UseRealTime();
