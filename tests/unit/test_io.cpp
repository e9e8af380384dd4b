// Output and restart I/O: VTK files, CSV logs, atomic writes and HDF5 snapshots.
//
// The snapshot tests are the guard for bit-identical resume: a run saved, loaded into a world
// rebuilt from scratch and continued must produce the same bits as the run that never stopped.
// Every comparison of state is therefore an exact hash equality, never a tolerance.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <hdf5.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "bed_world.hpp"
#include "sable/core/error.hpp"
#include "sable/dem/dem_solver.hpp"
#include "sable/io/atomic_file.hpp"
#include "sable/io/csv.hpp"
#include "sable/io/snapshot.hpp"
#include "sable/io/vtk.hpp"
#include "sable/world/state_hash.hpp"
#include "test_data.hpp"

namespace {

namespace fs = std::filesystem;
using sable::InputError;
using sable::RunPosition;
using sable::World;
using sable::test::make_world;

// ---------------------------------------------------------------- fixtures and builders

// Each test writes into its own scratch directory, removed afterwards.
class IoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("sable_io_" + std::to_string(::getpid()) + "_" +
                                        info->test_suite_name() + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  // Names in the scratch directory that look like leftover temporaries of atomic writes.
  std::vector<std::string> temporaries() const {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir_))
      if (e.path().filename().string().find(".tmp-") != std::string::npos)
        out.push_back(e.path().string());
    return out;
  }

  fs::path dir_;
};

::testing::AssertionResult contains(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "\"" << text << "\" does not contain \"" << part << "\"";
}

std::string read_file(const std::string& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void write_file(const std::string& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary);
  out << text;
}

std::size_t touching_pairs(const auto& list) {
  std::size_t n = 0;
  for (const auto& f : list.force) n += (f.array() != 0.0).any() ? 1 : 0;
  return n;
}

// ---------------------------------------------------------------- VTK

int check_vtp(const std::string& args) {
  const std::string cmd =
      "/usr/bin/python3 '" SABLE_SOURCE_DIR "/tests/tools/check_vtp.py' " + args;
  const int rc = std::system(cmd.c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

// Guards: the .vtp files are well-formed XML whose declared point and cell counts match the
// data arrays, with one vertex per grain, one line per touching pair and the expected wall
// cells, so ParaView opens them, in each of the three encodings (the appended sections'
// byte counts and zlib blocks decoded by scripts/vtkxml.py). Counts are integers: compared
// exactly.
template <int D>
void check_vtk_outputs(const std::string& dir, sable::VtkEncoding enc) {
  World<D> w = make_world<D>();
  sable::DemSolver<D> solver(w);
  solver.initialize();
  for (int s = 0; s < 20; ++s) solver.step();
  const std::size_t n = w.particles.size(), contacts = touching_pairs(w.neighbors.pairs);
  ASSERT_GT(contacts, 0u) << "the test world should have touching grains";
  const std::string g = dir + "/grains.vtp", c = dir + "/contacts.vtp", wl = dir + "/walls.vtp";
  sable::write_grains_vtp(w, g, enc);
  sable::write_contacts_vtp(w, c, enc);
  sable::write_walls_vtp(w, wl, enc);
  const std::string format = fmt::format(" --format {}", sable::vtk_encoding_name(enc));
  EXPECT_EQ(check_vtp(fmt::format("'{}' --points {} --cells {} --arrays {}", g, n, n,
                                  "id,radius,velocity,angular_velocity,force,coordination,"
                                  "material,fixed") +
                      format),
            0);
  EXPECT_EQ(
      check_vtp(fmt::format("'{}' --points {} --cells {} --arrays {}", c, 2 * contacts, contacts,
                            "normal_force,normal_force_vector,tangential_force,id_i,id_j") +
                format),
      0);
  // 2D: floor and ramp segments. 3D: floor and ramp polygons plus 64 x 2 drum triangles.
  const std::size_t wall_cells = D == 2 ? 2 : 2 + 128;
  EXPECT_EQ(check_vtp(fmt::format("'{}' --cells {} --arrays wall,force", wl, wall_cells) + format),
            0);
  // The grains file starts exactly with the XML declaration ParaView expects.
  EXPECT_EQ(read_file(g).rfind("<?xml version=\"1.0\"?>\n", 0), 0u);
}

TEST_F(IoTest, VtkFilesParseWithMatchingCounts2D) {
  SABLE_NEEDS(fs::exists("/usr/bin/python3"), "needs /usr/bin/python3");
  for (auto enc :
       {sable::VtkEncoding::kBinary, sable::VtkEncoding::kZlib, sable::VtkEncoding::kAscii})
    check_vtk_outputs<2>(dir_.string(), enc);
}

TEST_F(IoTest, VtkFilesParseWithMatchingCounts3D) {
  SABLE_NEEDS(fs::exists("/usr/bin/python3"), "needs /usr/bin/python3");
  for (auto enc :
       {sable::VtkEncoding::kBinary, sable::VtkEncoding::kZlib, sable::VtkEncoding::kAscii})
    check_vtk_outputs<3>(dir_.string(), enc);
}

// Guards: a file larger than the writer's 64 KiB pieces (8,000 extra grains: ~0.5 MB of
// text, and zlib arrays of several 32 KiB blocks) comes out whole, one well-formed file with
// every grain, as a small one does.
TEST_F(IoTest, VtkFileWrittenInPiecesIsWhole) {
  SABLE_NEEDS(fs::exists("/usr/bin/python3"), "needs /usr/bin/python3");
  World<3> w = make_world<3>();
  for (int row = 0; row < 80; ++row)
    for (int col = 0; col < 100; ++col)
      w.particles.add(Eigen::Vector3d(0.001 * col, 0.001 * row, 0.2), sable::test::kBedR, 2500.0, 0,
                      w.thickness);
  const std::size_t n = w.particles.size();
  sable::write_grains_vtp(w, path("big.vtp"), sable::VtkEncoding::kAscii);
  EXPECT_GT(fs::file_size(path("big.vtp")), 4u * 65536u) << "the test must span several pieces";
  EXPECT_EQ(check_vtp(fmt::format("'{}' --points {} --cells {} --arrays {}", path("big.vtp"), n, n,
                                  "id,radius,velocity,force")),
            0);
  sable::write_grains_vtp(w, path("big_z.vtp"), sable::VtkEncoding::kZlib);
  EXPECT_EQ(check_vtp(fmt::format("'{}' --points {} --format zlib --arrays velocity",
                                  path("big_z.vtp"), n)),
            0);
  EXPECT_FALSE(fs::exists(sable::atomic_temp_path(path("big.vtp")))) << "temporary left behind";
}

// Guards: an empty world still writes valid files (zero points, zero cells).
TEST_F(IoTest, VtkEmptyWorld) {
  SABLE_NEEDS(fs::exists("/usr/bin/python3"), "needs /usr/bin/python3");
  World<3> w = make_world<3>(false);
  sable::write_grains_vtp(w, path("g.vtp"));
  sable::write_contacts_vtp(w, path("c.vtp"));
  EXPECT_EQ(check_vtp("'" + path("g.vtp") + "' --points 0 --cells 0"), 0);
  EXPECT_EQ(check_vtp("'" + path("c.vtp") + "' --points 0 --cells 0"), 0);
}

// Guards: the .pvd collection lists every added step, stays valid XML after each rewrite, and
// a resumed series keeps only the steps up to the resume time (no duplicates in ParaView).
TEST_F(IoTest, PvdSeriesAddAndResume) {
  SABLE_NEEDS(fs::exists("/usr/bin/python3"), "needs /usr/bin/python3");
  const std::string pvd = path("grains.pvd");
  {
    sable::PvdSeries series(pvd);
    series.add(0.0, "grains_0.vtp");
    series.add(0.001, "grains_1.vtp");
    series.add(0.002, "a&b <2>.vtp");  // escaped in XML, read back verbatim
  }
  EXPECT_EQ(check_vtp("'" + pvd + "' --datasets 3"), 0);
  sable::PvdSeries resumed(pvd, 0.001);
  ASSERT_EQ(resumed.entries().size(), 2u);
  EXPECT_EQ(resumed.entries()[1].first, 0.001);  // exact: written with 17 digits
  resumed.add(0.002, "grains_2.vtp");
  EXPECT_EQ(check_vtp("'" + pvd + "' --datasets 3"), 0);
  sable::PvdSeries again(pvd, 1.0);
  EXPECT_EQ(again.entries().back().second, "grains_2.vtp");
  EXPECT_TRUE(temporaries().empty());
}

// ---------------------------------------------------------------- snapshots: round trip

// Guards bit-identical resume: after save + load into a world rebuilt without grains (as the
// CLI rebuilds it from the scenario), the state hash is equal, and stepping both worlds (the
// resumed one without re-initializing its solver) keeps the hashes equal through neighbour
// list rebuilds. Exact equality: any lost bit (history, last forces, rng) would diverge.
template <int D>
void check_round_trip(const std::string& file, bool rolling = false) {
  World<D> a = make_world<D>(true, rolling);
  sable::DemSolver<D> sa(a);
  sa.initialize();
  for (int s = 0; s < 40; ++s) sa.step();
  ASSERT_GT(touching_pairs(a.neighbors.pairs), 0u);
  ASSERT_GT(touching_pairs(a.neighbors.wall_pairs), 0u);
  std::size_t sheared = 0;  // friction history that the snapshot must carry
  for (const auto& s : a.neighbors.pairs.shear) sheared += s.squaredNorm() > 0.0 ? 1 : 0;
  ASSERT_GT(sheared, 0u);
  if (rolling) {  // wound rolling springs, of grain pairs and of grain-wall pairs
    std::size_t wound = 0, wall_wound = 0;
    for (const auto& th : a.neighbors.pairs.roll) wound += sable::Space<D>::rot_norm2(th) > 0.0;
    for (const auto& th : a.neighbors.wall_pairs.roll)
      wall_wound += sable::Space<D>::rot_norm2(th) > 0.0;
    ASSERT_GT(wound, 0u);
    ASSERT_GT(wall_wound, 0u);
  }
  ASSERT_FALSE(a.particles.ids.free_list().empty());
  const std::string scenario = "[simulation]\ndimension = " + std::to_string(D) + "\n# é\n";
  sable::save_snapshot(a, RunPosition{2, 17}, scenario, file);

  const auto info = sable::read_snapshot_info(file);
  EXPECT_EQ(info.dimension, D);
  EXPECT_EQ(info.step, a.step);
  EXPECT_EQ(info.time, a.time);
  EXPECT_EQ(info.grains, a.particles.size());
  EXPECT_EQ(info.pairs, a.neighbors.pairs.size());
  EXPECT_EQ(info.wall_pairs, a.neighbors.wall_pairs.size());
  EXPECT_EQ(info.walls, a.walls.size());
  EXPECT_EQ(info.pos, (RunPosition{2, 17}));
  EXPECT_EQ(info.state_hash, sable::state_hash(a));
  EXPECT_EQ(info.scenario_text, scenario);

  World<D> b = make_world<D>(false, rolling);
  std::string text;
  EXPECT_EQ(sable::load_snapshot(file, b, &text), (RunPosition{2, 17}));
  EXPECT_EQ(text, scenario);
  ASSERT_EQ(sable::state_hash(b), sable::state_hash(a));
  EXPECT_EQ(b.neighbors.builds, a.neighbors.builds);
  EXPECT_TRUE(b.neighbors.pairs.roll == a.neighbors.pairs.roll);
  EXPECT_TRUE(b.neighbors.wall_pairs.roll == a.neighbors.wall_pairs.roll);

  const std::uint64_t builds = a.neighbors.builds;
  sable::DemSolver<D> sb(b);  // resumed: no initialize()
  for (int s = 0; s < 400; ++s) {
    sa.step();
    sb.step();
  }
  EXPECT_GT(a.neighbors.builds, builds) << "the continuation should rebuild the lists";
  EXPECT_EQ(sable::state_hash(b), sable::state_hash(a));
  EXPECT_EQ(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL), 0) << "leaked HDF5 handles";
}

TEST_F(IoTest, SnapshotRoundTripIsBitIdentical2D) {
  check_round_trip<2>(path("s2.h5"));
}
TEST_F(IoTest, SnapshotRoundTripIsBitIdentical3D) {
  check_round_trip<3>(path("s3.h5"));
}
// The same with rolling resistance: the springs (a scalar per contact in 2D, a vector in 3D)
// are saved and restored bit for bit.
TEST_F(IoTest, SnapshotRoundTripWithRollingIsBitIdentical2D) {
  check_round_trip<2>(path("s2.h5"), true);
}
TEST_F(IoTest, SnapshotRoundTripWithRollingIsBitIdentical3D) {
  check_round_trip<3>(path("s3.h5"), true);
}

// Guards: N = 0 (empty datasets, no pairs) saves and loads; exact hash equality.
TEST_F(IoTest, SnapshotOfEmptyWorld) {
  World<3> a = make_world<3>(false);
  sable::DemSolver<3> sa(a);
  sa.initialize();
  for (int s = 0; s < 3; ++s) sa.step();
  sable::save_snapshot(a, {}, "", path("empty.h5"));
  World<3> b = make_world<3>(false);
  std::string text = "not cleared";
  sable::load_snapshot(path("empty.h5"), b, &text);
  EXPECT_EQ(text, "");
  EXPECT_EQ(b.particles.size(), 0u);
  EXPECT_EQ(sable::state_hash(b), sable::state_hash(a));
}

// ---------------------------------------------------------------- snapshots: bad files

// Load `file` into `w` expecting an InputError; returns its message.
template <int D>
std::string load_error(const std::string& file, World<D>& w) {
  try {
    sable::load_snapshot(file, w);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError loading " << file;
  return {};
}

// A small saved 3D snapshot for the corruption tests.
std::string saved_snapshot(const std::string& file) {
  World<3> w = make_world<3>();
  sable::DemSolver<3> s(w);
  s.initialize();
  sable::save_snapshot(w, {}, "scenario", file);
  return file;
}

// Guards: each kind of unusable file is an InputError naming the file and what is wrong,
// not a crash, an HDF5 error dump or a half-loaded world (its hash is unchanged: exact).
TEST_F(IoTest, BadSnapshotsAreReportedWithTheFileName) {
  World<3> w = make_world<3>();
  const std::uint64_t before = sable::state_hash(w);

  const std::string missing = path("missing.h5");
  EXPECT_TRUE(contains(load_error(missing, w), missing));
  EXPECT_TRUE(contains(load_error(missing, w), "does not exist"));

  const std::string text = path("text.h5");
  write_file(text, "this is not HDF5\n");
  EXPECT_TRUE(contains(load_error(text, w), text));
  EXPECT_TRUE(contains(load_error(text, w), "not an HDF5 file"));

  const std::string good = saved_snapshot(path("good.h5"));
  const std::string data = read_file(good);
  const std::string cut = path("truncated.h5");
  write_file(cut, data.substr(0, data.size() / 2));
  EXPECT_TRUE(contains(load_error(cut, w), cut));
  EXPECT_TRUE(contains(load_error(cut, w), "truncated"));

  World<2> w2 = make_world<2>();
  const std::string dim_error = load_error(good, w2);
  EXPECT_TRUE(contains(dim_error, good));
  EXPECT_TRUE(contains(dim_error, "'dimension'"));
  EXPECT_TRUE(contains(dim_error, "3D snapshot cannot be loaded into a 2D run"));

  EXPECT_EQ(sable::state_hash(w), before);
  EXPECT_EQ(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL), 0) << "leaked HDF5 handles";
}

// Guards: an HDF5 file that is not a Sable snapshot (no or another `format` tag) is named as
// such by both load_snapshot and read_snapshot_info.
TEST_F(IoTest, ForeignHdf5FileIsRejected) {
  const std::string foreign = path("foreign.h5");
  {
    const hid_t f = H5Fcreate(foreign.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    const hsize_t dims[1] = {3};
    const hid_t space = H5Screate_simple(1, dims, nullptr);
    const hid_t d =
        H5Dcreate2(f, "/data", H5T_NATIVE_INT, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    const int values[3] = {1, 2, 3};
    H5Dwrite(d, H5T_NATIVE_INT, H5S_ALL, H5S_ALL, H5P_DEFAULT, values);
    H5Dclose(d);
    H5Sclose(space);
    H5Fclose(f);
  }
  World<3> w = make_world<3>();
  const std::string msg = load_error(foreign, w);
  EXPECT_TRUE(contains(msg, foreign));
  EXPECT_TRUE(contains(msg, "not a Sable snapshot"));
  EXPECT_TRUE(contains(msg, "'format'"));
  EXPECT_THROW(sable::read_snapshot_info(foreign), InputError);
  EXPECT_EQ(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL), 0) << "leaked HDF5 handles";
}

// Replace dataset `name` of `file` with a 1-D dataset of `n` doubles.
void replace_dataset(const std::string& file, const std::string& name, hsize_t n) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  H5Ldelete(f, name.c_str(), H5P_DEFAULT);
  const hid_t space = H5Screate_simple(1, &n, nullptr);
  const hid_t d =
      H5Dcreate2(f, name.c_str(), H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  const std::vector<double> zeros(n, 0.0);
  if (n > 0) H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, zeros.data());
  H5Dclose(d);
  H5Sclose(space);
  H5Fclose(f);
}

// Replace dataset `name` of `file` with the 1-D unsigned 64-bit `values`, or delete it
// (nullopt).
void replace_u64(const std::string& file, const std::string& name,
                 const std::optional<std::vector<std::uint64_t>>& values) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  H5Ldelete(f, name.c_str(), H5P_DEFAULT);
  if (values) {
    const hsize_t n = values->size();
    const hid_t space = H5Screate_simple(1, &n, nullptr);
    const hid_t d = H5Dcreate2(f, name.c_str(), H5T_NATIVE_UINT64, space, H5P_DEFAULT, H5P_DEFAULT,
                               H5P_DEFAULT);
    if (n > 0) H5Dwrite(d, H5T_NATIVE_UINT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, values->data());
    H5Dclose(d);
    H5Sclose(space);
  }
  H5Fclose(f);
}

// A snapshot written before the grains had an order_key (no '/particles/order_key', a state
// hash that does not cover one) still loads: the slots' order becomes the key, and the hash is
// checked the way it was written. A key out of the slots' order is refused, naming it.
TEST_F(IoTest, SnapshotsWithoutAnOrderKeyLoadAndABadOneIsNamed) {
  const std::string file = path("old.h5");
  World<3> a = make_world<3>();
  sable::DemSolver<3> sa(a);
  sa.initialize();
  for (int s = 0; s < 50; ++s) sa.step();
  sable::save_snapshot(a, RunPosition{1, 50}, "", file);
  replace_u64(file, "/particles/order_key", std::nullopt);
  {
    const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    const hid_t attr = H5Aopen(f, "state_hash", H5P_DEFAULT);
    const std::uint64_t old_hash = sable::state_hash(a, false);
    H5Awrite(attr, H5T_NATIVE_UINT64, &old_hash);
    H5Aclose(attr);
    H5Fclose(f);
  }
  World<3> b = make_world<3>(false);
  sable::load_snapshot(file, b);
  ASSERT_EQ(b.particles.size(), a.particles.size());
  for (std::size_t k = 0; k < b.particles.size(); ++k) EXPECT_EQ(b.particles.order_key[k], k);
  EXPECT_EQ(sable::state_hash(b, false), sable::state_hash(a, false));

  sable::save_snapshot(a, RunPosition{1, 50}, "", file);
  std::vector<std::uint64_t> backwards(a.particles.size());
  for (std::size_t k = 0; k < backwards.size(); ++k) backwards[k] = backwards.size() - k;
  replace_u64(file, "/particles/order_key", backwards);
  World<3> c = make_world<3>(false);
  try {
    sable::load_snapshot(file, c);
    ADD_FAILURE() << "an order_key out of the slots' order should be refused";
  } catch (const InputError& e) {
    EXPECT_TRUE(contains(e.what(), "/particles/order_key"));
    EXPECT_TRUE(contains(e.what(), "rows 0 and 1"));
  }
  EXPECT_EQ(c.particles.size(), 0u);  // the world is left as it was
  EXPECT_EQ(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL), 0) << "leaked HDF5 handles";
}

// Guards: arrays whose lengths disagree, and walls that do not match the scenario, are
// reported with the dataset name and the expected size; the world is left untouched.
TEST_F(IoTest, InconsistentSnapshotsNameTheDataset) {
  World<3> w = make_world<3>();
  const std::uint64_t before = sable::state_hash(w);
  const std::string file = saved_snapshot(path("bad_radius.h5"));
  replace_dataset(file, "/particles/radius", w.particles.size() - 1);
  std::string msg = load_error(file, w);
  EXPECT_TRUE(contains(msg, file));
  EXPECT_TRUE(contains(msg, "'/particles/radius' has"));
  EXPECT_TRUE(contains(msg, std::to_string(w.particles.size() - 1) + " rows"));

  const std::string shape = saved_snapshot(path("bad_shape.h5"));
  replace_dataset(shape, "/particles/v", w.particles.size());  // N, not N x 3
  EXPECT_TRUE(contains(load_error(shape, w), "'/particles/v' has shape"));

  const std::string good = saved_snapshot(path("good.h5"));
  World<3> renamed = make_world<3>();
  renamed.walls[1].name = "chute";
  msg = load_error(good, renamed);
  EXPECT_TRUE(contains(msg, "'/walls/names'"));
  EXPECT_TRUE(contains(msg, "chute"));
  World<3> fewer = make_world<3>();
  fewer.walls.pop_back();
  EXPECT_TRUE(contains(load_error(good, fewer), "scenario defines 2"));

  EXPECT_EQ(sable::state_hash(w), before);
  EXPECT_EQ(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL), 0) << "leaked HDF5 handles";
}

// The doubles of dataset `name` of `file`, row-major.
std::vector<double> read_doubles(const std::string& file, const std::string& name) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t d = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
  const hid_t space = H5Dget_space(d);
  std::vector<double> out(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
  if (!out.empty()) H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data());
  H5Sclose(space);
  H5Dclose(d);
  H5Fclose(f);
  return out;
}

// Replace dataset `name` of `file` with a rows x cols dataset holding `values`.
void write_doubles(const std::string& file, const std::string& name, hsize_t rows, hsize_t cols,
                   const std::vector<double>& values) {
  ASSERT_EQ(values.size(), rows * cols);
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  H5Ldelete(f, name.c_str(), H5P_DEFAULT);
  const hsize_t dims[2] = {rows, cols};
  const hid_t space = H5Screate_simple(2, dims, nullptr);
  const hid_t d =
      H5Dcreate2(f, name.c_str(), H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  if (!values.empty()) H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
  H5Dclose(d);
  H5Sclose(space);
  H5Fclose(f);
}

// Guards: the rolling springs of a snapshot are checked as the other contact arrays: a wrong
// row count or a non-finite spring is refused naming the dataset (and the row), a missing
// dataset too, and a finite but altered spring fails the state hash (which covers the springs
// of a rolling snapshot). The world is left untouched (its hash, exactly).
TEST_F(IoTest, BadRollingSpringsNameTheDataset) {
  World<3> a = make_world<3>(true, true);
  sable::DemSolver<3> s(a);
  s.initialize();
  for (int k = 0; k < 40; ++k) s.step();
  const std::string good = path("rolling.h5");
  sable::save_snapshot(a, {}, "scenario", good);
  const std::string pairs = "/neighbors/pairs/roll", walls = "/neighbors/wall_pairs/roll";
  const std::vector<double> springs = read_doubles(good, pairs);
  const std::vector<double> wall_springs = read_doubles(good, walls);
  const hsize_t n = a.neighbors.pairs.size(), nw = a.neighbors.wall_pairs.size();
  ASSERT_EQ(springs.size(), 3 * n);
  ASSERT_EQ(wall_springs.size(), 3 * nw);
  ASSERT_GT(n, 2u);
  ASSERT_GT(nw, 0u);

  World<3> w = make_world<3>(false, true);
  const std::uint64_t before = sable::state_hash(w);
  auto corrupt = [&](const std::string& name, const std::string& dataset, hsize_t rows,
                     std::vector<double> values) {
    const std::string file = path(name);
    fs::copy_file(good, file);
    write_doubles(file, dataset, rows, 3, values);
    std::string msg = load_error(file, w);
    EXPECT_TRUE(contains(msg, file));
    EXPECT_EQ(sable::state_hash(w), before) << name;
    return msg;
  };

  std::string msg =
      corrupt("short.h5", pairs, n - 1, std::vector<double>(springs.begin(), springs.end() - 3));
  EXPECT_TRUE(contains(msg, "'" + pairs + "' has " + std::to_string(n - 1) + " rows, expected " +
                                std::to_string(n)));
  EXPECT_TRUE(contains(msg, "one per pair"));
  std::vector<double> values = wall_springs;
  values.insert(values.end(), {0.0, 0.0, 0.0});
  msg = corrupt("long.h5", walls, nw + 1, values);
  EXPECT_TRUE(contains(msg, "'" + walls + "' has " + std::to_string(nw + 1) + " rows"));

  values = springs;
  values[3 * 2 + 1] = std::numeric_limits<double>::quiet_NaN();
  msg = corrupt("nan.h5", pairs, n, values);
  EXPECT_TRUE(contains(msg, "'" + pairs + "' row 2 is not finite"));
  values = wall_springs;
  values[0] = -std::numeric_limits<double>::infinity();
  msg = corrupt("inf.h5", walls, nw, values);
  EXPECT_TRUE(contains(msg, "'" + walls + "' row 0 is not finite"));

  values = springs;  // a wound spring moved by one ulp: finite, the right shape, other bits
  std::size_t k = 0;
  while (k < values.size() && values[k] == 0.0) ++k;
  ASSERT_LT(k, values.size()) << "no wound spring to alter";
  values[k] = std::nextafter(values[k], 1.0);
  msg = corrupt("altered.h5", pairs, n, values);
  EXPECT_TRUE(contains(msg, "attribute 'state_hash'"));

  const std::string missing = path("missing.h5");
  fs::copy_file(good, missing);
  {
    const hid_t f = H5Fopen(missing.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    H5Ldelete(f, walls.c_str(), H5P_DEFAULT);
    H5Fclose(f);
  }
  EXPECT_TRUE(contains(load_error(missing, w), "missing dataset '" + walls + "'"));
  EXPECT_EQ(sable::state_hash(w), before);

  sable::load_snapshot(good, w);  // the good file loads into the same world
  EXPECT_EQ(sable::state_hash(w), sable::state_hash(a));
  EXPECT_EQ(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL), 0) << "leaked HDF5 handles";
}

// ---------------------------------------------------------------- atomic writes

// Guards: snapshots are written through a temporary that is renamed into place, so none is
// left behind, and overwriting an existing snapshot leaves a complete file holding the newer
// state (hash equality, exact).
TEST_F(IoTest, SnapshotWritesAreAtomic) {
  World<3> w = make_world<3>();
  sable::DemSolver<3> s(w);
  s.initialize();
  const std::string file = path("latest.h5");
  sable::save_snapshot(w, {0, 0}, "x", file);
  EXPECT_TRUE(temporaries().empty());
  for (int k = 0; k < 5; ++k) s.step();
  sable::save_snapshot(w, {0, 5}, "x", file);
  EXPECT_TRUE(temporaries().empty());
  World<3> r = make_world<3>(false);
  EXPECT_EQ(sable::load_snapshot(file, r), (RunPosition{0, 5}));
  EXPECT_EQ(sable::state_hash(r), sable::state_hash(w));

  // A directory that does not exist: an IoError naming the file, nothing left behind.
  const std::string nowhere = path("no/such/dir/latest.h5");
  try {
    sable::save_snapshot(w, {}, "x", nowhere);
    ADD_FAILURE() << "expected an IoError";
  } catch (const sable::IoError& e) {
    EXPECT_TRUE(contains(e.what(), nowhere));
  }
  EXPECT_TRUE(temporaries().empty());
}

// Guards: a writer that fails half-way (as a killed run would) leaves the previous file
// intact and no temporary; text files are replaced whole.
TEST_F(IoTest, FailedAtomicWriteKeepsTheOldFile) {
  const std::string file = path("energy.txt");
  sable::write_text_atomic(file, "old\n");
  EXPECT_THROW(sable::write_atomic(file,
                                   [](const std::string& tmp) {
                                     write_file(tmp, "half");
                                     throw std::runtime_error("killed");
                                   }),
               std::runtime_error);
  EXPECT_EQ(read_file(file), "old\n");
  EXPECT_TRUE(temporaries().empty());
  sable::write_text_atomic(file, "new\n");
  EXPECT_EQ(read_file(file), "new\n");
  try {
    sable::write_text_atomic(path("missing/x.txt"), "x");
    ADD_FAILURE() << "expected an IoError";
  } catch (const sable::IoError& e) {
    EXPECT_TRUE(contains(e.what(), path("missing/x.txt")));
  }
}

// ---------------------------------------------------------------- CSV

// Guards: a resumed CSV log keeps the header and the rows up to the snapshot's step and drops
// the later ones (and a half-written last line), so no step appears twice; values are exact
// text, compared as strings.
TEST_F(IoTest, CsvResumeTruncatesLaterRows) {
  const std::string file = path("energy.csv");
  const std::vector<std::string> header = {"step", "time_s", "kinetic_energy_J"};
  {
    sable::CsvLog log(file, header);
    for (int s = 0; s <= 10; ++s) log.row({double(s), s * 1e-5, 0.5 / (s + 1)});
  }
  { std::ofstream(file, std::ios::app) << "11,0.00011,0.04"; }  // cut off mid-line
  {
    sable::CsvLog log(file, header, 5);
    log.row({6, 6e-5, 1.0 / 14});
  }
  std::istringstream lines(read_file(file));
  std::vector<std::string> got;
  for (std::string line; std::getline(lines, line);) got.push_back(line);
  ASSERT_EQ(got.size(), 1u + 7u);
  EXPECT_EQ(got[0], "step,time_s,kinetic_energy_J");
  EXPECT_EQ(got[1], "0,0,0.5");
  EXPECT_EQ(got[6], "5,5e-05,0.08333333333");
  EXPECT_EQ(got[7], "6,6e-05,0.07142857143");

  // A fresh (non-resumed) log truncates; big integral steps are written exactly.
  {
    sable::CsvLog log(file, header);
    log.row({12345678901.0, 0.25, 1.0});
  }
  EXPECT_EQ(read_file(file), "step,time_s,kinetic_energy_J\n12345678901,0.25,1\n");

  // Resuming with other columns is refused, naming the file; a missing file is created.
  try {
    sable::CsvLog log(file, {"step", "time_s"}, 3);
    ADD_FAILURE() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_TRUE(contains(e.what(), file));
  }
  { sable::CsvLog log(path("new.csv"), header, 7); }
  EXPECT_EQ(read_file(path("new.csv")), "step,time_s,kinetic_energy_J\n");
  EXPECT_THROW(sable::CsvLog(path("no/dir/x.csv"), header), sable::IoError);
  EXPECT_TRUE(temporaries().empty());
}

}  // namespace
