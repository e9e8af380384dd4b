// Reordering of the grains' slots by cell (world/reorder.hpp): the order itself, a reorder
// that only moves data (every grain, contact history and id keeps its values exactly), the
// same bits for any thread count, the same trajectory to round-off, bit-identical resumes
// (DEM and contact dynamics), and the default ("auto": large beds only).
#include <gtest/gtest.h>

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "mesh_world.hpp"
#include "run_helpers.hpp"
#include "sable/core/error.hpp"
#include "sable/dem/dem_solver.hpp"
#include "sable/scenario/config.hpp"
#include "sable/world/reorder.hpp"
#include "sable/world/state_hash.hpp"

namespace sable {
namespace {

namespace fs = std::filesystem;
using Keys = std::vector<CellKey>;

// The slots' cell order (order[new] = old) of points `x` in the grid of cells of edge `cell`
// over [lo, hi]; the grain in slot s has id index id_index[s] (default: s).
template <int D>
std::vector<std::uint32_t> order_of(const std::vector<typename Space<D>::Vec>& x,
                                    const typename Space<D>::Vec& lo,
                                    const typename Space<D>::Vec& hi, double cell,
                                    std::vector<std::uint32_t> id_index = {}) {
  std::vector<ParticleId> id(x.size());
  for (std::size_t s = 0; s < x.size(); ++s)
    id[s].index = id_index.empty() ? static_cast<std::uint32_t>(s) : id_index[s];
  std::vector<std::uint32_t> order;
  Keys scratch;
  cell_order<D>(x, id, lo, hi, cell, order, scratch);
  return order;
}

// 3D: the centres of a 2 x 3 x 4 grid of cells (edge 0.25 from lo = (-1, -2, 0.5): exact in
// binary) put in slots in a scrambled order. z has the most cells, so it varies slowest, then
// y, then x: the order visits cell (cx, cy, cz) at position cx + 2 cy + 6 cz, exactly. 2D: a
// 5 x 3 grid, x the longer: position cy + 3 cx. Equal extents: the higher axis is the slower.
// Ties: grains of one cell go by id, whatever their slots and their positions inside it;
// grains outside the grid count in its nearest cell.
TEST(CellOrder, SortsByCellRowByRowTheLongestAxisSlowest) {
  const Eigen::Vector3d lo(-1.0, -2.0, 0.5);
  const double cell = 0.25;
  const Eigen::Vector3d hi = lo + cell * Eigen::Vector3d(2, 3, 4);
  std::vector<Eigen::Vector3d> x3;
  std::vector<std::uint32_t> pos3;  // slot s holds the cell visited at position pos3[s]
  for (std::uint32_t s = 0; s < 24; ++s) {
    const std::uint32_t c = s * 7 % 24, cx = c % 2, cy = c / 2 % 3, cz = c / 6;  // a bijection
    x3.push_back(lo + cell * Eigen::Vector3d(cx + 0.5, cy + 0.5, cz + 0.5));
    pos3.push_back(cx + 2 * cy + 6 * cz);
  }
  const auto order3 = order_of<3>(x3, lo, hi, cell);
  ASSERT_EQ(order3.size(), 24u);
  for (std::uint32_t k = 0; k < 24; ++k) EXPECT_EQ(pos3[order3[k]], k) << "position " << k;

  std::vector<Eigen::Vector2d> x2;
  std::vector<std::uint32_t> pos2;
  for (std::uint32_t s = 0; s < 15; ++s) {
    const std::uint32_t c = s * 4 % 15, cx = c % 5, cy = c / 5;
    x2.push_back(Eigen::Vector2d(cx + 0.5, cy + 0.5) * cell);
    pos2.push_back(cy + 3 * cx);
  }
  const auto order2 = order_of<2>(x2, Eigen::Vector2d::Zero(), Eigen::Vector2d(5, 3) * cell, cell);
  ASSERT_EQ(order2.size(), 15u);
  for (std::uint32_t k = 0; k < 15; ++k) EXPECT_EQ(pos2[order2[k]], k) << "position " << k;

  // A 2 x 2 square: y (the higher axis) slowest. Slots: (1, 0), (0, 1), (0, 0), (1, 1).
  const std::vector<Eigen::Vector2d> square{{1.5, 0.5}, {0.5, 1.5}, {0.5, 0.5}, {1.5, 1.5}};
  const std::vector<std::uint32_t> by_rows{2, 0, 1, 3};
  EXPECT_EQ(order_of<2>(square, Eigen::Vector2d::Zero(), Eigen::Vector2d(2, 2), 1.0), by_rows);

  // Slots 0 and 2 in cell (1, 0, 0), slots 1 and 3 in cell (0, 0, 0) of a 2 x 1 x 1 grid; slot
  // 2 lies nearer the origin than slot 0 and slot 3 nearer than slot 1: position inside a
  // cell does not count. Slot 4, beyond the grid's far end, counts in cell (1, 0, 0); slot 5,
  // before its start, in cell (0, 0, 0).
  const std::vector<Eigen::Vector3d> ties{{1.9, 0.1, 0.1}, {0.9, 0.9, 0.9}, {1.1, 0.1, 0.1},
                                          {0.1, 0.1, 0.1}, {7.0, 0.5, 0.5}, {-3.0, 0.5, 0.5}};
  const std::vector<std::uint32_t> expect{1, 3, 5, 0, 2, 4};
  EXPECT_EQ(order_of<3>(ties, Eigen::Vector3d::Zero(), Eigen::Vector3d(2, 1, 1), 1.0), expect);
  // The same grains with their ids in reverse slot order: each cell's grains by id, not by
  // slot (so that a process holding some of the grains, in other slots, orders them alike).
  const std::vector<std::uint32_t> by_id{5, 3, 1, 4, 2, 0};
  EXPECT_EQ(
      order_of<3>(ties, Eigen::Vector3d::Zero(), Eigen::Vector3d(2, 1, 1), 1.0, {5, 4, 3, 2, 1, 0}),
      by_id);
}

// A fixed LCG, numbers in [-0.5, 0.5): the same draws in every run.
struct Lcg {
  std::uint64_t seed;
  double next() {
    seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(seed >> 11) * 0x1.0p-53 - 0.5;
  }
};

template <int D>
typename Space<D>::Rot random_rot(Lcg& g, double scale) {
  if constexpr (D == 3) {
    return scale * Eigen::Vector3d(g.next(), g.next(), g.next());
  } else {
    return scale * g.next();
  }
}

// A bed of `side`^(D-1) x `layers` grains of radius 0.2 mm on a lattice of spacing 1.96 r
// (2 % overlaps: every grain touches its neighbours) on a floor, the leftmost column also
// against a side wall; added in a shuffled order (fixed seed), with random velocities (scale
// `v` m/s) and spins (scale 10 rad/s). Friction and rolling resistance: the lists carry
// shear, force and rolling springs.
template <int D>
World<D> shuffled_bed(int side, int layers, double v) {
  using Vec = typename Space<D>::Vec;
  World<D> w;
  w.materials.add({"g", 2500.0, 1e7, 0.3, 0.5, 0.5, 0.1});
  w.materials.finalize();
  w.model.rolling = RollingModel::kEpsd;
  w.neighbors.skin = 0.2e-3;
  w.neighbors.domain_lo = Vec::Constant(-0.01);
  w.neighbors.domain_hi = Vec::Constant(0.01);
  w.dt = 1e-6;
  const double r = 0.2e-3, a = 1.96 * r;
  std::vector<Vec> sites;
  for (int k = 0; k < layers; ++k)
    for (int y = 0; y < (D == 3 ? side : 1); ++y)
      for (int x = 0; x < side; ++x) {
        Vec s = Vec::Constant(-0.004);
        s[0] += a * x;
        if constexpr (D == 3) s[1] += a * y;
        s[D - 1] += a * k + r;
        sites.push_back(s);
      }
  Lcg g{12345};
  for (std::size_t k = sites.size(); k > 1; --k)  // Fisher-Yates
    std::swap(sites[k - 1],
              sites[static_cast<std::size_t>((g.next() + 0.5) * static_cast<double>(k))]);
  for (const Vec& s : sites) {
    w.particles.add(s, r, 2500.0, 0, w.thickness);
    for (int d = 0; d < D; ++d) w.particles.v.back()[d] = v * g.next();
    w.particles.omega.back() = random_rot<D>(g, 10.0);
  }
  w.gravity = Vec::Zero();
  w.gravity[D - 1] = -9.81;
  w.reorder_every = 0;  // each test says when it sorts
  Wall<D> floor, left;
  floor.point = Vec::Constant(-0.004);
  floor.set_plane(Vec::Unit(D - 1));
  left.point = Vec::Constant(-0.004 - 0.98 * r);  // the first column overlaps it by 2 %
  left.set_plane(Vec::Unit(0));
  w.walls = {floor, left};
  return w;
}

// What a grain (by its id) carries, and the contacts seen from each of their grains.
template <int D>
struct Grains {
  using Vec = typename Space<D>::Vec;
  using Rot = typename Space<D>::Rot;
  struct Grain {
    Vec x, v, f, x_ref;
    Rot w, t;
    double radius, mass, inv_mass, inv_inertia, film;
    Eigen::Vector4d q;  // orientation: the quaternion's coefficients, or (angle, 0, 0, 0)
    MaterialIndex material;
    std::uint8_t flags;
    bool operator==(const Grain&) const = default;
  };
  struct Contact {  // force, shear and rolling spring as the grain of the lower id sees them
    Vec force, shear;
    Rot roll;
    bool operator==(const Contact&) const = default;
  };
  std::vector<Grain> grain;                                               // by id index
  std::map<std::pair<std::uint32_t, std::uint32_t>, Contact> pair, wall;  // ids; (id, wall)
  std::map<std::pair<std::uint32_t, std::uint32_t>, bool> lower_first;    // lower id in slot i
};

template <int D>
Grains<D> record(const World<D>& w) {
  const auto& p = w.particles;
  const auto& nl = w.neighbors;
  Grains<D> g;
  g.grain.resize(p.size());
  for (std::size_t s = 0; s < p.size(); ++s) {
    Eigen::Vector4d q;
    if constexpr (D == 3) {
      q = p.q[s].coeffs();
    } else {
      q = Eigen::Vector4d(p.q[s], 0.0, 0.0, 0.0);
    }
    g.grain[p.id[s].index] = {p.x[s],        p.v[s],           p.f[s],           nl.x_ref[s],
                              p.omega[s],    p.t[s],           p.radius[s],      p.mass[s],
                              p.inv_mass[s], p.inv_inertia[s], w.liquid.film[s], q,
                              p.material[s], p.flags[s]};
  }
  for (std::size_t k = 0; k < nl.pairs.size(); ++k) {
    const std::uint32_t a = p.id[nl.pairs.i[k]].index, b = p.id[nl.pairs.j[k]].index;
    const double sign = a < b ? 1.0 : -1.0;  // stored for slot i; the partner sees minus it
    g.pair[std::minmax(a, b)] = {sign * nl.pairs.force[k], sign * nl.pairs.shear[k],
                                 sign * nl.pairs.roll[k]};
    g.lower_first[std::minmax(a, b)] = a < b;
  }
  const auto& wl = nl.wall_pairs;
  for (std::size_t k = 0; k < wl.size(); ++k)
    g.wall[{p.id[wl.i[k]].index, wl.wall[k]}] = {wl.force[k], wl.shear[k], wl.roll[k]};
  return g;
}

// 20 steps without reordering put history on the contacts; then one reorder. Every grain
// keeps its data and its id, every contact its force, shear and spring as each of its grains
// sees them, exactly (data are moved, and a swapped pair's history is negated: exact in
// floating point); both lists are sorted again, the slots are in cell order, and a second
// reorder finds nothing to do.
template <int D>
void check_reorder_keeps_everything(int side, int layers) {
  World<D> w = shuffled_bed<D>(side, layers, 0.01);
  DemSolver<D> solver(w);
  solver.initialize();
  for (int k = 0; k < 20; ++k) solver.step();
  auto& p = w.particles;
  auto& nl = w.neighbors;
  w.liquid.film.resize(p.size());
  for (std::size_t s = 0; s < p.size(); ++s) w.liquid.film[s] = 1e-12 * p.id[s].index;
  const Grains<D> before = record(w);
  std::size_t sheared = 0;
  for (const auto& [ids, c] : before.pair) sheared += c.shear.squaredNorm() > 0.0 ? 1 : 0;
  EXPECT_GT(sheared, p.size());  // history on most lattice contacts (~D per grain)
  EXPECT_GT(before.wall.size(), static_cast<std::size_t>(side));  // the floor's and the side's

  GrainReorder<D> reorder;
  ASSERT_TRUE(reorder.apply(w));
  EXPECT_EQ(reorder.reorders, 1u);
  const Grains<D> after = record(w);
  for (std::uint32_t k = 0; k < p.size(); ++k) {
    const ParticleId id = p.ids.id_at_index(k);
    EXPECT_EQ(p.id[p.ids.slot(id)], id);
    EXPECT_TRUE(after.grain[k] == before.grain[k]) << "grain id " << k;
  }
  EXPECT_TRUE(after.pair == before.pair) << "a contact's force, shear or spring changed";
  EXPECT_TRUE(after.wall == before.wall) << "a wall contact's force, shear or spring changed";
  std::size_t swapped = 0;  // loaded pairs whose first grain changed: negations exercised
  for (const auto& [ids, first] : before.lower_first)
    swapped += after.lower_first.at(ids) != first && before.pair.at(ids).shear.squaredNorm() > 0.0;
  EXPECT_GT(swapped, 0u);
  for (std::size_t k = 0; k < nl.pairs.size(); ++k) {
    EXPECT_LT(nl.pairs.i[k], nl.pairs.j[k]);
    if (k > 0) {
      EXPECT_LT(std::make_pair(nl.pairs.i[k - 1], nl.pairs.j[k - 1]),
                std::make_pair(nl.pairs.i[k], nl.pairs.j[k]));
    }
  }
  const auto& wl = nl.wall_pairs;
  for (std::size_t k = 1; k < wl.size(); ++k)
    EXPECT_LT(std::make_pair(wl.i[k - 1], wl.wall[k - 1]), std::make_pair(wl.i[k], wl.wall[k]));
  double rmax = 0.0;
  for (double r : p.radius) rmax = std::max(rmax, r);
  const auto order = order_of<D>(p.x, nl.domain_lo, nl.domain_hi, 2.0 * rmax + nl.skin);
  for (std::uint32_t k = 0; k < order.size(); ++k) ASSERT_EQ(order[k], k) << "not in cell order";

  const std::uint64_t hash = state_hash(w);
  EXPECT_FALSE(reorder.apply(w));
  EXPECT_EQ(reorder.reorders, 1u);
  EXPECT_EQ(state_hash(w), hash);
}

TEST(GrainReorder, KeepsEveryGrainAndContactHistory) {
  check_reorder_keeps_everything<3>(6, 4);
  check_reorder_keeps_everything<2>(12, 6);
}

// The bed of test_dem_basics' thread-count tests (16 x 16 x 12 grains, ~6,000 contacts: the
// pair pass splits among threads), shuffled, with a 1 um skin so that the lists are rebuilt
// during the 50 steps, and faster grains (0.1 m/s) so that some cross cells between builds.
struct BedRun {
  std::uint64_t hash, builds;
  std::size_t touching;               // contacts at the last step
  int reordered_steps = 0;            // steps after which the grains held other slots
  std::vector<Eigen::Vector3d> x, v;  // by id index
};

BedRun run_bed(int threads, std::uint64_t reorder_every) {
  World<3> w = shuffled_bed<3>(16, 12, 0.1);
  w.neighbors.skin = 1e-6;
  // The first column and row of grains lie 1 um above a cell boundary (cells of 2 r + skin
  // = 0.401 mm): the bed's overlaps push them outwards across it (by 1.4 to 3.7 um in x over
  // the 50 steps), and the reorders at the following builds move them to other slots.
  w.neighbors.domain_lo = Eigen::Vector3d::Constant(-0.004 - 10 * 0.401e-3 - 1e-6);
  w.reorder_every = reorder_every;
  const int before = omp_get_max_threads();
  omp_set_num_threads(threads);
  DemSolver<3> solver(w);
  solver.initialize();
  BedRun run;
  for (int k = 0; k < 50; ++k) {
    const std::vector<ParticleId> ids = w.particles.id;
    solver.step();
    run.reordered_steps += w.particles.id != ids ? 1 : 0;
  }
  omp_set_num_threads(before);
  run.hash = state_hash(w);
  run.builds = w.neighbors.builds;
  run.touching = solver.diagnostics().touching;
  run.x.resize(w.particles.size());
  run.v.resize(w.particles.size());
  for (std::size_t s = 0; s < w.particles.size(); ++s) {
    run.x[w.particles.id[s].index] = w.particles.x[s];
    run.v[w.particles.id[s].index] = w.particles.v[s];
  }
  return run;
}

// Reordering at every build keeps the thread count out of the bits: the order follows from
// the positions alone. 1, 2 and 3 threads give the same state hash, exactly; and the grains
// really were reordered during the steps, not only at the first build (measured: 39 builds,
// the slots changed after 9 of the 50 steps).
TEST(GrainReorder, SameBitsForAnyThreadCount) {
  const BedRun one = run_bed(1, 1);
  EXPECT_GT(one.touching, 2048u);  // the pair pass runs in parallel above 2048 contacts
  EXPECT_GT(one.builds, 2u);
  EXPECT_GT(one.reordered_steps, 0);
  for (int threads : {2, 3}) {
    const BedRun other = run_bed(threads, 1);
    EXPECT_EQ(other.hash, one.hash) << threads << " threads";
    EXPECT_EQ(other.reordered_steps, one.reordered_steps) << threads << " threads";
  }
}

// Reordering changes only the order in which each grain's contact forces are summed, so the
// bed follows the same trajectory with and without it, to round-off. Measured over the 50
// steps: positions differ in 71 of 3,072 grains, by at most 4.3e-19 m (one unit in the last
// place of a coordinate of 2 to 4 mm: a drift of 5e-8 m per step hides velocity round-off);
// velocities in 3,031 grains, by at most 2.2e-14 m/s (speeds reach 0.66 m/s: 3e-14
// relative). The bounds, ~100 times those, are 2e-13 of the radius and 3e-12 of the speeds.
TEST(GrainReorder, FollowsTheSameTrajectory) {
  const BedRun on = run_bed(1, 1), off = run_bed(1, 0);
  ASSERT_EQ(on.x.size(), off.x.size());
  EXPECT_GT(on.reordered_steps, 0);
  EXPECT_EQ(off.reordered_steps, 0);
  double dx = 0.0, dv = 0.0;
  for (std::size_t k = 0; k < on.x.size(); ++k) {
    dx = std::max(dx, (on.x[k] - off.x[k]).norm());
    dv = std::max(dv, (on.v[k] - off.v[k]).norm());
  }
  EXPECT_LT(dx, 4e-17);
  EXPECT_LT(dv, 2e-12);
}

// The pour of run_helpers.hpp, reordering every `every` builds, shortened: DEM 600 + 1,400
// steps, a snapshot every 300; contact dynamics 150 + 100 steps, a snapshot every 100.
std::string reorder_pour(const fs::path& dir, int every, const std::string& solver = "dem") {
  std::string text = test::small_pour_2d(dir.string(), solver);
  text.replace(text.find("[simulation]\n"), 13,
               "[simulation]\nreorder_every = " + std::to_string(every) + "\n");
  if (solver == "dem") text.replace(text.find("steps = 12000"), 13, "steps = 1400");
  if (solver == "cd") text.replace(text.find("steps = 600"), 11, "steps = 100");
  text.replace(text.find("snapshot_interval = 0"), 21,
               solver == "dem" ? "snapshot_interval = 300" : "snapshot_interval = 100");
  return text;
}

// Resuming in the middle of the fall reorders at the same builds as the unbroken run (the
// build count is in the snapshot): the same state hash, exactly. The same resume without
// reordering ends elsewhere, so reorders happened after the snapshot and the equality above
// covers them. Contact dynamics too: its sweep follows the list, so a sort changes the
// iterates, and a resume must sort where the unbroken run did.
TEST(ReorderScenario, ResumeIsBitIdentical) {
  struct Case {
    std::string solver, snapshot;
    std::uint64_t steps;
  };
  for (const Case& c :
       {Case{"dem", "step_0000000300.h5", 2000}, Case{"cd", "step_0000000100.h5", 250}}) {
    SCOPED_TRACE(c.solver);
    const fs::path dir = fs::temp_directory_path() / ("sable_test_reorder_resume_" + c.solver);
    fs::remove_all(dir);
    const std::string text = reorder_pour(dir, 2, c.solver);
    const auto full = test::run_text(text);
    ASSERT_EQ(full.steps, c.steps);
    const std::string snap = (dir / "snapshots" / c.snapshot).string();
    const auto resumed = test::run_text(text, {snap, false, 0});
    EXPECT_EQ(resumed.steps, full.steps);
    EXPECT_EQ(resumed.state_hash, full.state_hash);
    const auto unordered = test::run_text(reorder_pour(dir, 0, c.solver), {snap, false, 0});
    EXPECT_EQ(unordered.steps, full.steps);
    EXPECT_NE(unordered.state_hash, full.state_hash);
    fs::remove_all(dir);
  }
}

// The default, reorder_every = "auto", sorts every 20th build (the first included) of a bed of
// 1,000 grains or more and never a smaller one; a number N sorts every N-th build; 0 never.
TEST(ReorderDefault, SortsEveryTwentiethBuildOfBedsOfAThousandGrains) {
  const World<3> w3;
  const World<2> w2;
  EXPECT_EQ(w3.reorder_every, kReorderAuto);
  EXPECT_EQ(w2.reorder_every, kReorderAuto);
  for (std::uint64_t build : {0u, 20u, 40u, 1000u}) {
    EXPECT_TRUE(reorder_due(kReorderAuto, build, 1000)) << build;
    EXPECT_TRUE(reorder_due(kReorderAuto, build, 125000)) << build;
    EXPECT_FALSE(reorder_due(kReorderAuto, build, 999)) << build;
    EXPECT_FALSE(reorder_due(0, build, 125000)) << build;
  }
  for (std::uint64_t build : {1u, 19u, 21u, 39u})
    EXPECT_FALSE(reorder_due(kReorderAuto, build, 1000));
  for (std::uint64_t build : {0u, 3u, 6u, 300u}) EXPECT_TRUE(reorder_due(3, build, 10)) << build;
  for (std::uint64_t build : {1u, 2u, 4u, 301u}) EXPECT_FALSE(reorder_due(3, build, 10)) << build;
}

// The default in a solver: a shuffled bed of 1,024 grains is in cell order after the first
// build (every grain's slot is where cell_order puts it), one of 960 keeps its slots.
TEST(ReorderDefault, TheFirstBuildSortsALargeShuffledBedOnly) {
  for (const auto& [side, layers] : {std::pair{16, 4}, std::pair{16, 3}}) {
    World<3> w = shuffled_bed<3>(side, layers, 0.01);
    w.reorder_every = kReorderAuto;
    const std::vector<ParticleId> ids = w.particles.id;
    const std::size_t n = ids.size();
    ASSERT_TRUE(n == 1024 || n == 768) << n;
    std::vector<std::uint32_t> expected;
    Keys scratch;
    const double cell = 2.0 * 0.2e-3 + w.neighbors.skin;  // 2 R_max + skin
    cell_order<3>(w.particles.x, w.particles.id, w.neighbors.domain_lo, w.neighbors.domain_hi, cell,
                  expected, scratch);
    DemSolver<3> solver(w);
    solver.initialize();
    if (n >= kAutoReorderMinGrains) {
      for (std::size_t s = 0; s < n; ++s) ASSERT_EQ(w.particles.id[s], ids[expected[s]]) << s;
    } else {
      EXPECT_EQ(w.particles.id, ids);
    }
  }
}

// reorder_every takes a non-negative integer or "auto" (the default); anything else is an
// InputError naming the key and what it takes.
TEST(ReorderScenario, RejectsABadReorderEvery) {
  const std::string base = test::small_pour_2d("unused", "dem");
  auto with = [&base](const std::string& value) {
    return std::string(base).replace(base.find("[simulation]\n"), 13,
                                     "[simulation]\nreorder_every = " + value + "\n");
  };
  EXPECT_FALSE(parse_scenario(base, "t.toml").sim.reorder_every.has_value());
  EXPECT_FALSE(parse_scenario(with("\"auto\""), "t.toml").sim.reorder_every.has_value());
  EXPECT_EQ(parse_scenario(with("0"), "t.toml").sim.reorder_every, 0u);
  EXPECT_EQ(parse_scenario(with("7"), "t.toml").sim.reorder_every, 7u);
  for (const char* bad : {"-1", "\"x\"", "\"Auto\"", "2.5", "true"}) {
    try {
      parse_scenario(with(bad), "t.toml");
      ADD_FAILURE() << "expected an InputError for reorder_every = " << bad;
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find("simulation.reorder_every"), std::string::npos) << msg;
      EXPECT_NE(msg.find("non-negative integer"), std::string::npos) << msg;
      EXPECT_NE(msg.find("\"auto\""), std::string::npos) << msg;
    }
  }
}

}  // namespace
}  // namespace sable

namespace sable {
namespace {

// A mesh's wall entries keep their element and the feature their history belongs to when the
// grains are moved into cell order: each (grain, wall, element) holds after the sort the
// feature, history and force it held before. (They once stayed in place while the entries
// moved, scrambling mesh contacts' histories at every sort: the MPI comparison of the mixer
// found it, tests/CMakeLists.txt, Mpi.MixerSameBits.)
TEST(ReorderMesh, WallEntriesKeepTheirElementAndFeature) {
  World<3> w = test::mesh_world<3>();
  DemSolver<3> solver(w);
  solver.initialize();
  for (int s = 0; s < 300; ++s) solver.step();
  const auto& wl = w.neighbors.wall_pairs;
  using Key = std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>;
  std::map<Key, std::tuple<std::uint32_t, Eigen::Vector3d, Eigen::Vector3d>> before;
  std::size_t mesh_contacts = 0;
  for (std::size_t k = 0; k < wl.size(); ++k) {
    before[{w.particles.id[wl.i[k]].index, wl.wall[k], wl.element[k]}] = {wl.feature[k],
                                                                          wl.shear[k], wl.force[k]};
    mesh_contacts += wl.wall[k] == test::kPaddle && wl.force[k].squaredNorm() > 0.0 ? 1 : 0;
  }
  ASSERT_GT(mesh_contacts, 0u) << "the paddle should touch grains by now";
  GrainReorder<3> reorder;
  ASSERT_TRUE(reorder.apply(w)) << "the grains should not be in cell order already";
  ASSERT_EQ(wl.size(), before.size());
  for (std::size_t k = 0; k < wl.size(); ++k) {
    const auto it = before.find({w.particles.id[wl.i[k]].index, wl.wall[k], wl.element[k]});
    ASSERT_NE(it, before.end()) << "entry " << k;
    EXPECT_EQ(std::get<0>(it->second), wl.feature[k]) << "entry " << k;
    EXPECT_EQ(std::get<1>(it->second), wl.shear[k]) << "entry " << k;
    EXPECT_EQ(std::get<2>(it->second), wl.force[k]) << "entry " << k;
  }
}

}  // namespace
}  // namespace sable
