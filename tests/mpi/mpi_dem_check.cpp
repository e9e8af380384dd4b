// The promise of the MPI decomposition (world/domain.hpp): the same bits as a serial run for
// any number of processes. Run as
// `mpirun -np N sable_mpi_dem_check SCENARIO STEPS [BIAS [STAGE [SNAPSHOT [RECUT]]]]`:
// every process builds the scenario's world; process 0 also steps a serial copy with the
// plain DemSolver; the decomposed run steps STEPS steps of its first stage's physics (no
// stage rules; the wall velocities and rotations of stage STAGE, counted from 0, default 0),
// then the whole state is gathered on process 0 and both state hashes are compared. With
// SNAPSHOT (`-`: none), both runs resume from it (every process loads it whole, then keeps its
// share). BIAS (default 1) makes every cut lopsided (mpi/rcb.hpp). RECUT > 0 forces a list
// rebuild, and so new cuts, every RECUT steps in both runs, the bias swapped with 2 - BIAS at
// each, so that the cuts swing and grains migrate back and forth. Exit 0 when the hashes
// are equal (on every process), 1 when not, 2 on bad arguments.
#include <mpi.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "sable/dem/dem_solver.hpp"
#include "sable/io/snapshot.hpp"
#include "sable/mpi/mpi_domain.hpp"
#include "sable/scenario/build.hpp"
#include "sable/scenario/config.hpp"
#include "sable/world/state_hash.hpp"

namespace {

// Where two states differ (the first grain by slot, the lists' sizes, the walls' forces): a
// failure's first clue.
template <int D>
void compare(const sable::World<D>& a, const sable::World<D>& b) {
  const auto& p = a.particles;
  const auto& q = b.particles;
  if (p.size() != q.size()) {
    std::printf("  grains: %zu against %zu\n", p.size(), q.size());
    return;
  }
  std::size_t differ = 0;
  for (std::size_t k = 0; k < p.size(); ++k) {
    if (p.id[k] == q.id[k] && p.x[k] == q.x[k] && p.v[k] == q.v[k] && p.f[k] == q.f[k] &&
        p.omega[k] == q.omega[k] && p.t[k] == q.t[k] && p.order_key[k] == q.order_key[k])
      continue;
    if (differ == 0) {
      for (const sable::World<D>* w : {&a, &b}) {
        std::printf("  its entries:");
        const auto& pl = w->neighbors.pairs;
        for (std::size_t e = 0; e < pl.size(); ++e)
          if ((pl.i[e] == k || pl.j[e] == k) && pl.force[e].squaredNorm() > 0)
            std::printf(" %u-%u", w->particles.id[pl.i[e]].index, w->particles.id[pl.j[e]].index);
        const auto& wl = w->neighbors.wall_pairs;
        for (std::size_t e = 0; e < wl.size(); ++e)
          if (wl.i[e] == k && wl.force[e].squaredNorm() > 0)
            std::printf(" w%u/%u", wl.wall[e], wl.element[e]);
        std::printf("\n");
      }
    }
    if (differ++ == 0)
      std::printf(
          "  first grain apart: slot %zu, ids %u/%u, |dx| %.3g, |df| %.3g, keys %llu/%llu\n", k,
          p.id[k].index, q.id[k].index, (p.x[k] - q.x[k]).norm(), (p.f[k] - q.f[k]).norm(),
          static_cast<unsigned long long>(p.order_key[k]),
          static_cast<unsigned long long>(q.order_key[k]));
  }
  std::size_t shear = 0;
  if (a.neighbors.pairs.size() == b.neighbors.pairs.size())
    for (std::size_t e = 0; e < a.neighbors.pairs.size(); ++e)
      if (a.neighbors.pairs.shear[e] != b.neighbors.pairs.shear[e] && shear++ == 0)
        std::printf("  first pair history apart: %u-%u: %.17g %.17g against %.17g %.17g\n",
                    p.id[a.neighbors.pairs.i[e]].index, p.id[a.neighbors.pairs.j[e]].index,
                    a.neighbors.pairs.shear[e][0], a.neighbors.pairs.shear[e][1],
                    b.neighbors.pairs.shear[e][0], b.neighbors.pairs.shear[e][1]);
  std::printf("  %zu pair histories apart\n", shear);
  std::printf("  %zu grains apart; pairs %zu/%zu, wall pairs %zu/%zu\n", differ,
              a.neighbors.pairs.size(), b.neighbors.pairs.size(), a.neighbors.wall_pairs.size(),
              b.neighbors.wall_pairs.size());
  for (std::size_t w = 0; w < a.walls.size(); ++w)
    if (a.walls[w].force != b.walls[w].force) std::printf("  wall %zu's force differs\n", w);
  // The rest of what state_hash() covers, part by part.
  const auto& na = a.neighbors;
  const auto& nb = b.neighbors;
  const std::pair<const char*, bool> parts[] = {
      {"id slots", p.ids.slots() == q.ids.slots()},
      {"id generations", p.ids.generations() == q.ids.generations()},
      {"id free list", p.ids.free_list() == q.ids.free_list()},
      {"pair forces", na.pairs.force == nb.pairs.force},
      {"wall-pair grains", na.wall_pairs.i == nb.wall_pairs.i},
      {"wall-pair histories", na.wall_pairs.shear == nb.wall_pairs.shear},
      {"wall-pair forces", na.wall_pairs.force == nb.wall_pairs.force},
      {"x_ref", na.x_ref == nb.x_ref},
      {"wall_ref", na.wall_ref == nb.wall_ref},
      {"skin and domain",
       na.skin == nb.skin && na.domain_lo == nb.domain_lo && na.domain_hi == nb.domain_hi},
      {"clock and generator",
       a.time == b.time && a.step == b.step && a.dt == b.dt && a.rng.state() == b.rng.state()}};
  for (const auto& [name, same] : parts)
    if (!same) std::printf("  %s differ\n", name);
}

struct Options {
  int steps = 0;
  double bias = 1.0;
  std::size_t stage = 0;
  const char* snapshot = nullptr;
  int recut = 0;
};

// A rebuild forced before step s (RECUT): the same steps in both runs.
bool forced(const Options& o, int s) {
  return o.recut > 0 && s > 0 && s % o.recut == 0;
}

template <int D>
int check(const sable::ScenarioConfig& cfg, const Options& o, int rank) {
  const int steps = o.steps;
  const double bias = o.bias;
  const std::size_t stage = o.stage;
  const char* snapshot = o.snapshot;
  sable::World<D> world;
  sable::build_model(cfg, world);
  if (snapshot)
    sable::load_snapshot(snapshot, world);
  else
    sable::build_grains(cfg, world);
  if (stage < cfg.stages.size()) {  // the stage's wall motions, as the runner sets them
    for (const auto& [name, vel] : cfg.stages[stage].wall_velocity)
      for (std::size_t k : sable::walls_named(world, name))
        world.walls[k].velocity = sable::Space<D>::from_array(vel);
    for (const auto& [name, rot] : cfg.stages[stage].wall_rotation)
      for (auto& wall : world.walls)
        if (wall.name == name)
          wall.set_rotation(sable::Space<D>::from_array(rot.point),
                            sable::Space<D>::from_array(rot.axis), rot.rate);
  }
  std::uint64_t serial = 0;
  sable::World<D> ref;
  if (rank == 0) {
    ref = world;
    sable::DemSolver<D> solver(ref);
    if (!snapshot) solver.initialize();
    for (int s = 0; s < steps; ++s) {
      if (forced(o, s)) ref.neighbors.x_ref.clear();
      solver.step();
    }
    serial = sable::state_hash(ref);
  }
  sable::MpiDomain<D> domain(MPI_COMM_WORLD);
  domain.set_cut_bias(bias);
  // Cuts by grain count (the time weights of `sable run` move them with the machine's noise):
  // the ghosts and traffic printed below are then reproducible. `sable run` under mpirun
  // (run_check.py) checks the time-weighted cuts.
  domain.set_time_weights(false);
  domain.scatter(world);
  sable::DemSolver<D> solver(world);
  solver.set_domain(&domain);
  if (!snapshot) solver.initialize();
  for (int s = 0; s < steps; ++s) {
    if (forced(o, s)) {
      world.neighbors.x_ref.clear();
      domain.set_cut_bias((s / o.recut) % 2 ? 2.0 - bias : bias);
    }
    solver.step();
  }
  // How many grains this process owns and how many ghosts it holds, at the end.
  std::size_t ghosts = 0;
  for (std::uint8_t f : world.particles.flags) ghosts += (f & sable::kGhost) ? 1 : 0;
  // And what it sent (the scaling model's inputs, docs/BENCHMARKS.md).
  const auto& t = domain.traffic();
  const double steps_done = static_cast<double>(std::max<std::uint64_t>(t.steps, 1));
  const double builds = static_cast<double>(std::max<std::uint64_t>(t.builds, 1));
  std::string box;
  for (int d = 0; d < D; ++d)
    box += std::to_string(domain.box().lo[d]) + ".." + std::to_string(domain.box().hi[d]) +
           (d + 1 < D ? " x " : "");
  std::printf(
      "process %d: %zu grains owned, %zu ghosts; a step: %.0f bytes in %.2f messages; a list "
      "build: %.0f bytes in %.2f messages (%llu builds); box %s m\n",
      rank, world.particles.size() - ghosts, ghosts, static_cast<double>(t.step_bytes) / steps_done,
      static_cast<double>(t.step_messages) / steps_done,
      static_cast<double>(t.build_bytes) / builds, static_cast<double>(t.build_messages) / builds,
      static_cast<unsigned long long>(t.builds), box.c_str());
  sable::World<D> whole;
  domain.gather(world, whole, 0);
  int same = 1;
  if (rank == 0) {
    const std::uint64_t split = sable::state_hash(whole);
    same = split == serial ? 1 : 0;
    std::printf(
        "%d processes, %d steps (%llu list builds), %zu grains: serial %016llx, split "
        "%016llx: %s\n",
        domain.size(), steps, static_cast<unsigned long long>(whole.neighbors.builds),
        whole.particles.size(), static_cast<unsigned long long>(serial),
        static_cast<unsigned long long>(split), same ? "the same" : "DIFFERENT");
    if (!same) compare(ref, whole);
  }
  MPI_Bcast(&same, 1, MPI_INT, 0, MPI_COMM_WORLD);
  return same ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  int rc = 2;
  if (argc >= 3 && argc <= 7) {
    try {
      const sable::ScenarioConfig cfg = sable::load_scenario(argv[1]);
      Options o;
      o.steps = std::atoi(argv[2]);
      if (argc >= 4) o.bias = std::atof(argv[3]);
      if (argc >= 5) o.stage = static_cast<std::size_t>(std::atoi(argv[4]));
      if (argc >= 6 && std::string(argv[5]) != "-") o.snapshot = argv[5];
      if (argc >= 7) o.recut = std::atoi(argv[6]);
      rc = cfg.sim.dimension == 2 ? check<2>(cfg, o, rank) : check<3>(cfg, o, rank);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "process %d: %s\n", rank, e.what());
      MPI_Abort(MPI_COMM_WORLD, 1);
    }
  } else if (rank == 0) {
    std::fprintf(stderr,
                 "usage: mpirun -np N %s SCENARIO STEPS [BIAS [STAGE [SNAPSHOT|- [RECUT]]]]\n",
                 argv[0]);
  }
  MPI_Finalize();
  return rc;
}
