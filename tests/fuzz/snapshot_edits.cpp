#include "snapshot_edits.hpp"

#include <hdf5.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <limits>
#include <sstream>

#include "sable/scenario/config.hpp"
#include "sable/scenario/runner.hpp"

namespace sable::fuzz {

namespace {

namespace fs = std::filesystem;

// ------------------------------------------------------------------------- seed snapshots

// Each writes its snapshot at the end of its last stage, into `{out}/snapshots/`.
const char* const kCommon = R"(
[[material]]
name = "g"
density = 2500.0
young = 5e6
poisson = 0.3
friction = 0.4
restitution = 0.5
rolling_friction = ROLLING
[output]
dir = "{out}"
csv_interval = 0
vtk_interval = 0
snapshot_interval = 0
log_interval = 0
vtk_contacts = false
vtk_walls = false
)";

struct Seed {
  const char* name;
  const char* rolling;  // the material's rolling_friction
  const char* text;
};

const Seed kSeeds[] = {
    {"dem-2d", "0.0", R"(
[simulation]
dimension = 2
seed = 3
gravity = [0, -9.81]
thickness = 0.002
[domain]
lo = [0, 0]
hi = [0.02, 0.02]
[[grains]]
generator = "random"
material = "g"
radius = { distribution = "uniform", mean = 1e-3, spread = 0.2 }
region = { box = { lo = [0, 0], hi = [0.02, 0.02] } }
count = 24
[[wall]]
name = "box"
type = "box"
material = "g"
lo = [0, 0]
hi = [0.02, 0.02]
[[stage]]
steps = 2000
)"},
    {"dem-3d-rolling", "0.1", R"(
[simulation]
dimension = 3
seed = 4
gravity = [0, 0, -9.81]
# The jittered lattice starts in contact on purpose: springs and history to edit.
initial_overlap = 0.5
[domain]
lo = [0, 0, 0]
hi = [0.01, 0.01, 0.02]
[contact]
rolling = "epsd"
[[grains]]
generator = "lattice"
material = "g"
radius = 1e-3
region = { box = { lo = [0, 0, 0], hi = [0.01, 0.01, 0.02] } }
count = 20
jitter = 1e-4
[[wall]]
name = "floor"
material = "g"
point = [0, 0, 0]
normal = [0, 0, 1]
[[stage]]
steps = 1500
)"},
    {"dem-3d-wet", "0.0", R"(
[simulation]
dimension = 3
seed = 5
[domain]
lo = [0, 0, 0]
hi = [0.008, 0.008, 0.008]
[contact]
cohesion = "capillary"
[[grains]]
generator = "lattice"
material = "g"
radius = 1e-3
region = { box = { lo = [0, 0, 0], hi = [0.008, 0.008, 0.008] } }
count = 12
[[stage]]
steps = 10
[[stage]]
steps = 50
water_content = 0.01
)"},
    {"cd-2d", "0.0", R"(
[simulation]
dimension = 2
solver = "cd"
dt = 1e-4
seed = 6
# The jittered lattice starts in contact on purpose: contacts to edit.
initial_overlap = 0.5
gravity = [0, -9.81]
thickness = 0.002
[domain]
lo = [0, 0]
hi = [0.012, 0.02]
[[grains]]
generator = "lattice"
material = "g"
radius = 1e-3
region = { box = { lo = [0, 0], hi = [0.012, 0.02] } }
count = 18
jitter = 1e-4
[[wall]]
name = "box"
type = "box"
material = "g"
lo = [0, 0]
hi = [0.012, 0.02]
[[stage]]
steps = 300
)"},
};

std::string replace_all(std::string s, const std::string& from, const std::string& to) {
  for (std::size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size()))
    s.replace(at, from.size(), to);
  return s;
}

// The newest snapshot a run wrote (end_of_stage_N.h5 for the largest N).
std::string last_snapshot(const fs::path& out) {
  std::string last;
  for (const auto& e : fs::directory_iterator(out / "snapshots"))
    if (e.path().extension() == ".h5" && e.path().string() > last) last = e.path().string();
  return last;
}

}  // namespace

SeedSnapshots::SeedSnapshots() {
  // Keep what HDF5 frees for reuse, without limit: each file opened allocates a metadata
  // cache of about a megabyte, which HDF5's default limits hand back to malloc, and ASan's
  // allocator then maps and faults in afresh, page by page (most of an input's time).
  H5set_free_list_limits(-1, -1, -1, -1, -1, -1);
  const fs::path base = fs::exists("/dev/shm") ? fs::path("/dev/shm") : fs::temp_directory_path();
  dir_ = base / ("sable-fuzz-snapshot-" + std::to_string(::getpid()));
  fs::remove_all(dir_);
  fs::create_directories(dir_);
  for (const Seed& s : kSeeds) {
    const fs::path out = dir_ / s.name;
    const std::string text = std::string(s.text) + replace_all(kCommon, "ROLLING", s.rolling);
    const ScenarioConfig cfg = parse_scenario(replace_all(text, "{out}", out.string()), s.name);
    std::ostringstream log;
    RunOptions opt;
    opt.log = &log;
    opt.live_progress = false;
    opt.threads = 1;
    run_scenario(cfg, opt);
    paths_.push_back((dir_ / (std::string(s.name) + ".h5")).string());
    fs::copy_file(last_snapshot(out), paths_.back());
  }
}

SeedSnapshots::~SeedSnapshots() {
  std::error_code ec;
  fs::remove_all(dir_, ec);
}

namespace {

// ------------------------------------------------------------------------------ the edits

// Every dataset and attribute of the snapshot layout (io/snapshot.hpp), some absent from
// some seeds (editing an absent one creates it).
const char* const kDatasets[] = {"/scenario",
                                 "/rng_state",
                                 "/particles/x",
                                 "/particles/v",
                                 "/particles/w",
                                 "/particles/f",
                                 "/particles/t",
                                 "/particles/q",
                                 "/particles/radius",
                                 "/particles/inv_mass",
                                 "/particles/mass",
                                 "/particles/inv_inertia",
                                 "/particles/material",
                                 "/particles/flags",
                                 "/particles/shape",
                                 "/particles/id",
                                 "/particles/ids/slots",
                                 "/particles/ids/generations",
                                 "/particles/ids/free_list",
                                 "/walls/names",
                                 "/walls/point",
                                 "/walls/velocity",
                                 "/walls/force",
                                 "/neighbors/domain_lo",
                                 "/neighbors/domain_hi",
                                 "/neighbors/x_ref",
                                 "/neighbors/wall_ref",
                                 "/neighbors/pairs/i",
                                 "/neighbors/pairs/j",
                                 "/neighbors/pairs/shear",
                                 "/neighbors/pairs/force",
                                 "/neighbors/pairs/roll",
                                 "/neighbors/pairs/bridge",
                                 "/neighbors/wall_pairs/i",
                                 "/neighbors/wall_pairs/wall",
                                 "/neighbors/wall_pairs/shear",
                                 "/neighbors/wall_pairs/force",
                                 "/neighbors/wall_pairs/roll",
                                 "/liquid/film"};

struct Attr {
  const char* object;
  const char* name;
};
const Attr kAttrs[] = {{"/", "format"},
                       {"/", "version"},
                       {"/", "dimension"},
                       {"/", "step"},
                       {"/", "time"},
                       {"/", "dt"},
                       {"/", "stage"},
                       {"/", "stage_step"},
                       {"/", "state_hash"},
                       {"/neighbors", "skin"},
                       {"/neighbors", "builds"},
                       {"/liquid", "total"},
                       {"/liquid", "lost"}};

// The types an edit may give a dataset or attribute.
hid_t pick_type(Bytes& in) {
  static const hid_t kTypes[] = {H5T_NATIVE_DOUBLE, H5T_NATIVE_UINT64, H5T_NATIVE_UINT32,
                                 H5T_NATIVE_UINT16, H5T_NATIVE_UINT8,  H5T_NATIVE_INT32};
  const std::uint64_t k = in.below(std::size(kTypes) + 1);
  if (k < std::size(kTypes)) return H5Tcopy(kTypes[k]);
  const hid_t s = H5Tcopy(H5T_C_S1);
  H5Tset_size(s, 1 + in.below(16));
  H5Tset_cset(s, in.below(2) == 0 ? H5T_CSET_UTF8 : H5T_CSET_ASCII);
  return s;
}

// A dataset as it is in the file: its type, dimensions and values (the values only when
// they take at most 1 MiB: a dataset an earlier edit made huge is not read).
struct Data {
  hid_t type = -1;
  std::vector<hsize_t> dims;
  std::vector<std::uint8_t> bytes;
  Data() = default;
  Data(const Data&) = delete;
  Data& operator=(const Data&) = delete;
  ~Data() {
    if (type >= 0) H5Tclose(type);
  }
  std::size_t points() const {
    std::size_t n = 1;
    for (hsize_t d : dims) n *= static_cast<std::size_t>(d);
    return n;
  }
};

// A dataset with values that read() left in the file (too large to rewrite).
bool unread(const Data& d) {
  return d.bytes.empty() && d.points() != 0;
}

bool read(hid_t f, const char* name, Data& out) {
  const hid_t d = H5Dopen2(f, name, H5P_DEFAULT);
  if (d < 0) return false;
  out.type = H5Dget_type(d);
  const hid_t space = H5Dget_space(d);
  const int rank = H5Sget_simple_extent_ndims(space);
  out.dims.assign(static_cast<std::size_t>(std::max(rank, 0)), 0);
  if (rank > 0) H5Sget_simple_extent_dims(space, out.dims.data(), nullptr);
  // From the dimensions: HDF5's count of points is signed and wraps negative past 2^63 (a
  // dataset an edit made 2^62 rows of 2 columns).
  double bytes = static_cast<double>(H5Tget_size(out.type));
  for (const hsize_t n : out.dims) bytes *= static_cast<double>(n);
  if (H5Tis_variable_str(out.type) <= 0 && bytes <= (1 << 20)) {
    out.bytes.assign(static_cast<std::size_t>(bytes), 0);
    if (!out.bytes.empty() &&
        H5Dread(d, out.type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.bytes.data()) < 0)
      out.bytes.clear();
  }
  H5Sclose(space);
  H5Dclose(d);
  return out.type >= 0;
}

// Replaces (or creates) dataset `name`; `huge` makes it chunked or late-allocated with
// nothing written, whatever its dimensions claim.
void write(hid_t f, const char* name, hid_t type, const std::vector<hsize_t>& dims,
           const std::vector<std::uint8_t>& bytes, bool huge = false) {
  H5Ldelete(f, name, H5P_DEFAULT);
  const hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
  H5Pset_create_intermediate_group(lcpl, 1);
  const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
  if (huge && !dims.empty()) {
    std::vector<hsize_t> chunk(dims.size(), 1);
    chunk[0] = 64;
    H5Pset_chunk(dcpl, static_cast<int>(dims.size()), chunk.data());
  }
  const hid_t space = dims.empty()
                          ? H5Screate(H5S_SCALAR)
                          : H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr);
  const hid_t d = H5Dcreate2(f, name, type, space, lcpl, dcpl, H5P_DEFAULT);
  std::size_t points = 1;
  for (hsize_t n : dims) points *= static_cast<std::size_t>(n);
  if (d >= 0 && !huge && points > 0 && bytes.size() >= points * H5Tget_size(type))
    H5Dwrite(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, bytes.data());
  if (d >= 0) H5Dclose(d);
  H5Sclose(space);
  H5Pclose(dcpl);
  H5Pclose(lcpl);
}

// `n` bytes: the input's next ones while they last, then zeros.
std::vector<std::uint8_t> fill(Bytes& in, std::size_t n) {
  std::vector<std::uint8_t> out(n, 0);
  for (std::size_t k = 0; k < n && !in.empty(); ++k) out[k] = in.byte();
  return out;
}

void set_value(hid_t f, const char* name, Bytes& in) {
  Data d;
  if (!read(f, name, d) || d.bytes.empty()) return;
  const std::size_t size = H5Tget_size(d.type);
  std::uint8_t* at = d.bytes.data() + in.below(d.points()) * size;
  const std::uint64_t how = in.below(3);
  if (how == 0) {  // raw bit pattern
    for (std::size_t k = 0; k < size; ++k) at[k] = in.byte();
  } else if (how == 1) {  // an index or count nudged by a little
    std::uint64_t v = 0;
    std::memcpy(&v, at, std::min(size, sizeof v));
    v += in.below(5) - 2;
    std::memcpy(at, &v, std::min(size, sizeof v));
  } else if (H5Tget_class(d.type) == H5T_FLOAT && size == sizeof(double)) {
    constexpr double inf = std::numeric_limits<double>::infinity();
    const double specials[] = {std::numeric_limits<double>::quiet_NaN(),
                               inf,
                               -inf,
                               0.0,
                               -0.0,
                               -1.0,
                               1e300,
                               -1e300,
                               5e-324};
    std::memcpy(at, &specials[in.below(std::size(specials))], sizeof(double));
  } else {  // integer extremes
    const std::uint64_t specials[] = {
        0, 1, 0xffffffffffffffffULL, 0xfffffffeULL, 0x80000000ULL, d.dims.empty() ? 0 : d.dims[0]};
    std::memcpy(at, &specials[in.below(std::size(specials))],
                std::min(size, sizeof(std::uint64_t)));
  }
  write(f, name, d.type, d.dims, d.bytes);
}

// New row count (or a created dataset of doubles), the old rows kept as far as they go.
void resize(hid_t f, const char* name, Bytes& in) {
  Data d;
  if (!read(f, name, d)) {
    d.type = H5Tcopy(H5T_NATIVE_DOUBLE);
    d.dims = {0, 1 + in.below(4)};
  }
  if (unread(d)) return;
  if (d.dims.empty()) d.dims = {1};
  const hsize_t rows = d.dims[0];
  const hsize_t choices[] = {0, rows > 0 ? rows - 1 : 0, rows + 1, 2 * rows, in.below(64)};
  d.dims[0] = choices[in.below(std::size(choices))];
  std::vector<std::uint8_t> bytes = fill(in, d.points() * H5Tget_size(d.type));
  std::copy_n(d.bytes.begin(), std::min(d.bytes.size(), bytes.size()), bytes.begin());
  write(f, name, d.type, d.dims, bytes);
}

// Another type, or another shape (a scalar, 1-D, 2-D with other columns, 3-D).
void retype_or_reshape(hid_t f, const char* name, Bytes& in, bool retype) {
  Data d;
  if (!read(f, name, d) || unread(d)) return;
  const hsize_t rows = d.dims.empty() ? 1 : d.dims[0];
  hid_t type = d.type;
  if (retype) {
    type = pick_type(in);
  } else {
    const std::uint64_t rank = in.below(4);
    d.dims.clear();
    if (rank >= 1) d.dims.push_back(rows);
    if (rank >= 2) d.dims.push_back(in.below(6));
    if (rank >= 3) d.dims.push_back(2);
  }
  write(f, name, type, d.dims, fill(in, d.points() * H5Tget_size(type)));
  if (retype) H5Tclose(type);
}

// The same columns, 2^20 to 2^62 rows claimed, none stored.
void make_huge(hid_t f, const char* name, Bytes& in) {
  Data d;
  if (!read(f, name, d)) return;
  if (d.dims.empty()) d.dims = {1};
  d.dims[0] = hsize_t{1} << (20 + in.below(43));
  write(f, name, d.type, d.dims, {}, true);
}

void set_attr(hid_t f, const Attr& a, Bytes& in) {
  H5Adelete_by_name(f, a.object, a.name, H5P_DEFAULT);
  const hid_t type = pick_type(in);
  const bool pair = in.below(8) == 0;  // an array of 2 instead of a single value
  const hsize_t two = 2;
  const hid_t space = pair ? H5Screate_simple(1, &two, nullptr) : H5Screate(H5S_SCALAR);
  const hid_t id =
      H5Acreate_by_name(f, a.object, a.name, type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  if (id >= 0) {
    const auto bytes = fill(in, (pair ? 2 : 1) * H5Tget_size(type));
    H5Awrite(id, type, bytes.data());
    H5Aclose(id);
  }
  H5Sclose(space);
  H5Tclose(type);
}

// A few bytes of the stored scenario text replaced, inserted or cut.
void edit_scenario(hid_t f, Bytes& in) {
  Data d;
  if (!read(f, "/scenario", d) || d.bytes.empty()) return;
  std::string text(d.bytes.begin(), d.bytes.end());
  text = text.substr(0, text.find('\0'));
  for (std::uint64_t n = 1 + in.below(4); n > 0 && !text.empty(); --n) {
    const std::size_t at = static_cast<std::size_t>(in.below(text.size()));
    switch (in.below(3)) {
      case 0:
        text[at] = static_cast<char>(in.byte());
        break;
      case 1:
        text.insert(at, in.text(16));
        break;
      default:
        text.erase(at, static_cast<std::size_t>(in.below(64)));
    }
  }
  const hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, text.size() + 1);
  H5Tset_cset(type, H5T_CSET_UTF8);  // as Sable writes it
  write(f, "/scenario", type, {},
        std::vector<std::uint8_t>(text.c_str(), text.c_str() + text.size() + 1));
  H5Tclose(type);
}

}  // namespace

void apply_edits(const std::string& path, Bytes& in) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  if (f < 0) return;
  for (std::uint64_t n = in.below(9); n > 0 && !in.empty(); --n) {
    const char* dset = kDatasets[in.below(std::size(kDatasets))];
    switch (in.below(9)) {
      case 0:
      case 1:
        set_value(f, dset, in);
        break;
      case 2:
        resize(f, dset, in);
        break;
      case 3:
        H5Ldelete(f, dset, H5P_DEFAULT);
        break;
      case 4:
        retype_or_reshape(f, dset, in, true);
        break;
      case 5:
        retype_or_reshape(f, dset, in, false);
        break;
      case 6:
        make_huge(f, dset, in);
        break;
      case 7: {
        const Attr& a = kAttrs[in.below(std::size(kAttrs))];
        if (in.below(4) == 0)
          H5Adelete_by_name(f, a.object, a.name, H5P_DEFAULT);
        else
          set_attr(f, a, in);
        break;
      }
      default:
        edit_scenario(f, in);
    }
  }
  H5Fclose(f);
}

}  // namespace sable::fuzz
