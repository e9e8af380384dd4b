// `sable analyze` end to end: every analysis runs on a DEM and a CD snapshot and writes its
// numbers (and, with --plot, its figures); bad input gets exit status 2 and a message naming
// the file or the option, and the analysed snapshot is never touched.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <Eigen/Core>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "run_helpers.hpp"
#include "sable/io/snapshot.hpp"

namespace fs = std::filesystem;

namespace {

fs::path temp_dir(const std::string& name) {
  fs::path p = fs::temp_directory_path() / ("sable_test_analyze_" + name);
  fs::remove_all(p);
  fs::create_directories(p);
  return p;
}

std::string read(const fs::path& p) {
  return sable::test::slurp(p);
}

// A small 3D box of grains settling under gravity (DEM or CD), snapshots at the stage ends.
std::string small_run(const std::string& solver, const std::string& out) {
  const bool cd = solver == "cd";
  std::ostringstream s;
  s << "[simulation]\ndimension = 3\nseed = 2\nsolver = \"" << solver << "\"\n"
    << (cd ? "dt = 2e-4\n" : "") << "gravity = [0, 0, -9.81]\n"
    << "[domain]\nlo = [0, 0, 0]\nhi = [0.012, 0.012, 0.03]\n"
    << "[[material]]\nname = \"g\"\ndensity = 2500.0\nyoung = 5e6\npoisson = 0.45\n"
    << "restitution = 0.3\nfriction = 0.4\n"
    << (cd ? "[cd]\ntolerance = 1e-5\nmax_iterations = 300\n" : "")
    << "[[grains]]\ngenerator = \"random\"\nmaterial = \"g\"\n"
    << "radius = { distribution = \"uniform\", mean = 1e-3, spread = 0.2 }\n"
    << "region = { box = { lo = [0, 0, 0], hi = [0.012, 0.012, 0.03] } }\ncount = 60\n"
    << "[[wall]]\nname = \"box\"\ntype = \"box\"\nmaterial = \"g\"\nlo = [0, 0, 0]\n"
    << "hi = [0.012, 0.012, 0.03]\n"
    << "[[stage]]\nname = \"fall\"\nsteps = " << (cd ? 300 : 3000) << "\n"
    << "[output]\ndir = \"" << out
    << "\"\ncsv_interval = 0\nsnapshot_interval = " << (cd ? 100 : 1000)
    << "\nvtk_interval = 0\nlog_interval = 0\n";
  return s.str();
}

// contacts.csv's contact point (x_c_m, y_c_m, z_c_m) for round grains: on the segment between
// the two centres for a grain pair (their distances to it add up to the centres' distance, to
// 1e-12 relative: rounding of a few additions), the wall's contact point for a wall row. Returns
// the grain-pair rows checked.
int check_contact_points(const fs::path& csv) {
  auto c = sable::test::read_csv_columns(csv);
  for (const char* name : {"wall", "x_i_m", "x_end_m", "x_c_m"})
    EXPECT_EQ(c.count(name), 1u) << name;
  const auto at = [&](const char* x, const char* y, const char* z, std::size_t k) {
    return Eigen::Vector3d(c[x][k], c[y][k], c[z][k]);
  };
  int pairs = 0;
  for (std::size_t k = 0; k < c["wall"].size(); ++k) {
    const Eigen::Vector3d a = at("x_i_m", "y_i_m", "z_i_m", k),
                          e = at("x_end_m", "y_end_m", "z_end_m", k),
                          p = at("x_c_m", "y_c_m", "z_c_m", k);
    if (c["wall"][k] != 0.0) {
      EXPECT_LE((p - e).norm(), 1e-15) << "row " << k;
      continue;
    }
    ++pairs;
    EXPECT_NEAR((p - a).norm() + (e - p).norm(), (e - a).norm(), 1e-12 * (e - a).norm())
        << "row " << k;
  }
  return pairs;
}

// Both solvers: every analysis writes its table and figure; the summary has each section.
TEST(AnalyzeCli, EveryAnalysisWritesNumbersAndFigures) {
  for (const std::string solver : {"dem", "cd"}) {
    SCOPED_TRACE(solver);
    const fs::path dir = temp_dir(solver);
    sable::test::run_text(small_run(solver, (dir / "run").string()));
    const fs::path snap = dir / "run" / "snapshots" / "end_of_stage_1.h5";
    const auto before = read(snap);
    std::string out;
    const int rc = sable::test::run_cli(
        "analyze " + snap.string() + " --out " + (dir / "an").string() + " --grid 3x3x6 --plot",
        dir / "log.txt", out);
    ASSERT_EQ(rc, 0) << out;
    for (const char* f : {"summary.json",
                          "force_pdf_compressive.csv",
                          "force_pdf_tangential.csv",
                          "coordination.csv",
                          "fabric.csv",
                          "fabric_azimuth.csv",
                          "polarization_bulk.csv",
                          "polarization_walls.csv",
                          "particle_stress.csv",
                          "pressure_pdf.csv",
                          "wall_profile_box_xlo.csv",
                          "percolation.csv",
                          "fields.vti",
                          "fields.csv",
                          "force_pdf_compressive.png",
                          "pressure_pdf.png",
                          "fields.png",
                          "wall_profile_box_xlo.png",
                          "polarization_bulk.png",
                          "fabric.png",
                          "percolation.png",
                          "coordination.png"})
      EXPECT_TRUE(fs::exists(dir / "an" / f)) << f << "\n" << out;
    const std::string summary = read(dir / "an" / "summary.json");
    for (const char* key : {"\"forces\"", "\"coordination\"", "\"fabric\"", "\"polarization\"",
                            "\"particle_stress\"", "\"stress\"", "\"walls\"", "\"percolation\"",
                            "\"fields\"", "\"beta_mle\"", "\"love_weber\""})
      EXPECT_NE(summary.find(key), std::string::npos) << key;
    EXPECT_GT(check_contact_points(dir / "an" / "contacts.csv"), 5);  // 8 by DEM, 16 by CD
    EXPECT_EQ(read(snap), before);  // the analysed snapshot is untouched
    // Several snapshots: averaged, with a per-snapshot series.
    const std::string all = (dir / "run" / "snapshots" / "step_*.h5").string();
    ASSERT_EQ(sable::test::run_cli("analyze " + all + " --only stress,coordination,fields --out " +
                                       (dir / "avg").string(),
                                   dir / "log2.txt", out),
              0)
        << out;
    EXPECT_TRUE(fs::exists(dir / "avg" / "series.csv"));
    EXPECT_NE(read(dir / "avg" / "summary.json").find("\"inputs\": 3"), std::string::npos);
    fs::remove_all(dir);
  }
}

// Bad input: exit status 2 and a message that names the file or the option.
TEST(AnalyzeCli, BadInputNamesTheProblem) {
  const fs::path dir = temp_dir("bad");
  sable::test::run_text(small_run("dem", (dir / "run").string()));
  const std::string snap = (dir / "run" / "snapshots" / "end_of_stage_1.h5").string();
  const std::string out = " --out " + (dir / "an").string();
  struct Case {
    std::string args, expect;
  };
  std::ofstream(dir / "foreign.h5") << "not a snapshot";
  fs::copy_file(snap, dir / "cut.h5");
  fs::resize_file(dir / "cut.h5", fs::file_size(dir / "cut.h5") / 3);
  const Case cases[] = {
      {(dir / "missing.h5").string() + out, "missing.h5"},
      {(dir / "foreign.h5").string() + out, "foreign.h5"},
      {(dir / "cut.h5").string() + out, "cut.h5"},
      {snap + out + " --only fields --grid 0x3x3", "cells"},
      {snap + out + " --only fields --grid 3x3", "--grid"},
      {snap + out + " --only fields --width -1", "--width"},
      {snap + out + " --only fields --kernel boxcar", "boxcar"},
      {snap + out + " --region 0,0,0:0,1,1", "--region"},
      {snap + out + " --region 1,1,1:2,2,2 --only stress", "region"},
      {snap + out + " --only nonsense", "nonsense"},
      {snap + out + " --eps 1.5", "--eps"},
      {snap + out + " --walls roof", "roof"},
      {snap + " --out " + (dir / "run" / "snapshots").string() + " --only stress", ""},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.args);
    std::string output;
    const int rc = sable::test::run_cli("analyze " + c.args, dir / "log.txt", output);
    if (c.expect.empty()) {
      EXPECT_EQ(rc, 0) << output;  // writing beside the snapshot is fine: other names
      continue;
    }
    EXPECT_EQ(rc, 2) << output;
    EXPECT_NE(output.find(c.expect), std::string::npos) << output;
  }
  // The snapshot still reads after all this.
  EXPECT_NO_THROW(sable::read_snapshot_info(snap));
  fs::remove_all(dir);
}

}  // namespace
