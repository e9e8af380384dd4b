// ParaView output of polyhedral grains (io/vtk.hpp, write_polyhedra_vtp): one polygon per face,
// its corners where the grain's pose puts them and wound counterclockwise seen from outside,
// the grain's data on each face, in every encoding; and the runner's polyhedra.pvd series,
// fresh and resumed. The files are read back by scripts/vtkxml.py (tests/tools/vtp_arrays.py),
// every double to the bit.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "mesh_world.hpp"
#include "polyhedra_helpers.hpp"
#include "run_helpers.hpp"
#include "sable/cd/cd_solver.hpp"
#include "sable/core/error.hpp"
#include "sable/io/vtk.hpp"
#include "sable/scenario/simulation.hpp"
#include "sable/world/polyhedral_grains.hpp"

namespace {

namespace fs = std::filesystem;
using sable::VtkEncoding;
using sable::World;
using Vec = Eigen::Vector3d;
using Quat = Eigen::Quaterniond;
using Arrays = std::map<std::string, std::vector<double>>;

class VtkPolyhedra : public sable::test::TempDirTest {};

constexpr VtkEncoding kEncodings[] = {VtkEncoding::kBinary, VtkEncoding::kZlib,
                                      VtkEncoding::kAscii};

// The arrays of a .vtp by key (tests/tools/vtp_arrays.py writes each double by repr(), which
// strtod reads back as the same double; the integers are below 2^53, exact as doubles).
Arrays read_vtp(const std::string& file) {
  const std::string dump = file + ".txt";
  const std::string cmd = "/usr/bin/python3 '" SABLE_SOURCE_DIR "/tests/tools/vtp_arrays.py' '" +
                          file + "' '" + dump + "'";
  Arrays out;
  if (std::system(cmd.c_str()) != 0) {
    ADD_FAILURE() << "vtp_arrays.py could not read " << file;
    return out;
  }
  std::istringstream in(sable::test::slurp(dump));
  for (std::string line; std::getline(in, line);) {
    std::istringstream row(line);
    std::string key, value;
    row >> key;
    auto& values = out[key];
    while (row >> value) values.push_back(std::strtod(value.c_str(), nullptr));
  }
  return out;
}

int check_vtp(const std::string& args) {
  return std::system(
      ("/usr/bin/python3 '" SABLE_SOURCE_DIR "/tests/tools/check_vtp.py' " + args).c_str());
}

Vec point(const std::vector<double>& xyz, std::size_t k) {
  return {xyz[3 * k], xyz[3 * k + 1], xyz[3 * k + 2]};
}

// A unit cube turned by kTurn about its centroid kCubeAt, a round grain (skipped by the
// writer), and a fixed tetrahedron of another material given by its corners in the world.
const Quat kTurn(Eigen::AngleAxisd(0.7, Vec(1.0, 2.0, 3.0).normalized()));
const Vec kCubeAt(0.25, -0.5, 1.5);
const std::vector<Vec> kTetCorners{Vec(-2.0, 1.0, 0.5), Vec(-1.0, 1.0, 0.5), Vec(-2.0, 2.5, 0.5),
                                   Vec(-2.0, 1.0, 1.25)};
// The largest coordinate magnitude of the scene: the scale of the tolerances below.
constexpr double kScale = 2.5;

std::vector<Vec> unit_cube() {
  std::vector<Vec> c;
  for (int m = 0; m < 8; ++m)
    c.emplace_back(m & 1 ? 0.5 : -0.5, m & 2 ? 0.5 : -0.5, m & 4 ? 0.5 : -0.5);
  return c;
}

struct Scene {
  World<3> w;
  std::vector<Vec> cube;  // the cube's corners where its pose puts them
};

Scene scene() {
  Scene s;
  World<3>& w = s.w;
  w.materials.add({"rock", 2600.0, 0.0, 0.0, 1.0, 0.5, 0.0});
  w.materials.add({"glass", 2500.0, 0.0, 0.0, 1.0, 0.3, 0.0});
  w.materials.finalize();
  const sable::ShapePlacement cube = w.shapes.add(unit_cube());
  sable::add_polyhedral_grain(w, cube.index, kCubeAt, kTurn, 2600.0, 0);
  w.particles.add(Vec(3.0, 0.0, 0.0), 0.25, 2600.0, 0, 1.0);
  sable::add_polyhedral_grain(w, kTetCorners, 2500.0, 1, true);
  w.particles.v[0] = Vec(0.1, -0.2, 0.3);
  w.particles.omega[0] = Vec(1.0, 2.0, -3.0);
  w.particles.v[1] = Vec(9.0, 9.0, 9.0);  // the round grain's: in no face's data
  // A corner c given to the table is centroid + frame * v for its body-frame corner v.
  for (const Vec& c : unit_cube())
    s.cube.push_back(kTurn * (cube.frame.conjugate() * (c - cube.centroid)) + kCubeAt);
  return s;
}

// Every corner of `expected` is, within `tol`, exactly one of the file's expected.size()
// points from `first` on (a grain's corners, in the order of its hull).
void expect_same_corners(const std::vector<double>& xyz, std::size_t first,
                         const std::vector<Vec>& expected, double tol) {
  for (const Vec& e : expected) {
    int matches = 0;
    for (std::size_t k = first; k < first + expected.size(); ++k)
      matches += (point(xyz, k) - e).cwiseAbs().maxCoeff() <= tol ? 1 : 0;
    EXPECT_EQ(matches, 1) << "corner " << e.transpose();
  }
}

// Face c of the file: its corners' Newell normal (the right-hand normal of the loop) is the
// file's normal and points out of the grain whose centroid is `centre`.
void expect_outward_face(const Arrays& a, std::size_t c, const Vec& centre, double tol) {
  const auto& offsets = a.at("Polys/offsets");
  const auto& conn = a.at("Polys/connectivity");
  const auto begin = static_cast<std::size_t>(c ? offsets[c - 1] : 0);
  const auto end = static_cast<std::size_t>(offsets[c]);
  Vec newell = Vec::Zero(), mid = Vec::Zero();
  for (std::size_t k = begin; k < end; ++k) {
    const Vec p = point(a.at("Points"), static_cast<std::size_t>(conn[k]));
    const Vec q =
        point(a.at("Points"), static_cast<std::size_t>(conn[k + 1 < end ? k + 1 : begin]));
    newell += (p - centre).cross(q - centre);
    mid += p / static_cast<double>(end - begin);
  }
  const Vec n = point(a.at("cell/normal"), c);
  EXPECT_LE((newell.normalized() - n).norm(), tol) << "face " << c;
  EXPECT_GT(n.dot(mid - centre), 0.0) << "face " << c << " points inward";
}

// The cube's 6 faces and the tetrahedron's 4, their 8 + 4 corners at the posed places, each
// face counterclockwise seen from outside, its data the grain's. Tolerances: the binary
// encodings store the doubles' bits, and the expected corners differ from the written ones
// only by the rounding of a rotation and of the hull's move into its body frame (a few 1e-16
// of kScale): 1e-12 relative. ASCII keeps 9 significant digits (5e-9 relative each value,
// io/vtk_xml.hpp: velocities 5e-9 of themselves, corners 5e-9 of kScale), and a normal from
// corners rounded so, over edges of 0.75 m to 1.8 m, is good to about 1e-8: 1e-7.
TEST_F(VtkPolyhedra, FacesArePosedWoundOutwardAndCarryTheirGrain) {
  const Scene sc = scene();
  const World<3>& w = sc.w;
  const auto& p = w.particles;
  for (VtkEncoding enc : kEncodings) {
    SCOPED_TRACE(std::string(sable::vtk_encoding_name(enc)));
    const bool text = enc == VtkEncoding::kAscii;
    const double tol = text ? 5e-9 * kScale : 1e-12 * kScale, tol_n = text ? 1e-7 : 1e-12;
    const std::string file = path(fmt::format("p_{}.vtp", sable::vtk_encoding_name(enc)));
    sable::write_polyhedra_vtp(w, file, enc);
    ASSERT_EQ(check_vtp(fmt::format("'{}' --points 12 --cells 10 --format {} --arrays "
                                    "id,velocity,angular_velocity,material,fixed,normal",
                                    file, sable::vtk_encoding_name(enc))),
              0);
    const Arrays a = read_vtp(file);
    ASSERT_EQ(a.at("piece/NumberOfPolys"), std::vector<double>{10.0});
    ASSERT_EQ(a.at("Points").size(), 3u * 12u);
    ASSERT_EQ(a.at("Polys/offsets").size(), 10u);
    // Slot order: the cube's 8 corners, then the tetrahedron's 4 (the round grain has none).
    expect_same_corners(a.at("Points"), 0, sc.cube, tol);
    expect_same_corners(a.at("Points"), 8, kTetCorners, tol);
    const auto& offsets = a.at("Polys/offsets");
    const auto& conn = a.at("Polys/connectivity");
    for (std::size_t c = 0; c < 10; ++c) {
      const bool is_cube = c < 6;
      const std::size_t k = is_cube ? 0 : 2, first = is_cube ? 0 : 8;
      const double corners = offsets[c] - (c ? offsets[c - 1] : 0.0);
      EXPECT_EQ(corners, is_cube ? 4.0 : 3.0) << "face " << c;
      for (auto v = static_cast<std::size_t>(c ? offsets[c - 1] : 0.0);
           v < static_cast<std::size_t>(offsets[c]); ++v) {
        const auto i = static_cast<std::size_t>(conn[v]);
        EXPECT_TRUE(i >= first && i < first + (is_cube ? 8 : 4)) << "face " << c << ": " << i;
      }
      expect_outward_face(a, c, p.x[k], tol_n);
      EXPECT_EQ(a.at("cell/id")[c], static_cast<double>(p.id[k].index));
      EXPECT_EQ(a.at("cell/material")[c], is_cube ? 0.0 : 1.0);
      EXPECT_EQ(a.at("cell/fixed")[c], is_cube ? 0.0 : 1.0);
      for (int d = 0; d < 3; ++d) {
        const double v = p.v[k][d], spin = p.omega[k][d];
        EXPECT_NEAR(a.at("cell/velocity")[3 * c + d], v, text ? 5e-9 * std::abs(v) : 0.0);
        EXPECT_NEAR(a.at("cell/angular_velocity")[3 * c + d], spin,
                    text ? 5e-9 * std::abs(spin) : 0.0);
      }
    }
  }
}

// The contacts' file draws a polyhedral contact through the point its solver stored: a cube
// of side a resting on a fixed one, shifted by a / 4 along x, is pushed up under its centroid
// (x = a / 4 on the shared face z = 0), off the line of centres (which crosses z = 0 at
// x = a / 8). One line of three points, x_i, that point, x_j; its normal force m g (the CD
// solver's 1e-11 tolerance, exactly the stored force's bits in binary).
TEST_F(VtkPolyhedra, ContactsAreDrawnThroughTheirPoint) {
  constexpr double a = 0.01, rho = 2500.0, g = 9.81;
  World<3> w;
  w.materials.add({"grain", rho, 0.0, 0.0, 0.0, 0.5, 0.0});
  w.materials.finalize();
  w.neighbors.skin = 0.2 * a;
  w.neighbors.domain_lo.setConstant(-0.2);
  w.neighbors.domain_hi.setConstant(0.2);
  w.gravity = Vec(0.0, 0.0, -g);
  w.dt = 1e-4;
  sable::add_polyhedral_grain(
      w, sable::test::box_points(Vec(-0.5, -0.5, -1) * a, Vec(0.5, 0.5, 0) * a), rho, 0, true);
  sable::add_polyhedral_grain(
      w, sable::test::box_points(Vec(-0.25, -0.5, 0) * a, Vec(0.75, 0.5, 1) * a), rho, 0);
  sable::CdSettings settings;
  settings.nlgs.tolerance = 1e-11;
  settings.nlgs.max_iterations = 100000;
  sable::CdSolver<3> solver(w, settings);
  solver.initialize();
  for (int k = 0; k < 20; ++k) solver.step();
  const std::string file = path("contacts.vtp");
  sable::write_contacts_vtp(w, file, VtkEncoding::kBinary);
  const Arrays arrays = read_vtp(file);
  const auto& xyz = arrays.at("Points");
  ASSERT_EQ(xyz.size(), 9u);
  EXPECT_EQ(arrays.at("Lines/connectivity"), (std::vector<double>{0.0, 1.0, 2.0}));
  EXPECT_EQ(arrays.at("Lines/offsets"), std::vector<double>{3.0});
  const auto& p = w.particles;
  const std::uint32_t i = w.neighbors.pairs.i[0], j = w.neighbors.pairs.j[0];
  EXPECT_EQ(point(xyz, 0), p.x[i]);
  EXPECT_EQ(point(xyz, 1), Vec(p.x[i] + w.contact_geometry.pairs.arm[0]));
  EXPECT_EQ(point(xyz, 2), p.x[j]);
  EXPECT_NEAR(point(xyz, 1).x(), 0.25 * a, 1e-9 * a);
  EXPECT_NEAR(point(xyz, 1).y(), 0.0, 1e-9 * a);
  EXPECT_NEAR(point(xyz, 1).z(), 0.0, 1e-12 * a);
  const double mg = p.mass[p.ids.slot(p.id[1])] * g;
  EXPECT_NEAR(arrays.at("cell/normal_force").at(0), mg, 1e-9 * mg) << "compression positive";
}

// A world without polyhedra (round grains only, or none) gives a well-formed empty file.
TEST_F(VtkPolyhedra, AWorldWithoutPolyhedraWritesAnEmptyFile) {
  World<3> w;
  w.materials.add({"rock", 2600.0, 0.0, 0.0, 1.0, 0.5, 0.0});
  w.materials.finalize();
  w.particles.add(Vec::Zero(), 0.25, 2600.0, 0, 1.0);
  for (VtkEncoding enc : kEncodings) {
    const std::string file = path(fmt::format("e_{}.vtp", sable::vtk_encoding_name(enc)));
    sable::write_polyhedra_vtp(w, file, enc);
    EXPECT_EQ(check_vtp("'" + file + "' --points 0 --cells 0"), 0);
  }
}

// --- the runner -------------------------------------------------------------------------------

// Two cubes falling freely by contact dynamics, a frame each step and a snapshot every other.
std::string falling_cubes(const fs::path& out) {
  return "[simulation]\ndimension = 3\nsolver = \"cd\"\ndt = 1e-3\ngravity = [0, 0, -9.81]\n"
         "[domain]\nlo = [-1, -1, -1]\nhi = [1, 1, 1]\n"
         "[[material]]\nname = \"g\"\ndensity = 2500.0\nyoung = 5e6\npoisson = 0.3\n"
         "friction = 0.4\n"
         "[[stage]]\nsteps = 4\n"
         "[output]\ndir = \"" +
         out.string() +
         "\"\nvtk_interval = 1\nsnapshot_interval = 2\ncsv_interval = 1\nlog_interval = 0\n"
         "vtk_contacts = false\nvtk_walls = false\n";
}

sable::RunOptions quiet(std::ostringstream& log, const std::string& resume = "",
                        bool overwrite = false) {
  sable::RunOptions opt;
  opt.log = &log;
  opt.live_progress = false;
  opt.resume = resume;
  opt.overwrite = overwrite;
  return opt;
}

std::vector<std::pair<double, std::string>> entries(const fs::path& pvd) {
  return sable::PvdSeries(pvd.string(), std::numeric_limits<double>::infinity()).entries();
}

// grains.pvd's entries naming the polyhedra's frames of the same steps.
std::vector<std::pair<double, std::string>> as_polyhedra(
    std::vector<std::pair<double, std::string>> e) {
  const std::string from = "vtk/grains_";
  for (auto& entry : e)
    if (entry.second.rfind(from, 0) == 0)
      entry.second = "vtk/polyhedra_" + entry.second.substr(from.size());
  return e;
}

// A run of a world holding polyhedra writes polyhedra.pvd frame for frame with grains.pvd: the
// same times (compared exactly) naming the same steps' files, each the two cubes' 12 faces
// on 16 corners (counts: exact). A resume
// from step 2 refuses the later polyhedra frames (they belong to the run it would replace),
// and with --overwrite continues the series as it does grains.pvd: the same entries again.
TEST_F(VtkPolyhedra, TheRunnerWritesAPolyhedraSeriesAndResumesIt) {
  const fs::path out = dir_ / "out";
  const std::string text = falling_cubes(out);
  std::ostringstream log;
  {
    sable::Simulation<3> sim(sable::parse_scenario(text, "cubes.toml"), quiet(log));
    std::vector<Vec> cube;
    for (const Vec& c : unit_cube()) cube.push_back(0.01 * c);
    const std::uint32_t shape = sim.world().shapes.add(cube).index;
    sable::add_polyhedral_grain(sim.world(), shape, Vec(-0.1, 0.0, 0.0), kTurn, 2500.0, 0);
    sable::add_polyhedral_grain(sim.world(), shape, Vec(0.1, 0.0, 0.0), Quat::Identity(), 2500.0,
                                0);
    sim.run();
  }
  const auto fresh = entries(out / "polyhedra.pvd");
  // Steps 0 to 4, and step 4's again at the stage's end.
  ASSERT_EQ(fresh.size(), 6u) << log.str();
  EXPECT_EQ(fresh, as_polyhedra(entries(out / "grains.pvd")));
  for (const auto& entry : fresh)
    EXPECT_EQ(check_vtp(fmt::format("'{}' --points 16 --cells 12", (out / entry.second).string())),
              0)
        << entry.second;

  const std::string from = (out / "snapshots" / "step_0000000002.h5").string();
  try {
    sable::Simulation<3>(sable::parse_scenario(text, "cubes.toml"), quiet(log, from)).run();
    ADD_FAILURE() << "a resume among later frames should be refused";
  } catch (const sable::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("vtk/polyhedra_0000000003.vtp"), std::string::npos)
        << e.what();
  }
  sable::Simulation<3>(sable::parse_scenario(text, "cubes.toml"), quiet(log, from, true)).run();
  EXPECT_EQ(entries(out / "polyhedra.pvd"), fresh);
  EXPECT_EQ(as_polyhedra(entries(out / "grains.pvd")), fresh);
}

}  // namespace
