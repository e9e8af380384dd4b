// Basic DEM behaviours the scenario features rely on: fixed grains, moving walls, the
// cylinder wall, and the run guards (runaway grains, overlap warnings).
#include <gtest/gtest.h>

#include <filesystem>
#include <limits>
#include <sstream>
#include <vector>

#include <omp.h>

#include "sable/core/error.hpp"
#include "sable/dem/dem_solver.hpp"
#include "sable/scenario/config.hpp"
#include "sable/scenario/runner.hpp"
#include "sable/world/guards.hpp"
#include "sable/world/state_hash.hpp"

namespace {

sable::World<3> world_with_material(double e = 0.3, double mu = 0.5, double mu_r = 0.0) {
  sable::World<3> w;
  w.materials.add({"g", 2500.0, 1e7, 0.3, e, mu, mu_r});
  w.materials.finalize();
  w.neighbors.skin = 0.2e-3;
  w.neighbors.domain_lo = Eigen::Vector3d(-0.01, -0.01, -0.01);
  w.neighbors.domain_hi = Eigen::Vector3d(0.01, 0.01, 0.01);
  w.dt = 1e-6;
  return w;
}

// A grain resting on a fixed grain under gravity: the fixed grain never moves, and at rest the
// contact carries exactly the weight m g (static balance; 1e-6 relative once damped out).
TEST(DemBasics, GrainRestsOnFixedGrain) {
  auto w = world_with_material();
  const double r = 1e-3;
  w.particles.add({0, 0, 0}, r, 2500.0, 0, 1.0, /*fixed=*/true);
  w.particles.add({0, 0, 2 * r}, r, 2500.0, 0, 1.0);
  w.gravity = {0, 0, -9.81};
  sable::DemSolver<3> s(w);
  s.initialize();
  for (int k = 0; k < 200000; ++k) s.step();
  EXPECT_EQ(w.particles.x[0], Eigen::Vector3d(0, 0, 0));
  EXPECT_EQ(w.particles.v[0], Eigen::Vector3d(0, 0, 0));
  ASSERT_EQ(w.neighbors.pairs.size(), 1u);
  const double weight = w.particles.mass[1] * 9.81;
  // pairs.force is the force on i = slot 0 (the fixed grain): -m g along z.
  EXPECT_NEAR(w.neighbors.pairs.force[0].z(), -weight, 1e-6 * weight);
  EXPECT_LT(w.particles.v[1].norm(), 1e-6);
}

// A floor rising at constant speed lifts a grain resting on it under gravity: after the
// transient the grain travels with the floor (averaged over the second half, 1 % of the
// speed covers the damped contact oscillation), and the floor carries the weight m g.
TEST(DemBasics, MovingWallPushesGrain) {
  auto w = world_with_material(0.2, 0.0);
  const double r = 1e-3;
  w.particles.add({0, 0, r}, r, 2500.0, 0, 1.0);
  w.gravity = {0, 0, -9.81};
  sable::Wall<3> floor;
  floor.point = Eigen::Vector3d(0, 0, 0);
  floor.set_plane(Eigen::Vector3d(0, 0, 1));
  floor.velocity = Eigen::Vector3d(0, 0, 0.01);
  w.walls.push_back(floor);
  sable::DemSolver<3> s(w);
  s.initialize();
  double mean_v = 0.0;
  const int n = 200000, half = n / 2;
  for (int k = 0; k < n; ++k) {
    s.step();
    if (k >= half) mean_v += w.particles.v[0].z() / half;
  }
  EXPECT_NEAR(mean_v, 0.01, 1e-4);  // 1 % of the wall speed: transient residue
  EXPECT_NEAR(w.walls[0].point.z(), 0.01 * n * w.dt, 1e-12);
  const double weight = w.particles.mass[0] * 9.81;
  EXPECT_NEAR(w.walls[0].force.z(), -weight, 1e-3 * weight);  // the grain's weight, at rest
}

// A sphere's orientation enters no force, so `track_orientation = false` changes nothing but
// the orientations: positions, velocities and spins are the same bits (exact: the same
// operations in the same order), the orientations stay the identity, and with tracking they
// turn (a grain sliding on a rough floor starts to roll) and stay unit (1e-12: round-off).
TEST(DemBasics, OrientationTrackingChangesNothingElse) {
  auto run = [](bool track) {
    auto w = world_with_material(0.5, 0.5);
    w.track_orientation = track;
    const double r = 1e-3;
    for (int k = 0; k < 3; ++k) {
      w.particles.add({2.2 * r * k, 0, r}, r, 2500.0, 0, 1.0);
      w.particles.v.back() = Eigen::Vector3d(0.05 * (k - 1), 0.02, 0);
    }
    w.gravity = {0, 0, -9.81};
    sable::Wall<3> floor;
    floor.point = Eigen::Vector3d(0, 0, 0);
    floor.set_plane(Eigen::Vector3d(0, 0, 1));
    w.walls.push_back(floor);
    sable::DemSolver<3> s(w);
    s.initialize();
    for (int k = 0; k < 20000; ++k) s.step();
    return w.particles;
  };
  const auto on = run(true), off = run(false);
  ASSERT_EQ(on.size(), 3u);
  for (std::size_t k = 0; k < on.size(); ++k) {
    EXPECT_EQ(on.x[k], off.x[k]);
    EXPECT_EQ(on.v[k], off.v[k]);
    EXPECT_EQ(on.omega[k], off.omega[k]);
    EXPECT_TRUE(off.q[k].coeffs() == Eigen::Quaterniond::Identity().coeffs());
    EXPECT_GT(on.q[k].vec().norm(), 1e-3);  // it rolled: turned by more than ~0.002 rad
    EXPECT_NEAR(on.q[k].norm(), 1.0, 1e-12);
  }
}

// The bed of the thread-count tests, in world `w` (its material and contact law): 16 x 16 x 12
// grains on a lattice with 2 % overlaps, on a floor, with random velocities and spins from a
// fixed LCG (the same draws for every run). 50 steps on `threads` threads; returns the
// solver's touching count of the last step.
std::size_t run_lattice_bed(sable::World<3>& w, int threads, double spacing = 1.96,
                            std::vector<double> shares = {},
                            std::vector<std::vector<std::uint32_t>>* cuts = nullptr) {
  const double r = 0.2e-3, a = spacing * r;
  std::uint64_t seed = 12345;
  auto jitter = [&seed]() {
    seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(seed >> 11) * 0x1.0p-53 - 0.5;
  };
  for (int z = 0; z < 12; ++z)
    for (int y = 0; y < 16; ++y)
      for (int x = 0; x < 16; ++x) {
        w.particles.add({a * x - 0.004, a * y - 0.004, a * z - 0.004 + r}, r, 2500.0, 0, 1.0);
        w.particles.v.back() = 0.01 * Eigen::Vector3d(jitter(), jitter(), jitter());
        w.particles.omega.back() = 10.0 * Eigen::Vector3d(jitter(), jitter(), jitter());
      }
  w.gravity = {0, 0, -9.81};
  sable::Wall<3> floor;
  floor.point = Eigen::Vector3d(0, 0, -0.004);
  floor.set_plane(Eigen::Vector3d(0, 0, 1));
  w.walls.push_back(floor);
  const int before = omp_get_max_threads();
  omp_set_num_threads(threads);
  sable::DemSolver<3> s(w);
  if (!shares.empty()) s.fix_thread_shares(shares);
  s.initialize();
  for (int k = 0; k < 50; ++k) s.step();
  omp_set_num_threads(before);
  if (cuts)
    for (const sable::GrainSplit* split : s.grain_splits())
      cuts->emplace_back(split->bounds(), split->bounds() + split->blocks() + 1);
  return s.diagnostics().touching;
}

// The thread count does not change a bit, in a bed where every grain touches its lattice
// neighbours from the first step (~3 contacts per grain, thousands in all, so the force pass
// really splits): each thread takes a block of grains and adds forces as it goes; the grains
// another block reaches are summed afterwards, in the same order (DemSolver::dry_pair_forces).
// 1, 2, 3 and 4 threads: more blocks, more such grains. Exact equality of the state hash.
TEST(DemBasics, ThreadCountDoesNotChangeABit) {
  auto run = [](int threads) {
    auto w = world_with_material(0.5, 0.5);
    EXPECT_GT(run_lattice_bed(w, threads), 6000u);  // the pass runs in parallel above 2048
    return sable::state_hash(w);
  };
  const std::uint64_t one = run(1);
  for (int threads : {2, 3, 4}) EXPECT_EQ(run(threads), one) << threads << " threads";
}

// The threads' shares of the grains follow their measured speeds (dem/grain_split.hpp), so
// the cut between their blocks changes from run to run; the results must not. The bed of
// ThreadCountDoesNotChangeABit with deliberately lopsided fixed shares, the cut far from where
// an even split or the measured speeds would put it (a block of 10 % of the work, thousands
// of grains gathered from another block): the same state hash as one thread, exactly. Also
// in the dilute bed, where the grain loops are cut by grain count alone. The grain loops
// also share their grains in chunks (a thread done with its block takes what is left of the
// others'): with a block of 10 %, its thread does much of the other block too; so does the
// pair pass with each block's tail (the last 5 % of its work), taken from its far end by the
// threads done with their own, whose grains are then gathered after the pass.
TEST(DemBasics, LopsidedThreadSharesDoNotChangeABit) {
  const std::vector<std::vector<double>> lopsided{{0.1, 0.9}, {0.85, 0.15}, {0.6, 0.1, 0.3}};
  for (double spacing : {1.96, 2.5}) {
    auto base = world_with_material(0.5, 0.5);
    run_lattice_bed(base, 1, spacing);
    const std::uint64_t one = sable::state_hash(base);
    for (const auto& shares : lopsided) {
      auto w = world_with_material(0.5, 0.5);
      std::vector<std::vector<std::uint32_t>> cuts;
      run_lattice_bed(w, static_cast<int>(shares.size()), spacing, shares, &cuts);
      EXPECT_EQ(sable::state_hash(w), one)
          << "spacing " << spacing << ", shares " << shares[0] << ", " << shares[1];
      // The cuts really are lopsided: in each loop block 0 holds its share of the grains to
      // 0.05 (the grain loops cut by count; the pair pass by work, which varies a little with
      // depth: 3,072 grains, ~3 entries each).
      ASSERT_EQ(cuts.size(), 2u);  // the opening loop's and the pair pass's (which closes)
      const double n = static_cast<double>(w.particles.size());
      for (const auto& cut : cuts) {
        ASSERT_EQ(cut.size(), shares.size() + 1);
        EXPECT_NEAR(cut[1] / n, shares[0], 0.05) << "spacing " << spacing;
      }
    }
  }
}

// A dilute bed: the lattice spread out (gaps of half a radius, within the list's skin but
// beyond the near list's), so the near list is empty while 3,072 grains fall, and those of
// the bottom layer that move down touch the floor: the pair pass has nothing to split, the
// grain loops still run on a team. 1, 2, 3 and 4 threads give the same state hash, exactly.
TEST(DemBasics, ThreadCountDoesNotChangeABitInADiluteBed) {
  std::size_t candidates = 0;
  auto run = [&candidates](int threads) {
    auto w = world_with_material(0.5, 0.5);
    const std::size_t touching = run_lattice_bed(w, threads, 2.5);
    EXPECT_EQ(w.particles.size(), 3072u);
    EXPECT_GT(touching, 50u);  // bottom-layer grains moving down onto the floor (118 of 256)
    candidates = w.neighbors.pairs.size();
    return sable::state_hash(w);
  };
  const std::uint64_t one = run(1);
  EXPECT_GT(candidates, 3000u);  // pairs within the skin, none within the near list's
  for (int threads : {2, 3, 4}) EXPECT_EQ(run(threads), one) << threads << " threads";
}

// Rolling resistance (in the pair pass, dem/dem_solver_impl.hpp) keeps the thread count out of the
// bits: each contact's couple is added to its grains right after its force's torque, in the
// fixed per-grain order of the pass and of the gather. The bed of ThreadCountDoesNotChangeABit
// with rolling resistance (mu_r = 0.1 on the material, the lists carrying springs from their
// first build): 1, 2, 3 and 4 threads give the same state hash, which covers the springs, and
// the same torques, spins and springs, exactly. The same run without rolling resistance ends
// with other spins (the couples really acted): they oppose the grains' random relative spins,
// so the bed keeps less rotational energy than without them.
TEST(DemBasics, ThreadCountDoesNotChangeABitWithRollingResistance) {
  struct End {
    std::uint64_t hash;
    std::vector<Eigen::Vector3d> w, t, roll, wall_roll;
    double rotational_energy = 0.0;
    std::size_t touching = 0;
  };
  auto run = [](int threads, bool rolling) {
    auto w = world_with_material(0.5, 0.5, rolling ? 0.1 : 0.0);
    if (rolling) {
      w.model.rolling = sable::RollingModel::kEpsd;
      w.neighbors.rolling = true;
    }
    const std::size_t touching = run_lattice_bed(w, threads);
    End end{sable::state_hash(w), w.particles.omega, w.particles.t, w.neighbors.pairs.roll,
            w.neighbors.wall_pairs.roll};
    for (std::size_t k = 0; k < w.particles.size(); ++k)
      end.rotational_energy +=
          0.5 * w.particles.omega[k].squaredNorm() / w.particles.inv_inertia[k];
    end.touching = touching;
    return end;
  };
  const End one = run(1, true);
  EXPECT_GT(one.touching, 6000u);         // the couple pass runs in parallel above 2048 contacts
  std::size_t wound = 0, wall_wound = 0;  // springs the snapshot and the hash must carry
  for (const auto& th : one.roll) wound += th.squaredNorm() > 0.0 ? 1 : 0;
  for (const auto& th : one.wall_roll) wall_wound += th.squaredNorm() > 0.0 ? 1 : 0;
  EXPECT_GT(wound, 6000u);
  EXPECT_GT(wall_wound, 200u);  // the bottom layer of 256 grains on the floor
  for (int threads : {2, 3, 4}) {
    const End other = run(threads, true);
    EXPECT_EQ(other.hash, one.hash) << threads << " threads";
    EXPECT_TRUE(other.w == one.w) << threads << " threads: spins differ";
    EXPECT_TRUE(other.t == one.t) << threads << " threads: torques differ";
    EXPECT_TRUE(other.roll == one.roll) << threads << " threads: springs differ";
    EXPECT_TRUE(other.wall_roll == one.wall_roll) << threads << " threads: wall springs differ";
  }
  const End free = run(1, false);
  EXPECT_TRUE(free.roll.empty());  // no springs without the sub-model
  std::size_t changed = 0;
  for (std::size_t k = 0; k < one.w.size(); ++k) changed += one.w[k] != free.w[k] ? 1 : 0;
  EXPECT_EQ(changed, one.w.size()) << "rolling resistance should change every grain's spin";
  EXPECT_LT(one.rotational_energy, free.rotational_energy);
}

// Inside a cylinder a grain thrown outwards comes back: the wall's normal points to the axis
// and the grain never leaves the cylinder by more than a small overlap. Elastic and
// frictionless, so its speed is conserved over the bounces (to the symplectic O(dt^2) error).
TEST(DemBasics, CylinderWallContainsGrain) {
  auto w = world_with_material(1.0, 0.0);
  const double r = 1e-3, rc = 5e-3;
  w.particles.add({0, 0, 0}, r, 2500.0, 0, 1.0);
  w.particles.v[0] = Eigen::Vector3d(0.3, 0.2, 0.0);
  sable::Wall<3> cyl;
  cyl.point = Eigen::Vector3d(0, 0, 0);
  cyl.set_cylinder(rc);
  w.walls.push_back(cyl);
  sable::DemSolver<3> s(w);
  s.initialize();
  double max_rho = 0.0;
  for (int k = 0; k < 100000; ++k) {
    s.step();
    max_rho = std::max(max_rho, w.particles.x[0].head<2>().norm());
  }
  EXPECT_GT(max_rho, rc - r - 0.1 * r);  // it reached the wall
  EXPECT_LT(max_rho, rc - r + 0.1 * r);  // and did not pass it
  EXPECT_NEAR(w.particles.v[0].norm(), std::hypot(0.3, 0.2), 1e-3 * std::hypot(0.3, 0.2));
  EXPECT_EQ(w.particles.x[0].z(), 0.0);  // the wall is vertical: no force along the axis
}

std::string runaway_scenario(const std::string& out, double dt, double z2 = 0.0035) {
  std::ostringstream s;
  s << "[simulation]\ndt = " << dt << "\ngravity = [0, 0, -9.81]\nmax_speed = 10.0\n"
    << "overlap_warning = 0.01\n"
    << "initial_overlap = 0.6\n"  // deliberate: these grains must start overlapping
    << "[domain]\nlo = [0, 0, 0]\nhi = [0.01, 0.01, 0.01]\n"
    << "[[material]]\nname = \"g\"\ndensity = 2500.0\nyoung = 1e8\npoisson = 0.3\n"
    << "[[grains]]\ngenerator = \"list\"\nmaterial = \"g\"\nradius = 1e-3\n"
    << "positions = [[0.005, 0.005, 0.002], [0.005, 0.005, " << z2 << "]]\n"
    << "[[wall]]\nname = \"floor\"\ntype = \"plane\"\nmaterial = \"g\"\npoint = [0, 0, 0]\n"
    << "normal = [0, 0, 1]\n"
    << "[[stage]]\nsteps = 200\n[output]\ndir = \"" << out << "\"\n";
  return s.str();
}

// Grains inserted overlapping by half a radius (allowed by initial_overlap) explode: the run
// stops with a SimulationError naming the step and a grain, and writes a crash snapshot first.
// The time step, 0.37 Rayleigh times, is within the bound the scenario checks.
TEST(DemBasics, RunawayStopsWithSnapshot) {
  const auto dir = std::filesystem::temp_directory_path() / "sable_runaway";
  std::filesystem::remove_all(dir);
  const auto cfg = sable::parse_scenario(runaway_scenario(dir.string(), 1e-5), "r.toml");
  sable::RunOptions opt;
  std::ostringstream log;
  opt.log = &log;
  opt.live_progress = false;
  try {
    sable::run_scenario(cfg, opt);
    FAIL() << "expected the run to stop";
  } catch (const sable::SimulationError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("grain id"), std::string::npos) << msg;
    EXPECT_NE(msg.find("crash_step_"), std::string::npos) << msg;
  }
  bool found = false;
  for (const auto& f : std::filesystem::directory_iterator(dir / "snapshots"))
    found |= f.path().filename().string().rfind("crash_step_", 0) == 0;
  EXPECT_TRUE(found);
  std::filesystem::remove_all(dir);
}

// A grain whose position is not finite stops the next step, named, although its velocity is
// sound and it touches nothing: the guard checks positions too (guards.hpp, position_ok).
TEST(DemBasics, NonFinitePositionStopsTheStep) {
  auto w = world_with_material();
  const double r = 1e-3;
  w.particles.add({0, 0, 0}, r, 2500.0, 0, 1.0);
  w.particles.add({0.005, 0, 0}, r, 2500.0, 0, 1.0);
  sable::DemSolver<3> s(w);
  s.initialize();
  s.step();
  w.particles.x[1].y() = std::numeric_limits<double>::quiet_NaN();
  try {
    s.step();
    FAIL() << "expected the step to stop";
  } catch (const sable::SimulationError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("grain id 1 has a non-finite state"), std::string::npos) << msg;
  }
}

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The run guard's two halves (world/guards.hpp). position_ok: every finite position passes,
// even the largest (x - x is 0 there too); an infinite or NaN coordinate fails, in any
// component, in 2D and 3D. motion_ok: a speed up to max_speed passes, above it fails, and so
// does any non-finite velocity or spin.
TEST(Guards, PositionAndMotionTests) {
  const double big = std::numeric_limits<double>::max();
  EXPECT_TRUE(sable::position_ok<3>(Eigen::Vector3d(1.0, -2.0, 3.0)));
  EXPECT_TRUE(sable::position_ok<3>(Eigen::Vector3d(big, -big, big)));
  EXPECT_TRUE(sable::position_ok<2>(Eigen::Vector2d(-big, 0.0)));
  for (int c = 0; c < 3; ++c)
    for (double bad : {kInf, -kInf, kNaN}) {
      Eigen::Vector3d x(1.0, 2.0, 3.0);
      x[c] = bad;
      EXPECT_FALSE(sable::position_ok<3>(x)) << "component " << c << " = " << bad;
      if (c < 2) {
        Eigen::Vector2d x2(1.0, 2.0);
        x2[c] = bad;
        EXPECT_FALSE(sable::position_ok<2>(x2)) << "2D component " << c << " = " << bad;
      }
    }
  const Eigen::Vector3d w(1.0, 2.0, 3.0);
  EXPECT_TRUE(sable::motion_ok<3>(Eigen::Vector3d(3.0, 4.0, 0.0), w, 5.0));  // |v| = max
  EXPECT_FALSE(sable::motion_ok<3>(Eigen::Vector3d(3.0, 4.0, 1e-6), w, 5.0));
  EXPECT_FALSE(sable::motion_ok<3>(Eigen::Vector3d(kNaN, 0.0, 0.0), w, 5.0));
  EXPECT_FALSE(
      sable::motion_ok<3>(Eigen::Vector3d(0.0, 0.0, 0.0), Eigen::Vector3d(0, kInf, 0), 5.0));
  EXPECT_FALSE(sable::motion_ok<2>(Eigen::Vector2d(0.0, 0.0), kNaN, 5.0));
  // Spins are only required finite, tested through their square (so up to ~1e154 rad/s).
  EXPECT_TRUE(sable::motion_ok<2>(Eigen::Vector2d(0.0, 1.0), 1e150, 5.0));
}

// A pair inserted with a 5 % overlap and a sensible dt separates without running away, but the
// overlap exceeds overlap_warning = 1 %: the log says so, once.
TEST(DemBasics, OverlapWarning) {
  const auto cfg = sable::parse_scenario(runaway_scenario("unused", 1e-7, 0.00395), "r.toml");
  sable::RunOptions opt;
  std::ostringstream log;
  opt.log = &log;
  opt.live_progress = false;
  opt.write_outputs = false;
  sable::run_scenario(cfg, opt);
  const std::string text = log.str();
  const auto first = text.find("warning: step");
  ASSERT_NE(first, std::string::npos) << text;
  EXPECT_NE(text.find("overlap_warning = 0.01"), std::string::npos) << text;
  EXPECT_EQ(text.find("warning: step", first + 1), std::string::npos) << "warned more than once";
}

}  // namespace
