// The mean stress tensor with gravity and inertia terms (Dumont-Fortin-Ouafik 2010 eq. 16;
// de Saxce, Fortin & Millet 2004) on real DEM and CD runs: symmetric whether the grains flow
// or rest, independent of the reference point; the contact part alone is neither.
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>

#include "../unit/run_helpers.hpp"
#include "sable/analysis/sample.hpp"
#include "sable/analysis/stress.hpp"
#include "sable/scenario/snapshot_sample.hpp"

namespace fs = std::filesystem;
using namespace sable;

namespace {

fs::path temp_dir(const std::string& name) {
  fs::path p = fs::temp_directory_path() / ("sable_test_mean_stress_" + name);
  fs::remove_all(p);
  fs::create_directories(p);
  return p;
}

// Dumont-Fortin-Ouafik eq. 16: with the gravity and inertia terms the mean stress is
// symmetric (each grain obeys m a = sum f + m g and I alpha = torque), in a flowing packing
// (end of the fall stage: grains still moving) and a settled one; the contact part alone is
// not (the floor's reactions act at the bottom, gravity at the centres). Both solvers to
// round-off: DEM integrates m a = f + m g with the stored forces, and CD's end velocities are
// made from its impulses in the start-of-step configuration that the CD sample restores.
TEST(AnalysisStress, MeanStressWithBodyForcesIsSymmetric) {
  for (const std::string solver : {"dem", "cd"}) {
    const fs::path dir = temp_dir("mean_" + solver);
    sable::test::run_text(sable::test::small_pour_2d(dir.string(), solver));
    for (const char* stage : {"end_of_stage_1.h5", "end_of_stage_2.h5"}) {
      SCOPED_TRACE(solver + " " + stage);
      const Sample<2> s = load_sample<2>((dir / "snapshots" / stage).string());
      const MeanStress<2> m = mean_stress(s, grain_bounds(s));
      EXPECT_GT(m.grains, 100u);
      EXPECT_GT(asymmetry<2>(m.contact), 0.02);  // the contact part alone: clearly not symmetric
      EXPECT_LT(asymmetry<2>(m.total()), 1e-9);
    }
    fs::remove_all(dir);
  }
}

// The total does not depend on the reference point x0 (each grain's forces balance, so the
// x0 terms cancel grain by grain), while the contact part alone does.
TEST(AnalysisStress, MeanStressIsIndependentOfTheReferencePoint) {
  const fs::path dir = temp_dir("origin");
  sable::test::run_text(sable::test::small_pour_2d(dir.string(), "dem"));
  const Sample<2> s = load_sample<2>((dir / "snapshots" / "end_of_stage_1.h5").string());
  const Region<2> box = grain_bounds(s);
  const MeanStress<2> ma = mean_stress(s, box), mb = mean_stress(s, box, {0.5, -0.25});
  EXPECT_LT((ma.total() - mb.total()).norm(), 1e-9 * ma.total().norm());  // round-off, 120 grains
  EXPECT_GT((ma.contact - mb.contact).norm(), 0.1 * ma.total().norm());
  fs::remove_all(dir);
}

}  // namespace
