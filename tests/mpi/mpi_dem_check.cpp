// The promise of the MPI decomposition (world/domain.hpp): the same bits as a serial run for
// any number of processes. Run as `mpirun -np N sable_mpi_dem_check SCENARIO STEPS [RECUT]`:
// every process builds the scenario's world; process 0 also steps a serial copy with the
// plain DemSolver; the decomposed run steps STEPS steps of its first stage's physics (no
// stage rules; the wall velocities and rotations of stage STAGE, counted from 0, default 0),
// then the whole state is gathered on process 0 and both state hashes are compared. BIAS
// (default 1) makes every cut lopsided (mpi/rcb.hpp). Exit 0 when the hashes
// are equal (on every process), 1 when not, 2 on bad arguments.
#include <mpi.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "sable/dem/dem_solver.hpp"
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
}

template <int D>
int check(const sable::ScenarioConfig& cfg, int steps, double bias, std::size_t stage, int rank) {
  sable::World<D> world;
  sable::build_model(cfg, world);
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
    solver.initialize();
    for (int s = 0; s < steps; ++s) solver.step();
    serial = sable::state_hash(ref);
  }
  sable::MpiDomain<D> domain(MPI_COMM_WORLD);
  domain.set_cut_bias(bias);
  domain.scatter(world);
  sable::DemSolver<D> solver(world);
  solver.set_domain(&domain);
  solver.initialize();
  for (int s = 0; s < steps; ++s) solver.step();
  // How many grains this process owns and how many ghosts it holds, at the end.
  std::size_t ghosts = 0;
  for (std::uint8_t f : world.particles.flags) ghosts += (f & sable::kGhost) ? 1 : 0;
  std::printf("process %d: %zu grains owned, %zu ghosts\n", rank, world.particles.size() - ghosts,
              ghosts);
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
  if (argc >= 3 && argc <= 5) {
    try {
      const sable::ScenarioConfig cfg = sable::load_scenario(argv[1]);
      const int steps = std::atoi(argv[2]);
      const double bias = argc >= 4 ? std::atof(argv[3]) : 1.0;
      const auto stage = static_cast<std::size_t>(argc == 5 ? std::atoi(argv[4]) : 0);
      rc = cfg.sim.dimension == 2 ? check<2>(cfg, steps, bias, stage, rank)
                                  : check<3>(cfg, steps, bias, stage, rank);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "process %d: %s\n", rank, e.what());
      MPI_Abort(MPI_COMM_WORLD, 1);
    }
  } else if (rank == 0) {
    std::fprintf(stderr, "usage: mpirun -np N %s SCENARIO STEPS [BIAS [STAGE]]\n", argv[0]);
  }
  MPI_Finalize();
  return rc;
}
