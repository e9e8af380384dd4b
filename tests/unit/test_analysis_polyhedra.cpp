// The analyses of polyhedral grains: each list entry's normal, point and depth as the solvers
// store them (world/contact_geometry.hpp), the Sample made from them (analysis/sample.cpp),
// their trip through a snapshot, and `sable analyze` on a run of polyhedra.
//
// A cube of side a and mass m resting face-down on a support carries m g at the centre of its
// bottom face: its contact's point is a / 2 below its centroid, its normal points down, and
// its particle stress (solid fraction 1: the free volume is the cube's) is
// sigma_zz = -(1/V) f_z arm_z = m g (a / 2) / a^3, all other components zero.
#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "polyhedra_helpers.hpp"
#include "run_helpers.hpp"
#include "sable/analysis/coarse_grain.hpp"
#include "sable/analysis/dissipation.hpp"
#include "sable/analysis/sample.hpp"
#include "sable/analysis/stress.hpp"
#include "sable/cd/cd_solver.hpp"
#include "sable/contact/registry.hpp"
#include "sable/core/error.hpp"
#include "sable/dem/dem_solver.hpp"
#include "sable/io/snapshot.hpp"
#include "sable/scenario/config.hpp"
#include "sable/scenario/runner.hpp"
#include "sable/scenario/snapshot_sample.hpp"
#include "sable/world/polyhedral_grains.hpp"
#include "sable/world/state_hash.hpp"

namespace {

namespace fs = std::filesystem;
using Vec = Eigen::Vector3d;

constexpr double kG = 9.81;
constexpr double kA = 0.01;  // the cube's side (m)
constexpr double kRho = 2500.0;
constexpr double kKn = 1e4;  // DEM: N/m per contact point

sable::World<3> rigid_world() {
  sable::World<3> w = sable::test::polyhedra_world(kA, 1e-4);
  w.materials.add({"grain", kRho, 0.0, 0.0, 0.0, 0.5, 0.0});
  w.materials.finalize();
  return w;
}

sable::World<3> soft_world() {
  sable::World<3> w = sable::test::polyhedra_world(kA, 5e-6);
  w.materials.add({"grain", kRho, 1e7, 0.3, 0.2, 0.5, 0.0});
  w.materials.finalize();
  w.model.normal = sable::NormalLaws::id<sable::LinearNormal>();
  w.model.kn = kKn;
  w.model.kt = 0.8 * kKn;
  return w;
}

void add_floor(sable::World<3>& w) {
  sable::Wall<3> wall;
  wall.name = "floor";
  wall.set_plane(Vec::UnitZ());
  w.walls.push_back(wall);
}

// The cube [-a/2, a/2]^2 x [z0, z0 + a].
sable::ParticleId add_cube(sable::World<3>& w, double z0, bool fixed = false) {
  return sable::add_polyhedral_grain(
      w, sable::test::box_points(Vec(-0.5 * kA, -0.5 * kA, z0), Vec(0.5 * kA, 0.5 * kA, z0 + kA)),
      kRho, 0, fixed);
}

sable::CdSettings tight() {
  sable::CdSettings s;
  s.nlgs.tolerance = 1e-11;
  s.nlgs.max_iterations = 100000;
  return s;
}

double cube_stress(double mass) {
  return mass * kG * 0.5 * kA / (kA * kA * kA);
}

// The one contact of a cube resting on the floor, and the cube's particle stress.
void expect_cube_on_floor(const sable::Sample<3>& s, double fn_tol, double depth, double depth_tol,
                          double stress_tol) {
  ASSERT_EQ(s.contacts.size(), 1u);
  const auto& c = s.contacts;
  const double mg = s.mass[0] * kG;
  EXPECT_TRUE(c.is_wall(0));
  EXPECT_NEAR(c.fn[0], mg, fn_tol * mg);
  EXPECT_NEAR((c.n[0] - Vec(0, 0, -1)).norm(), 0.0, 1e-12) << "towards the wall";
  // Under the centroid (a tilt or an uneven share would move it sideways), a / 2 below it.
  EXPECT_NEAR(c.arm_i[0].x(), 0.0, 1e-9 * kA);
  EXPECT_NEAR(c.arm_i[0].y(), 0.0, 1e-9 * kA);
  EXPECT_NEAR(c.arm_i[0].z(), -0.5 * kA, 1e-12 * kA);
  EXPECT_EQ(c.branch[0], c.arm_i[0]);
  EXPECT_NEAR(c.overlap[0], depth, depth_tol);
  EXPECT_DOUBLE_EQ(s.volume[0], kA * kA * kA);
  const sable::ParticleStresses<3> ps = sable::particle_stresses(s, 1.0);
  const double expected = cube_stress(s.mass[0]);
  EXPECT_NEAR(ps.sigma[0](2, 2), expected, stress_tol * expected);
  Eigen::Matrix3d rest = ps.sigma[0];
  rest(2, 2) = 0.0;
  EXPECT_LT(rest.norm(), 1e-6 * expected) << "only sigma_zz: the force and the arm are vertical";
}

// CD: the impulses balance the weight to the solver's 1e-11 with zero moment, so the point
// weighted by the normal impulses is under the centroid; the gap at rest is closed (rounding).
TEST(AnalysisPolyhedra, CdCubeOnFloorActsUnderItsCentroid) {
  sable::World<3> w = rigid_world();
  add_floor(w);
  add_cube(w, 0.0);
  sable::CdSolver<3> solver(w, tight());
  solver.initialize();
  for (int k = 0; k < 20; ++k) solver.step();
  const sable::Sample<3> s = sable::make_sample(w, sable::ForceGeometry::kContactDynamics);
  EXPECT_TRUE(s.polyhedra);
  expect_cube_on_floor(s, 1e-10, 0.0, 1e-12 * kA, 1e-10);
  // Rigid grains at rest: the angular acceleration from the tensor inverse inertia is ~0.
  EXPECT_LT(s.alpha[0].norm(), 1e-6);
}

// DEM: at rest each of the four corner springs sinks m g / (4 k_n); the centre of pressure of
// four equal corners is under the centroid. 1 %: what is left of the settling's oscillation.
TEST(AnalysisPolyhedra, DemCubeOnFloorActsAtItsCentreOfPressure) {
  sable::World<3> w = soft_world();
  add_floor(w);
  add_cube(w, 0.0);
  sable::DemSolver<3> solver(w);
  solver.initialize();
  for (int k = 0; k < 3000; ++k) solver.step();
  const sable::Sample<3> s = sable::make_sample(w);
  const double sink = w.particles.mass[0] * kG / (4.0 * kKn);
  expect_cube_on_floor(s, 0.01, sink, 0.01 * sink, 0.01);
}

// A cube on a fixed cube: the top one is pushed up by m g at a / 2 below its centroid, the
// bottom one down by m g at a / 2 above its own: both carry sigma_zz = m g (a / 2) / a^3
// (the bottom one's support is no contact: it is fixed).
TEST(AnalysisPolyhedra, CubeOnCubeParticleStresses) {
  for (const bool cd : {true, false}) {
    SCOPED_TRACE(cd ? "cd" : "dem");
    sable::World<3> w = cd ? rigid_world() : soft_world();
    add_cube(w, -kA, true);
    add_cube(w, 0.0);
    if (cd) {
      sable::CdSolver<3> solver(w, tight());
      solver.initialize();
      for (int k = 0; k < 20; ++k) solver.step();
    } else {
      sable::DemSolver<3> solver(w);
      solver.initialize();
      for (int k = 0; k < 3000; ++k) solver.step();
    }
    const sable::Sample<3> s = sable::make_sample(
        w, cd ? sable::ForceGeometry::kContactDynamics : sable::ForceGeometry::kSoft);
    ASSERT_EQ(s.contacts.size(), 1u);
    const std::size_t top = w.particles.ids.slot(w.particles.id[1]);
    const std::size_t bottom = 1 - top;
    const auto& c = s.contacts;
    // Both arms reach the same point: on the shared face, under the top cube's centroid.
    EXPECT_NEAR((s.x[c.i[0]] + c.arm_i[0] - s.x[c.j[0]] - c.arm_j[0]).norm(), 0.0, 1e-15);
    EXPECT_NEAR(s.x[c.i[0]].z() + c.arm_i[0].z(), s.x[top].z() - 0.5 * kA, 1e-12 * kA);
    const double tol = cd ? 1e-9 : 0.01;
    const sable::ParticleStresses<3> ps = sable::particle_stresses(s, 1.0);
    const double expected = cube_stress(s.mass[top]);
    EXPECT_NEAR(ps.sigma[top](2, 2), expected, tol * expected);
    EXPECT_NEAR(ps.sigma[bottom](2, 2), expected, tol * expected);
  }
}

// The mean stress of tumbling boxes (DEM): its total is symmetric, to rounding, when every
// grain obeys m a = sum f + m g and Euler's equations about its centroid with the force acting
// at the stored point, and its inertial part holds each grain's own second moment (a box's is
// not isotropic, and a turning box's angular velocity changes without a torque). The contact
// part alone is far from symmetric: the balance is not trivial.
TEST(AnalysisPolyhedra, TumblingBoxesMeanStressIsSymmetric) {
  sable::World<3> w = soft_world();
  add_floor(w);
  const Eigen::Quaterniond q0(Eigen::AngleAxisd(0.6, Vec(1.0, 2.0, 0.5).normalized()));
  const Eigen::Quaterniond q1(Eigen::AngleAxisd(1.1, Vec(-0.3, 1.0, 2.0).normalized()));
  // Two boxes of 1 x 0.6 x 0.4 a: one corner-down onto the floor, one onto the first.
  const Vec lo(-0.5 * kA, -0.3 * kA, -0.2 * kA), hi(0.5 * kA, 0.3 * kA, 0.2 * kA);
  auto box = [&](const Eigen::Quaterniond& q, const Vec& at) {
    std::vector<Vec> v = sable::test::box_points(lo, hi, q);
    double bottom = 1e300;
    for (const Vec& c : v) bottom = std::min(bottom, c.z());
    for (Vec& c : v) c += at - Vec(0, 0, bottom);
    return v;
  };
  const std::vector<Vec> bottom = box(q0, Vec(0, 0, -1e-5));
  sable::add_polyhedral_grain(w, bottom, kRho, 0);
  // The second box's lowest corner above the first's centroid, level with its highest corner:
  // it falls onto the first's upper face or edge.
  double top_z = -1e300;
  for (const Vec& c : bottom) top_z = std::max(top_z, c.z());
  const Vec above(w.particles.x[0].x(), w.particles.x[0].y(), top_z);
  const auto top = sable::add_polyhedral_grain(w, box(q1, above), kRho, 0);
  w.particles.v[w.particles.ids.slot(top)] = Vec(0, 0, -0.3);
  w.particles.omega[0] = Vec(20.0, -10.0, 5.0);
  sable::DemSolver<3> solver(w);
  solver.initialize();
  std::size_t touching = 0;
  for (int k = 0; k < 20000 && touching < 2; ++k) {
    solver.step();
    touching = sable::make_sample(w).contacts.size();
  }
  const sable::Sample<3> s = sable::make_sample(w);
  ASSERT_EQ(s.contacts.size(), 2u) << "the floor's contact and the boxes' one";
  ASSERT_GT(s.omega[0].norm() * s.omega[1].norm(), 0.0) << "both turning";
  for (double d : s.contacts.overlap) EXPECT_LT(d, 0.01 * kA) << "a contact, not a collision";
  sable::Region<3> region;
  region.lo = Vec::Constant(-0.1);
  region.hi = Vec::Constant(0.1);
  const sable::MeanStress<3> m = sable::mean_stress(s, region);
  EXPECT_LT(sable::asymmetry<3>(m.total()), 1e-9);
  EXPECT_GT(sable::asymmetry<3>(m.contact), 1e-3);
}

// A snapshot keeps each entry's normal, point and depth to the bit; they stay out of the state
// hash (the load checks the hash as written).
TEST(AnalysisPolyhedra, SnapshotKeepsTheContactGeometry) {
  const fs::path path = fs::temp_directory_path() /
                        ("sable_analysis_polyhedra_" + std::to_string(::getpid()) + ".h5");
  sable::World<3> a = rigid_world();
  add_floor(a);
  add_cube(a, 0.0);
  add_cube(a, kA);
  sable::CdSolver<3> solver(a, tight());
  solver.initialize();
  for (int k = 0; k < 20; ++k) solver.step();
  ASSERT_EQ(a.contact_geometry.pairs.size(), a.neighbors.pairs.size());
  ASSERT_GE(a.neighbors.pairs.size(), 1u);
  ASSERT_GE(a.neighbors.wall_pairs.size(), 1u);
  sable::save_snapshot(a, {}, "scenario", path.string());
  sable::World<3> b = rigid_world();
  add_floor(b);
  sable::load_snapshot(path.string(), b);
  const auto same = [](const sable::EntryGeometry<3>& x, const sable::EntryGeometry<3>& y) {
    ASSERT_EQ(x.size(), y.size());
    for (std::size_t k = 0; k < x.size(); ++k) {
      EXPECT_EQ(x.normal[k], y.normal[k]) << k;
      EXPECT_EQ(x.arm[k], y.arm[k]) << k;
      EXPECT_EQ(x.depth[k], y.depth[k]) << k;
    }
  };
  same(a.contact_geometry.pairs, b.contact_geometry.pairs);
  same(a.contact_geometry.wall_pairs, b.contact_geometry.wall_pairs);
  // Not hashed: clearing it leaves the state's hash as it was.
  const std::uint64_t h = sable::state_hash(a);
  a.contact_geometry.clear();
  EXPECT_EQ(sable::state_hash(a), h);
  // A World whose contacts carry forces but no geometry cannot be analysed: said so.
  EXPECT_THROW(sable::make_sample(a), sable::InputError);
  fs::remove(path);
}

// The analyses that cannot hold for polyhedra refuse, naming themselves.
TEST(AnalysisPolyhedra, RefusedAnalysesSaySo) {
  sable::World<3> w = soft_world();
  add_floor(w);
  add_cube(w, 0.0);
  sable::DemSolver<3> solver(w);
  solver.initialize();
  for (int k = 0; k < 10; ++k) solver.step();
  const sable::Sample<3> s = sable::make_sample(w);
  try {
    (void)sable::power_budget(s);
    ADD_FAILURE() << "the dissipation analysis ran on polyhedra";
  } catch (const sable::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("dissipation"), std::string::npos) << e.what();
  }
  sable::FieldSpec<3> spec;
  spec.kernel = sable::CgKernel::Sphere;
  spec.width = kA;
  spec.cells = {2, 2, 2};
  spec.box.lo = Vec::Constant(-kA);
  spec.box.hi = Vec::Constant(kA);
  EXPECT_THROW((void)sable::coarse_grain(s, spec), sable::InputError);
  spec.kernel = sable::CgKernel::Gaussian;
  EXPECT_NO_THROW((void)sable::coarse_grain(s, spec));
}

// `sable analyze` on the end of tests/data/polyhedra_fall.toml's run (48 polyhedra settled by
// contact dynamics in a box): it completes, skipping (and listing) what polyhedra refuse, and
// refuses them with their reason when asked for by name. The sample it reads holds, exactly:
//  - every floor contact's point on the floor: the impulse-weighted centre of grain vertices
//    whose heights are their gaps, so between the deepest one (-depth) and the highest kept,
//    within the step's reach (far below the grains' 0.8 mm), with the normal straight down;
//  - Newton for the grains together (the pairs' forces cancel): the walls' forces on the grains
//    plus the weight equal the sum of m a, to rounding.
TEST(AnalysisPolyhedra, AnalyzeARunOfPolyhedra) {
  const fs::path dir =
      fs::temp_directory_path() / ("sable_analyze_polyhedra_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  sable::RunOptions opt;
  std::ostringstream log;
  opt.log = &log;
  opt.live_progress = false;
  opt.out_dir = (dir / "run").string();
  sable::run_scenario(sable::load_scenario(std::string(SABLE_TEST_DATA) + "/polyhedra_fall.toml"),
                      opt);
  const fs::path snap = dir / "run" / "snapshots" / "end_of_stage_2.h5";
  ASSERT_TRUE(fs::exists(snap));

  const sable::Sample<3> s = sable::load_sample<3>(snap.string());
  ASSERT_TRUE(s.polyhedra);
  ASSERT_GT(s.contacts.size(), 48u) << "a settled heap: more contacts than grains";
  Vec wall_force = Vec::Zero(), momentum_rate = Vec::Zero();
  std::size_t on_floor = 0;
  const auto& c = s.contacts;
  for (std::size_t k = 0; k < c.size(); ++k) {
    if (!c.is_wall(k)) continue;
    wall_force += c.force[k];
    if (std::abs(c.n[k].z() + 1.0) > 1e-12) continue;  // a side wall
    ++on_floor;
    const double z = c.point(k, s.x).z();
    EXPECT_GE(z, -c.overlap[k] - 1e-15) << k;
    EXPECT_LE(z, 1e-5) << k;
  }
  EXPECT_GT(on_floor, 0u);
  for (std::size_t g = 0; g < s.size(); ++g) momentum_rate += s.mass[g] * s.a[g];
  const double weight = s.total_mass() * kG;
  EXPECT_LT((wall_force + s.total_mass() * s.gravity - momentum_rate).norm(), 1e-9 * weight);

  std::string out;
  const std::string an = " --out " + (dir / "an").string();
  ASSERT_EQ(sable::test::run_cli("analyze " + snap.string() + an, dir / "log.txt", out), 0) << out;
  const std::string summary = sable::test::slurp(dir / "an" / "summary.json");
  for (const char* key : {"\"stress\"", "\"particle_stress\"", "\"skipped_dissipation\""})
    EXPECT_NE(summary.find(key), std::string::npos) << key;
  EXPECT_TRUE(fs::exists(dir / "an" / "particle_stress.csv"));
  EXPECT_FALSE(fs::exists(dir / "an" / "dissipation.csv"));
  const struct {
    std::string args, expect;
  } refused[] = {{" --only dissipation", "dissipation analysis does not apply"},
                 {" --only fields --grid 2x2x4", "sphere kernel"}};
  for (const auto& r : refused) {
    EXPECT_EQ(sable::test::run_cli("analyze " + snap.string() + an + r.args, dir / "log.txt", out),
              2)
        << out;
    EXPECT_NE(out.find(r.expect), std::string::npos) << out;
  }
  EXPECT_EQ(sable::test::run_cli(
                "analyze " + snap.string() + an + " --only fields --grid 2x2x4 --kernel gaussian",
                dir / "log.txt", out),
            0)
      << out;
  fs::remove_all(dir);
}

}  // namespace
