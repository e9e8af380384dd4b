// Damaged and crafted snapshots: sizes the file claims but does not hold, and the integrity
// check of `sable info`. A crafted snapshot claiming 2^40 grains ended in "error:
// std::bad_alloc" (no file named) on resume and analyze, and `sable info` called it valid; a
// snapshot with two flipped bits in a data array was reported fine by `sable info`.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "run_helpers.hpp"
#include "sable/core/error.hpp"
#include "sable/io/snapshot.hpp"
#include "sable/scenario/build.hpp"
#include "sable/scenario/config.hpp"
#include "sable/scenario/verify.hpp"

namespace sable {
namespace {

namespace fs = std::filesystem;

// Eight disks settling on a floor for 300 steps: a snapshot with grains, walls and contacts.
std::string scenario(const std::string& out) {
  return "[simulation]\ndimension = 2\nseed = 2\ngravity = [0, -9.81]\nthickness = 0.002\n"
         "[domain]\nlo = [0, 0]\nhi = [0.008, 0.008]\n"
         "[[material]]\nname = \"g\"\ndensity = 2500.0\nyoung = 5e6\npoisson = 0.3\n"
         "friction = 0.4\n"
         "[[grains]]\ngenerator = \"lattice\"\nmaterial = \"g\"\nradius = 1e-3\n"
         "region = { box = { lo = [0, 0], hi = [0.008, 0.008] } }\ncount = 8\n"
         "[[wall]]\nname = \"box\"\ntype = \"box\"\nmaterial = \"g\"\nlo = [0, 0]\n"
         "hi = [0.008, 0.008]\n"
         "[[stage]]\nsteps = 300\n"
         "[output]\ndir = \"" +
         out +
         "\"\ncsv_interval = 0\nvtk_interval = 0\nlog_interval = 0\nvtk_contacts = false\n"
         "vtk_walls = false\n";
}

class SnapshotBounds : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("sable_snapbounds_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    text_ = scenario((dir_ / "run").string());
    std::ofstream(dir_ / "scenario.toml") << text_;
    test::run_text(text_);
    good_ = (dir_ / "run" / "snapshots" / "end_of_stage_1.h5").string();
  }
  void TearDown() override { fs::remove_all(dir_); }

  // A copy of the good snapshot, to damage.
  std::string copy(const std::string& name) const {
    std::string p = (dir_ / name).string();
    fs::copy_file(good_, p, fs::copy_options::overwrite_existing);
    return p;
  }
  // Loads `path` as a resume does: the message of the InputError, or "" and the stored
  // scenario text in `stored`.
  std::string load(const std::string& path, std::string* stored = nullptr) const {
    const ScenarioConfig cfg = parse_scenario(text_, "scenario.toml");
    World<2> w;
    build_model(cfg, w);
    try {
      load_snapshot(path, w, stored);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
  int cli(const std::string& args, std::string& out) const {
    return test::run_cli(args, dir_ / "cli.log", out);
  }

  fs::path dir_;
  std::string text_, good_;
};

::testing::AssertionResult has(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "\"" << text << "\" lacks \"" << part << "\"";
}

// Replaces dataset `name` by one of the same type and columns claiming `rows` rows, with
// nothing stored: chunked (no chunk written) or contiguous (allocated when first written).
void claim_rows(const std::string& file, const std::string& name, hsize_t rows, bool chunked) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  const hid_t d = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
  const hid_t type = H5Dget_type(d), space = H5Dget_space(d);
  hsize_t dims[2] = {0, 0};
  const int rank = H5Sget_simple_extent_ndims(space);
  H5Sget_simple_extent_dims(space, dims, nullptr);
  H5Sclose(space);
  H5Dclose(d);
  H5Ldelete(f, name.c_str(), H5P_DEFAULT);
  dims[0] = rows;
  const hid_t huge = H5Screate_simple(rank, dims, nullptr);
  const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
  const hsize_t chunk[2] = {1024, rank == 2 ? dims[1] : 1};
  if (chunked) H5Pset_chunk(dcpl, rank, chunk);
  const hid_t nd = H5Dcreate2(f, name.c_str(), type, huge, H5P_DEFAULT, dcpl, H5P_DEFAULT);
  EXPECT_GE(nd, 0);
  H5Dclose(nd);
  H5Pclose(dcpl);
  H5Sclose(huge);
  H5Tclose(type);
  H5Fclose(f);
}

constexpr hsize_t k2to40 = hsize_t{1} << 40;

// Guards: a dataset claiming 2^40 rows with nothing stored (chunked or contiguous) is refused
// by every reader, naming the file, the dataset, the values claimed and the bytes stored,
// before anything is allocated.
TEST_F(SnapshotBounds, CraftedRowCountsAreRefusedNamingTheDataset) {
  for (const bool chunked : {true, false}) {
    const std::string x = copy(chunked ? "x_chunked.h5" : "x_contiguous.h5");
    claim_rows(x, "/particles/x", k2to40, chunked);
    const std::string expected = "snapshot '" + x +
                                 "': dataset '/particles/x' claims 2199023255552 values of 8 "
                                 "bytes, but the file stores 0 bytes of them";
    EXPECT_TRUE(has(load(x), expected));
    try {
      read_snapshot_info(x);
      ADD_FAILURE() << "read_snapshot_info accepted " << x;
    } catch (const InputError& e) {
      EXPECT_TRUE(has(e.what(), expected));
    }
  }
  // One per kind of reader: counts (ids, pairs), strings; a dataset whose rows must match
  // the grains' is refused by its row count first.
  for (const char* name : {"/particles/ids/slots", "/neighbors/pairs/i", "/walls/names"}) {
    const std::string p = copy("rows.h5");
    claim_rows(p, name, k2to40, true);
    EXPECT_TRUE(
        has(load(p), std::string("dataset '") + name + "' claims 1099511627776 values of "));
  }
  const std::string p = copy("radius.h5");
  claim_rows(p, "/particles/radius", k2to40, true);
  EXPECT_TRUE(has(load(p), "dataset '/particles/radius' has 1099511627776 rows, expected 8"));
}

// Guards: a string dataset claiming 2 GiB of text with nothing stored is refused (its buffer
// would have been allocated from the claimed width).
TEST_F(SnapshotBounds, CraftedStringWidthIsRefused) {
  const std::string p = copy("text.h5");
  const hid_t f = H5Fopen(p.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  H5Ldelete(f, "/scenario", H5P_DEFAULT);
  const hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, hsize_t{1} << 31);
  const hid_t space = H5Screate(H5S_SCALAR);
  H5Dclose(H5Dcreate2(f, "/scenario", type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
  H5Sclose(space);
  H5Tclose(type);
  H5Fclose(f);
  try {
    read_snapshot_info(p);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_TRUE(has(e.what(), "dataset '/scenario' claims 1 values of 2147483648 bytes"));
  }
}

// Guards: a compressed dataset (chunked + deflate, as h5repack -f GZIP=9 writes) still loads,
// its state hash intact: the bound on stored bytes allows deflate's largest ratio.
TEST_F(SnapshotBounds, CompressedDatasetsStillLoad) {
  if (H5Zfilter_avail(H5Z_FILTER_DEFLATE) <= 0) GTEST_SKIP() << "no deflate in this libhdf5";
  const std::string p = copy("gzip.h5");
  const hid_t f = H5Fopen(p.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  const hid_t d = H5Dopen2(f, "/particles/x", H5P_DEFAULT);
  const hid_t space = H5Dget_space(d);
  std::vector<double> x(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
  H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, x.data());
  H5Dclose(d);
  H5Ldelete(f, "/particles/x", H5P_DEFAULT);
  const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
  const hsize_t chunk[2] = {4, 2};
  H5Pset_chunk(dcpl, 2, chunk);
  H5Pset_deflate(dcpl, 9);
  const hid_t nd =
      H5Dcreate2(f, "/particles/x", H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
  H5Dwrite(nd, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, x.data());
  H5Dclose(nd);
  H5Pclose(dcpl);
  H5Sclose(space);
  H5Fclose(f);
  EXPECT_EQ(load(p), "");  // the state hash is checked on loading
}

// Replaces the snapshot's /scenario by `text` stored as a fixed-length ASCII string (HDF5's
// default string type; Sable writes UTF-8).
void store_ascii_scenario(const std::string& file, const std::string& text) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  H5Ldelete(f, "/scenario", H5P_DEFAULT);
  const hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, text.size() + 1);
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t d = H5Dcreate2(f, "/scenario", type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  H5Dwrite(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, text.c_str());
  H5Dclose(d);
  H5Sclose(space);
  H5Tclose(type);
  H5Fclose(f);
}

// Guards: a string stored as ASCII, as other tools write them (Sable writes UTF-8), is read:
// HDF5 converts neither way between the two, and the reader asked for UTF-8 ("no appropriate
// function for conversion path").
TEST_F(SnapshotBounds, AsciiStringsAreRead) {
  const std::string p = copy("ascii.h5");
  store_ascii_scenario(p, text_);
  std::string stored;
  EXPECT_EQ(load(p, &stored), "");
  EXPECT_EQ(stored, text_);
}

// Rewrites value `k` of dataset `name` (doubles) to `value`.
void set_double(const std::string& file, const std::string& name, std::size_t k, double value) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  const hid_t d = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
  const hid_t space = H5Dget_space(d);
  std::vector<double> v(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
  H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  v.at(k) = value;
  H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  H5Sclose(space);
  H5Dclose(d);
  H5Fclose(f);
}

// Guards: values the solvers divide by or size arrays with are checked whatever the state
// hash says (a hash is a checksum, not a signature: a crafted file can match it), naming the
// grain or dataset: a radius of 0, a NaN mass, a NaN domain bound, reference positions for
// other grains than the file's.
TEST_F(SnapshotBounds, ImpossibleValuesAreRefused) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::string p = copy("radius.h5");
  set_double(p, "/particles/radius", 2, 0.0);
  EXPECT_TRUE(has(load(p), "grain 2 has radius 0, mass "));
  p = copy("mass.h5");
  set_double(p, "/particles/mass", 5, nan);
  EXPECT_TRUE(has(load(p), "grain 5 has radius 0.001, mass nan,"));
  p = copy("domain.h5");
  set_double(p, "/neighbors/domain_lo", 1, nan);
  EXPECT_TRUE(has(load(p), "'/neighbors/domain_lo' and 'domain_hi' are nan and 0.008 on axis 1"));
  p = copy("x_ref.h5");
  const hid_t f = H5Fopen(p.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  H5Ldelete(f, "/neighbors/x_ref", H5P_DEFAULT);
  const hsize_t dims[2] = {3, 2};
  const double zeros[6] = {};
  const hid_t space = H5Screate_simple(2, dims, nullptr);
  const hid_t d = H5Dcreate2(f, "/neighbors/x_ref", H5T_NATIVE_DOUBLE, space, H5P_DEFAULT,
                             H5P_DEFAULT, H5P_DEFAULT);
  H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, zeros);
  H5Dclose(d);
  H5Sclose(space);
  H5Fclose(f);
  EXPECT_TRUE(has(load(p), "dataset '/neighbors/x_ref' has 3 rows, expected 0 or 8"));
}

// Guards: the CLI names the file and the dataset (exit 2) for `info`, `analyze` and
// `run --resume`, where it printed "error: std::bad_alloc" (info: nothing wrong).
TEST_F(SnapshotBounds, CliRefusesCraftedSnapshotsNamingThem) {
  if (!fs::exists(SABLE_CLI)) GTEST_SKIP() << SABLE_CLI << " not built";
  const std::string x = copy("crafted.h5");
  claim_rows(x, "/particles/x", k2to40, true);
  const std::string expected = "error: snapshot '" + x + "': dataset '/particles/x' claims";
  std::string out;
  EXPECT_EQ(cli("info " + x, out), 2);
  EXPECT_TRUE(has(out, expected));
  EXPECT_EQ(cli("analyze " + x + " --out " + (dir_ / "analysis").string(), out), 2);
  EXPECT_TRUE(has(out, "crafted.h5"));
  EXPECT_TRUE(has(out, "dataset '/particles/x' claims 2199023255552 values"));
  EXPECT_EQ(cli("run " + (dir_ / "scenario.toml").string() + " --resume " + x, out), 2);
  EXPECT_TRUE(has(out, expected));
}

// ---------------------------------------------------------------- integrity (sable info)

// Flips two bits of byte `at` of the values of dataset `name` (stored contiguously) in the
// file's bytes, as a bad disk or transfer would.
void flip_two_bits(const std::string& file, const std::string& name, std::size_t at) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t d = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
  const haddr_t offset = H5Dget_offset(d);
  H5Dclose(d);
  H5Fclose(f);
  ASSERT_NE(offset, HADDR_UNDEF);
  std::fstream io(file, std::ios::in | std::ios::out | std::ios::binary);
  io.seekg(static_cast<std::streamoff>(offset + at));
  char c = 0;
  io.get(c);
  c = static_cast<char>(c ^ 0x11);
  io.seekp(static_cast<std::streamoff>(offset + at));
  io.put(c);
}

// Guards: `sable info` loads the whole state and compares its hash: an intact snapshot is
// "verified", one with two flipped bits in a data array (which resume refuses) FAILED with the
// reason, exit 2; so is one whose value was rewritten through HDF5.
TEST_F(SnapshotBounds, InfoVerifiesTheStateHash) {
  EXPECT_TRUE(verify_snapshot(good_).verified) << verify_snapshot(good_).problem;
  const std::string flipped = copy("flipped.h5");
  flip_two_bits(flipped, "/particles/v", 8 * 5 + 3);  // the 6th double: grain 2's vx
  const SnapshotIntegrity v = verify_snapshot(flipped);
  EXPECT_FALSE(v.verified);
  EXPECT_TRUE(has(v.problem, "snapshot '" + flipped + "': the loaded state hashes to "));
  EXPECT_TRUE(has(v.problem, "but attribute 'state_hash' on '/' is"));
  // The same refusal as a resume's.
  EXPECT_EQ(load(flipped), v.problem);

  if (!fs::exists(SABLE_CLI)) GTEST_SKIP() << SABLE_CLI << " not built";
  std::string out;
  EXPECT_EQ(cli("info " + good_, out), 0);
  EXPECT_TRUE(has(out, "  integrity   verified (state hash matches)\n"));
  EXPECT_EQ(cli("info " + flipped, out), 2);
  EXPECT_TRUE(has(out, "  state hash  "));  // the header is still shown
  EXPECT_TRUE(
      has(out, "  integrity   FAILED: snapshot '" + flipped + "': the loaded state hashes to "));

  const std::string rewritten = copy("rewritten.h5");
  const hid_t f = H5Fopen(rewritten.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  const hid_t d = H5Dopen2(f, "/particles/radius", H5P_DEFAULT);
  std::vector<double> r(8);
  H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, r.data());
  r[7] *= 1.0 + 1e-15;
  H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, r.data());
  H5Dclose(d);
  H5Fclose(f);
  EXPECT_EQ(cli("info " + rewritten, out), 2);
  EXPECT_TRUE(has(out, "  integrity   FAILED: "));
}

// Guards: a snapshot whose stored scenario no longer parses cannot be verified (its walls
// and materials are what the state is checked against): FAILED, saying so.
TEST_F(SnapshotBounds, InfoFailsWhenTheStoredScenarioDoesNotParse) {
  const std::string p = copy("scenario.h5");
  store_ascii_scenario(p, "[simulation]\ndimension = 2\n");
  const SnapshotIntegrity v = verify_snapshot(p);
  EXPECT_FALSE(v.verified);
  EXPECT_TRUE(has(v.problem, "the scenario stored in the snapshot does not parse: " + p +
                                 " (embedded scenario):1:1: missing required key domain"));
}

}  // namespace
}  // namespace sable
