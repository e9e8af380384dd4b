// Stresses from contacts: particle stresses, Love-Weber, the mean stress with gravity and
// inertia (Dumont-Fortin-Ouafik 2010 eq. 16), wall profiles, the rotating frame, and what the
// analysis does with bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>

#include "run_helpers.hpp"
#include "sable/analysis/coarse_grain.hpp"
#include "sable/analysis/frame.hpp"
#include "sable/analysis/report.hpp"
#include "sable/analysis/sample.hpp"
#include "sable/analysis/stress.hpp"
#include "sable/analysis/wall_stress.hpp"
#include "sable/core/error.hpp"
#include "sable/scenario/snapshot_sample.hpp"

namespace fs = std::filesystem;
using namespace sable;

namespace {

fs::path temp_dir(const std::string& name) {
  fs::path p = fs::temp_directory_path() / ("sable_test_stress_" + name);
  fs::remove_all(p);
  fs::create_directories(p);
  return p;
}

double uniform(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

// A hand-made 3D sample: grains at random places, random contacts between random pairs with
// random forces and lever arms, some at walls. The identities tested below are algebraic:
// they must hold for any forces, balanced or not.
Sample<3> random_sample(std::size_t n, std::size_t contacts, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  Sample<3> s;
  for (std::size_t g = 0; g < n; ++g) {
    s.x.emplace_back(uniform(rng), uniform(rng), uniform(rng));
    s.radius.push_back(0.02 + 0.02 * uniform(rng));
    s.volume.push_back(4.0 / 3.0 * M_PI * std::pow(s.radius.back(), 3));
    s.mass.push_back(2500.0 * s.volume.back());
    s.inertia.push_back(0.4 * s.mass.back() * s.radius.back() * s.radius.back());
    s.v.emplace_back(Eigen::Vector3d::Zero());
    s.a.emplace_back(Eigen::Vector3d::Zero());
    s.omega.emplace_back(Eigen::Vector3d::Zero());
    s.alpha.emplace_back(Eigen::Vector3d::Zero());
    s.fixed.push_back(0);
    s.id.push_back(static_cast<std::uint32_t>(g));
  }
  auto rvec = [&] {
    return Eigen::Vector3d(uniform(rng) - 0.5, uniform(rng) - 0.5, uniform(rng) - 0.5);
  };
  for (std::size_t k = 0; k < contacts; ++k) {
    const auto i = static_cast<std::uint32_t>(rng() % n);
    auto j = static_cast<std::uint32_t>(rng() % n);
    const bool wall = k % 5 == 0;
    if (!wall && j == i) j = (i + 1) % static_cast<std::uint32_t>(n);
    const Eigen::Vector3d nrm = rvec().normalized();
    const Eigen::Vector3d ai = 0.02 * rvec(), aj = wall ? Eigen::Vector3d(Eigen::Vector3d::Zero())
                                                        : Eigen::Vector3d(0.02 * rvec());
    s.contacts.push(i, wall ? 0 : j, wall, nrm, rvec(), ai, aj,
                    wall ? ai : Eigen::Vector3d(ai - aj), 0.0, 0.5);
  }
  s.walls.push_back({"floor", true, {}, {0, 0, 1}, {}});
  s.source = "random sample";
  return s;
}

// Love-Weber over a region cutting through the sample equals the free-volume-weighted sum of
// the particle stresses of the grains inside (Richefeu et al. 2009, after eq. 12): the two are
// computed by different loops (per contact vs per grain), so this checks both.
TEST(AnalysisStress, LoveWeberIsTheVolumeWeightedSumOfParticleStresses) {
  const Sample<3> s = random_sample(60, 300, 11);
  Region<3> region;
  region.lo = Eigen::Vector3d(0.1, 0.2, 0.0);
  region.hi = Eigen::Vector3d(0.7, 0.9, 0.8);
  const ParticleStresses<3> ps = particle_stresses(s, 0.6);
  Tensor<3> sum = Tensor<3>::Zero();
  for (std::size_t g = 0; g < s.size(); ++g)
    if (region.contains(s.x[g])) sum += ps.free_volume[g] * ps.sigma[g];
  sum /= region.volume(1.0);
  const Tensor<3> lw = love_weber(s, region);
  // Same sums in another order: equal to round-off (1e-12 of the tensor's size).
  EXPECT_LT((sum - lw).norm(), 1e-12 * lw.norm());
  EXPECT_GT(lw.norm(), 0.0);
}

// Particle stress of a single grain squeezed by two opposite forces F along x at its poles:
// sigma_xx = 2 F r / V_i (compression positive), all else 0; p = sigma_xx / 3.
TEST(AnalysisStress, ParticleStressOfASqueezedGrain) {
  Sample<3> s = random_sample(2, 0, 1);
  s.x[0] = Eigen::Vector3d::Zero();
  const double r = s.radius[0], f = 7.0;
  const Eigen::Vector3d ex = Eigen::Vector3d::UnitX();
  // Partner 1 pushes from +x (n towards it = +x, force on 0 = -f ex), the wall from -x.
  s.contacts.push(0, 1, false, ex, -f * ex, r * ex, -r * ex, 2 * r * ex, 0.0, 0.5);
  s.contacts.push(0, 0, true, -ex, f * ex, -r * ex, Eigen::Vector3d::Zero(), -r * ex, 0.0, 0.5);
  const ParticleStresses<3> ps = particle_stresses(s, 0.5);
  const double v = s.volume[0] / 0.5;
  EXPECT_NEAR(ps.sigma[0](0, 0), 2 * f * r / v, 1e-12 * f * r / v);  // exact arithmetic
  EXPECT_NEAR(ps.pressure[0], 2 * f * r / v / 3.0, 1e-12 * f * r / v);
  EXPECT_NEAR(ps.sigma[0](1, 1), 0.0, 1e-15);
}

// Wall profile on hand-made contacts: two bins, known forces -> stresses by hand.
TEST(AnalysisStress, WallProfileByHand) {
  Sample<2> s;
  s.thickness = 0.01;
  s.gravity = Eigen::Vector2d(0, -9.81);
  for (double y : {0.5, 1.5, 1.7}) {
    s.x.emplace_back(0.1, y);
    s.radius.push_back(0.1);
  }
  s.walls.push_back({"left", true, {0, 0, 0}, {1, 0, 0}, {}});
  s.walls.push_back({"right", true, {1, 0, 0}, {-1, 0, 0}, {}});
  s.source = "hand";
  const Eigen::Vector2d n(-1, 0), arm(-0.1, 0), z = Eigen::Vector2d::Zero();
  // Force on the grain: pushed along +x by fn, held up by the wall's friction ft.
  s.contacts.push(0, 0, true, n, Eigen::Vector2d(4.0, 1.0), arm, z, arm, 0.0, 0.25);
  s.contacts.push(1, 0, true, n, Eigen::Vector2d(2.0, 0.5), arm, z, arm, 0.0, 0.25);
  s.contacts.push(2, 0, true, n, Eigen::Vector2d(6.0, -0.5), arm, z, arm, 0.0, 0.25);
  s.contacts.push(2, 1, true, -n, Eigen::Vector2d(-9.0, 0.0), -arm, z, -arm, 0.0, 0.25);
  WallProfileOptions opt;
  opt.bin = 1.0;
  const WallProfile p = wall_profile(s, "left", opt);
  ASSERT_EQ(p.height.size(), 2u);  // grains span y in [0.4, 1.8]: two bins of 1
  const double area = 1.0 * 0.01;
  EXPECT_DOUBLE_EQ(p.sigma_n[0], 4.0 / area);
  EXPECT_DOUBLE_EQ(p.sigma_n[1], 8.0 / area);
  EXPECT_DOUBLE_EQ(p.tau[0], 1.0 / area);
  EXPECT_DOUBLE_EQ(p.tau[1], 0.0);
  EXPECT_DOUBLE_EQ(p.mobilisation[0], 1.0);  // |ft| = mu fn exactly: on the Coulomb cone
  EXPECT_DOUBLE_EQ(p.mobilisation[1], 1.0 / (0.25 * 8.0));
  EXPECT_EQ(p.contacts[1], 2u);
  EXPECT_DOUBLE_EQ(p.total_normal, 12.0);
  EXPECT_NEAR(p.depth[0], 1.8 - 0.4 - 0.5, 1e-12);  // from the top grain's top, at bin centre
  EXPECT_THROW(wall_profile(s, "roof", opt), InputError);
}

// A rigid motion turning with the frame is seen at rest: positions back where they were at
// t0, velocities zero, forces and arms turned back (3D about a tilted axis, and 2D).
TEST(AnalysisStress, RotatingFrameUndoesARigidRotation) {
  Sample<3> s0 = random_sample(20, 40, 3);
  RotatingFrame f;
  f.point = Eigen::Vector3d(0.3, 0.2, 0.1);
  f.axis = Eigen::Vector3d(0.2, -0.1, 1.0);
  f.omega = 2.5;
  const Eigen::Vector3d u = f.axis.normalized();
  for (double t : {0.0, 0.4, 1.3}) {
    const Eigen::Matrix3d r = Eigen::AngleAxisd(f.omega * t, u).toRotationMatrix();
    Sample<3> s = s0;
    s.time = t;
    for (std::size_t g = 0; g < s.size(); ++g) {
      s.x[g] = f.point + r * (s0.x[g] - f.point);
      s.v[g] = (f.omega * u).cross(s.x[g] - f.point);
      s.omega[g] = f.omega * u;
    }
    for (std::size_t k = 0; k < s.contacts.size(); ++k)
      s.contacts.force[k] = r * s0.contacts.force[k];
    const Sample<3> back = to_rotating_frame(s, f);
    for (std::size_t g = 0; g < s.size(); ++g) {
      EXPECT_LT((back.x[g] - s0.x[g]).norm(), 1e-14);  // a few rotations' round-off at |x| ~ 1
      EXPECT_LT(back.v[g].norm(), 1e-14);
      EXPECT_LT(back.omega[g].norm(), 1e-14);
    }
    for (std::size_t k = 0; k < s.contacts.size(); ++k)
      EXPECT_LT((back.contacts.force[k] - s0.contacts.force[k]).norm(), 1e-14);
  }
  Sample<2> s2;
  s2.x.emplace_back(1.0, 0.0);
  s2.v.emplace_back(0.0, 2.0);
  s2.a.emplace_back(-4.0, 0.0);
  s2.omega.push_back(2.0);
  s2.alpha.push_back(0.0);
  s2.time = 0.25 * M_PI;  // a quarter turn at omega = 2 takes (1, 0) to (0, 1)
  s2.x[0] = Eigen::Vector2d(0.0, 1.0);
  s2.v[0] = Eigen::Vector2d(-2.0, 0.0);
  RotatingFrame f2;
  f2.omega = 2.0;
  const Sample<2> b2 = to_rotating_frame(s2, f2);
  EXPECT_LT((b2.x[0] - Eigen::Vector2d(1.0, 0.0)).norm(), 1e-15);
  EXPECT_LT(b2.v[0].norm(), 1e-15);
  f2.axis = Eigen::Vector3d::UnitX();
  EXPECT_THROW(to_rotating_frame(s2, f2), InputError);  // 2D turns about z only
}

// Guillard et al. average their fields in the frame turning with the cylinder: a packing that
// turns rigidly with the frame must average, in that frame, to its own field at t0. Gaussian
// kernel (smooth: round-off in the positions moves the weights by round-off only).
TEST(AnalysisStress, RotatingFrameAverageOfACorotatingFieldIsTheField) {
  const Sample<3> s0 = random_sample(40, 80, 9);
  RotatingFrame f;
  f.point = Eigen::Vector3d(0.5, 0.5, 0.5);
  f.axis = Eigen::Vector3d::UnitZ();
  f.omega = 1.7;
  FieldSpec<3> spec;
  spec.kernel = CgKernel::Gaussian;
  spec.width = 0.15;
  spec.cells = {4, 4, 4};
  spec.box.lo = Eigen::Vector3d::Zero();
  spec.box.hi = Eigen::Vector3d::Ones();
  const Fields<3> reference = coarse_grain(s0, spec);
  Fields<3> sum;
  for (double t : {0.3, 1.1, 2.9, 4.0}) {
    const Eigen::Matrix3d r = Eigen::AngleAxisd(f.omega * t, f.axis).toRotationMatrix();
    Sample<3> s = s0;
    s.time = t;
    for (std::size_t g = 0; g < s.size(); ++g) {
      s.x[g] = f.point + r * (s0.x[g] - f.point);
      s.v[g] = (f.omega * f.axis).cross(s.x[g] - f.point);  // turning with the frame
    }
    for (std::size_t k = 0; k < s.contacts.size(); ++k) {
      s.contacts.force[k] = r * s0.contacts.force[k];
      s.contacts.arm_i[k] = r * s0.contacts.arm_i[k];
      s.contacts.arm_j[k] = r * s0.contacts.arm_j[k];
      s.contacts.branch[k] = r * s0.contacts.branch[k];
    }
    accumulate(sum, coarse_grain(to_rotating_frame(s, f), spec));
  }
  ASSERT_EQ(sum.snapshots, 4);
  average(sum);
  double rho_max = 0.0, sigma_max = 0.0;
  for (std::size_t k = 0; k < reference.size(); ++k) {
    rho_max = std::max(rho_max, reference.density[k]);
    sigma_max = std::max(sigma_max, reference.stress[k].norm());
  }
  ASSERT_GT(sigma_max, 0.0);
  for (std::size_t k = 0; k < reference.size(); ++k) {
    // Round-off of rotating forth and back: 1e-12 of the field's largest value.
    EXPECT_NEAR(sum.density[k], reference.density[k], 1e-12 * rho_max);
    EXPECT_LT((sum.stress[k] - reference.stress[k]).norm(), 1e-12 * sigma_max);
  }
}

// Bad snapshots: missing, truncated, not a snapshot at all, the other dimension. Each gives an
// InputError naming the file; and a result is never written over an input.
TEST(AnalysisStress, BadInputIsRefusedClearly) {
  const fs::path dir = temp_dir("bad");
  auto message = [](const std::function<void()>& f) {
    try {
      f();
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string missing = (dir / "missing.h5").string();
  EXPECT_NE(message([&] { load_sample<3>(missing); }).find("missing.h5"), std::string::npos);
  const std::string foreign = (dir / "foreign.h5").string();
  std::ofstream(foreign) << "this is not HDF5\n";
  EXPECT_NE(message([&] { load_sample<3>(foreign); }).find("foreign.h5"), std::string::npos);
  // A real snapshot, truncated to half its size.
  sable::test::run_text(sable::test::small_pour_2d((dir / "run").string(), "dem"));
  const fs::path snap = dir / "run" / "snapshots" / "end_of_stage_1.h5";
  EXPECT_NE(message([&] { load_sample<3>(snap.string()); }).find("2D snapshot"), std::string::npos);
  const fs::path cut = dir / "cut.h5";
  fs::copy_file(snap, cut);
  fs::resize_file(cut, fs::file_size(cut) / 2);
  EXPECT_NE(message([&] { load_sample<2>(cut.string()); }).find("cut.h5"), std::string::npos);
  // An empty region and a region with no grains.
  const Sample<2> s = load_sample<2>(snap.string());
  Region<2> far;
  far.lo = Eigen::Vector2d(10, 10);
  far.hi = Eigen::Vector2d(11, 11);
  EXPECT_NE(message([&] { mean_stress(s, far); }).find("no grain"), std::string::npos);
  EXPECT_NE(message([&] { love_weber(s, far); }).find("region"), std::string::npos);
  // Never overwrite the snapshot being analysed; the snapshot is unchanged afterwards.
  const auto size = fs::file_size(snap);
  const ResultWriter out((dir / "run" / "snapshots").string(), {snap.string()});
  EXPECT_NE(message([&] { out.write("end_of_stage_1.h5", std::string("x")); }).find("refusing"),
            std::string::npos);
  EXPECT_EQ(fs::file_size(snap), size);
  fs::remove_all(dir);
}

}  // namespace
