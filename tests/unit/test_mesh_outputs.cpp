// What the outputs say about walls' loads, turning meshes included: the walls .vtp of a mesh
// wall (one cell per element at its turned pose, the element forces summing to the wall's
// force), the torque columns of a run's series.csv, and the wall loads of `sable analyze`.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "mesh_world.hpp"
#include "run_helpers.hpp"
#include "sable/analysis/analyze.hpp"
#include "sable/analysis/sample.hpp"
#include "sable/io/snapshot.hpp"
#include "sable/io/vtk.hpp"
#include "sable/scenario/build.hpp"
#include "sable/scenario/config.hpp"
#include "sable/world/element_forces.hpp"

namespace {

namespace fs = std::filesystem;
using sable::World;
using sable::test::kPaddle;

class MeshOutputs : public sable::test::TempDirTest {};

// The numbers of the DataArray named `name` in a VTK XML file written in ASCII.
std::vector<double> vtk_array(const std::string& text, const std::string& name) {
  const auto at = text.find("Name=\"" + name + "\"");
  if (at == std::string::npos) {
    ADD_FAILURE() << "no DataArray " << name;
    return {};
  }
  const auto begin = text.find('>', at) + 1;
  const auto end = text.find("</DataArray>", begin);
  std::istringstream in(text.substr(begin, end - begin));
  std::vector<double> out;
  for (double v; in >> v;) out.push_back(v);
  return out;
}

// The .vtp's cells of the paddle: each has its three points at the paddle's vertices turned
// by the angle the run turned it through, and its cell_force is the element's force; these sum
// to the paddle's force (to the file's 9 significant digits; in memory to 1e-12).
TEST_F(MeshOutputs, WallsVtpHasOneCellPerTriangleAtTheTurnedPose) {
  using Vec = Eigen::Vector3d;
  constexpr int kSteps = 250;
  World<3> w = sable::test::mesh_world<3>();
  sable::DemSolver<3> s(w);
  s.initialize();
  for (int k = 0; k < kSteps; ++k) s.step();
  const auto& paddle = w.walls[kPaddle];
  ASSERT_GT(sable::test::touching(w.neighbors.wall_pairs, kPaddle), 0u);
  const std::vector<Vec> element_force = sable::element_forces(w, kPaddle);
  ASSERT_EQ(element_force.size(), 12u);
  Vec sum = Vec::Zero();
  double scale = 0.0;
  for (const Vec& f : element_force) {
    sum += f;
    scale += f.norm();
  }
  ASSERT_GT(paddle.force.norm(), 0.0);
  EXPECT_LE((sum - paddle.force).norm(), 1e-12 * paddle.force.norm());

  const std::string file = path("walls.vtp");
  sable::write_walls_vtp(w, file, sable::VtkEncoding::kAscii);  // vtk_array reads text
  const std::string text = sable::test::slurp(file);
  const auto points = vtk_array(text, "Points");
  const auto connectivity = vtk_array(text, "connectivity");
  const auto offsets = vtk_array(text, "offsets");
  const auto wall = vtk_array(text, "wall");
  const auto element = vtk_array(text, "element");
  const auto cell_force = vtk_array(text, "cell_force");
  ASSERT_EQ(element.size(), wall.size());
  ASSERT_EQ(offsets.size(), wall.size());
  ASSERT_EQ(cell_force.size(), 3 * wall.size());

  // The paddle as built, turned about z through the origin by the angle of kSteps steps.
  const sable::SurfaceMesh<3> start =
      sable::box_surface<3>(Vec(-0.03, -0.004, 0.002), Vec(0.03, 0.004, 0.03), "paddle");
  const double angle = kSteps * w.dt * sable::test::kPaddleRate;
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(angle, Vec::UnitZ()).toRotationMatrix();
  std::vector<bool> seen(start.size(), false);
  Vec file_sum = Vec::Zero();
  for (std::size_t c = 0; c < wall.size(); ++c) {
    if (wall[c] != static_cast<double>(kPaddle)) continue;
    const auto e = static_cast<std::size_t>(element[c]);
    ASSERT_LT(e, start.size());
    EXPECT_FALSE(seen[e]) << "element " << e << " twice";
    seen[e] = true;
    const auto first = c ? static_cast<std::size_t>(offsets[c - 1]) : 0;
    ASSERT_EQ(static_cast<std::size_t>(offsets[c]) - first, 3u) << "cell " << c;
    for (std::size_t k = 0; k < 3; ++k) {
      const auto p = static_cast<std::size_t>(connectivity[first + k]);
      const Vec x(points[3 * p], points[3 * p + 1], points[3 * p + 2]);
      const Vec expected = turn * start.vertices[start.elements[e][k]];
      EXPECT_LE((x - expected).norm(), 1e-10) << "element " << e << " corner " << k;
    }
    const Vec f(cell_force[3 * c], cell_force[3 * c + 1], cell_force[3 * c + 2]);
    EXPECT_LE((f - element_force[e]).norm(), 1e-8 * element_force[e].norm() + 1e-300)
        << "element " << e;
    file_sum += f;
  }
  EXPECT_EQ(std::count(seen.begin(), seen.end(), true), 12) << "one cell per triangle";
  EXPECT_LE((file_sum - paddle.force).norm(), 1e-8 * scale);
  EXPECT_EQ(std::system(("/usr/bin/python3 '" SABLE_SOURCE_DIR "/tests/tools/check_vtp.py' '" +
                         file + "' --arrays wall,force,element,cell_force")
                            .c_str()),
            0);
}

std::string box_scenario(int dim, const std::string& out) {
  const bool three = dim == 3;
  std::ostringstream s;
  s << "[simulation]\ndimension = " << dim << "\nseed = 2\n"
    << "gravity = " << (three ? "[0, 0, -9.81]" : "[0, -9.81]\nthickness = 0.002") << "\n"
    << "[domain]\nlo = " << (three ? "[0, 0, 0]" : "[0, 0]")
    << "\nhi = " << (three ? "[0.008, 0.008, 0.008]" : "[0.008, 0.008]") << "\n"
    << "[[material]]\nname = \"g\"\ndensity = 2500.0\nyoung = 5e6\npoisson = 0.3\n"
    << "friction = 0.4\n"
    << "[[grains]]\ngenerator = \"lattice\"\nmaterial = \"g\"\nradius = 1e-3\n"
    << "region = { box = { lo = " << (three ? "[0, 0, 0]" : "[0, 0]")
    << ", hi = " << (three ? "[0.008, 0.008, 0.008]" : "[0.008, 0.008]") << " } }\ncount = 8\n"
    << "[[wall]]\nname = \"box\"\ntype = \"box\"\nmaterial = \"g\"\nlo = "
    << (three ? "[0, 0, 0]" : "[0, 0]")
    << "\nhi = " << (three ? "[0.008, 0.008, 0.008]" : "[0.008, 0.008]") << "\n"
    << "[[stage]]\nsteps = 300\n"
    << "[output]\ndir = \"" << out << "\"\ncsv_interval = 100\nvtk_interval = 0\n"
    << "log_interval = 0\nvtk_contacts = false\nvtk_walls = false\n";
  return s.str();
}

// The torque columns of each wall of the run in `out` against its end snapshot: after the
// wall's force columns (2D: tz only), the last row holding the snapshot's torque (10
// significant digits).
template <int D>
void check_torque_columns(const std::string& text, const fs::path& out) {
  std::vector<std::string> names;
  const auto cols = sable::test::read_csv_columns(out / "series.csv", &names);
  World<D> world;
  sable::build_model(sable::parse_scenario(text, "test.toml"), world);
  sable::load_snapshot((out / "snapshots" / "end_of_stage_1.h5").string(), world);
  const auto at = [&](const std::string& n) {
    return static_cast<std::size_t>(std::find(names.begin(), names.end(), n) - names.begin());
  };
  std::size_t nonzero = 0;
  for (const auto& w : world.walls) {
    const std::string base = "wall_" + w.name + "_";
    const std::size_t last_force = at(base + (D == 3 ? "fz_N" : "fy_N"));
    ASSERT_LT(last_force, names.size()) << base;
    const auto torque = sable::Space<D>::rot_to_array(w.torque);
    const std::string axes = D == 3 ? "xyz" : "z";
    for (std::size_t k = 0; k < axes.size(); ++k) {
      const std::string name = base + "t" + axes[k] + "_Nm";
      EXPECT_EQ(at(name), last_force + 1 + k) << name;
      const double expected = torque[D == 3 ? k : 2];
      ASSERT_TRUE(cols.count(name)) << name;
      EXPECT_NEAR(cols.at(name).back(), expected, 1e-9 * std::abs(expected)) << name;
      nonzero += expected != 0.0 ? 1 : 0;
    }
    EXPECT_EQ(at(base + "tx_Nm") == names.size(), D == 2);
  }
  EXPECT_GT(nonzero, 0u);
}

// series.csv: each wall's torque (about the origin for walls never given a rotation) beside its
// force.
TEST_F(MeshOutputs, SeriesHasEachWallsTorqueAfterItsForce) {
  const fs::path out2 = dir_ / "run2", out3 = dir_ / "run3";
  const std::string text2 = box_scenario(2, out2.string()), text3 = box_scenario(3, out3.string());
  sable::test::run_text(text2);
  sable::test::run_text(text3);
  check_torque_columns<2>(text2, out2);
  check_torque_columns<3>(text3, out3);
}

// `sable analyze` over two snapshots of the turning paddle: each wall's mean force and torque
// in summary.json (wall_loads), per snapshot in series.csv after the other columns; a mesh gets
// no height profile, and every analysis still runs.
TEST_F(MeshOutputs, AnalyzeReportsEachWallsTorque) {
  World<3> w = sable::test::mesh_world<3>();
  sable::DemSolver<3> s(w);
  s.initialize();
  std::vector<std::string> snaps;
  std::vector<Eigen::Vector3d> torques, forces;
  for (int k = 0; k < 2; ++k) {
    for (int n = 0; n < 150; ++n) s.step();
    snaps.push_back(path(fmt::format("s{}.h5", k)));
    sable::save_snapshot(w, {}, "scenario", snaps.back());
    torques.push_back(w.walls[kPaddle].torque);
    forces.push_back(w.walls[kPaddle].force);
  }
  ASSERT_GT(torques.back().norm(), 0.0);
  sable::SampleLoaders loaders;
  loaders.load3 = [](const std::string& p) {
    World<3> world = sable::test::mesh_world<3>(false);
    sable::load_snapshot(p, world);
    sable::Sample<3> sample = sable::make_sample(world);
    sample.source = p;
    return sample;
  };
  loaders.load2 = [](const std::string&) -> sable::Sample<2> { throw std::logic_error("2D"); };
  sable::AnalyzeOptions opt;
  opt.snapshots = snaps;
  opt.out_dir = path("an");
  sable::run_analysis(opt, loaders);
  const std::string summary = sable::test::slurp(dir_ / "an" / "summary.json");
  const auto loads = summary.find("\"wall_loads\"");
  ASSERT_NE(loads, std::string::npos) << summary;
  const std::string tail = summary.substr(loads);
  EXPECT_NE(tail.find("\"paddle\""), std::string::npos);
  EXPECT_NE(tail.find("\"type\": \"mesh\""), std::string::npos) << tail;
  EXPECT_NE(
      tail.find(fmt::format("\"torque_Nm\": [{:.12g}, ", 0.5 * (torques[0].x() + torques[1].x()))),
      std::string::npos)
      << tail;
  EXPECT_NE(tail.find("\"pivot_m\": [0, 0, 0]"), std::string::npos) << tail;
  EXPECT_FALSE(fs::exists(dir_ / "an" / "wall_profile_paddle.csv"));
  std::vector<std::string> names;
  const auto cols = sable::test::read_csv_columns(dir_ / "an" / "series.csv", &names);
  ASSERT_GE(names.size(), 12u);
  EXPECT_EQ(names[names.size() - 12], "wall_floor_fx_N");
  EXPECT_EQ(names[names.size() - 6], "wall_paddle_fx_N");
  EXPECT_EQ(names.back(), "wall_paddle_tz_Nm");
  for (std::size_t k = 0; k < 2; ++k)
    for (int d = 0; d < 3; ++d) {
      const std::string ax(1, "xyz"[d]);
      EXPECT_NEAR(cols.at("wall_paddle_t" + ax + "_Nm")[k], torques[k][d],
                  1e-11 * torques[k].norm());
      EXPECT_NEAR(cols.at("wall_paddle_f" + ax + "_N")[k], forces[k][d], 1e-11 * forces[k].norm());
    }
}

}  // namespace
