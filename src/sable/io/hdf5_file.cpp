#include "sable/io/hdf5_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include "sable/core/error.hpp"

namespace sable::h5 {

Id& Id::operator=(Id&& o) noexcept {
  if (this != &o) {
    reset();
    id_ = o.id_;
    closer_ = o.closer_;
    o.id_ = -1;
  }
  return *this;
}

herr_t Id::reset() {
  herr_t status = 0;
  if (id_ >= 0 && closer_ != nullptr) status = closer_(id_);
  id_ = -1;
  return status;
}

void silence_errors() {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

namespace {

herr_t innermost_error(unsigned n, const H5E_error2_t* err, void* data) {
  if (n == 0 && err != nullptr && err->desc != nullptr)
    *static_cast<std::string*>(data) = err->desc;
  return 0;
}

const char* class_name(H5T_class_t c) {
  switch (c) {
    case H5T_INTEGER:
      return "integers";
    case H5T_FLOAT:
      return "floating-point numbers";
    case H5T_STRING:
      return "strings";
    default:
      return "another kind of data";
  }
}

std::string shape_text(int rank, const hsize_t* dims) {
  if (rank == 0) return "a scalar";
  std::string s = "[";
  for (int k = 0; k < rank; ++k) s += fmt::format("{}{}", k > 0 ? " x " : "", dims[k]);
  return s + "]";
}

Id string_type(std::size_t size) {
  Id t(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(t.get(), size);
  H5Tset_strpad(t.get(), H5T_STR_NULLTERM);
  H5Tset_cset(t.get(), H5T_CSET_UTF8);
  return t;
}

void reclaim_strings(hid_t mem, hid_t space, void* buf) {
#if H5_VERSION_GE(1, 12, 0)
  H5Treclaim(mem, space, H5P_DEFAULT, buf);
#else
  H5Dvlen_reclaim(mem, space, H5P_DEFAULT, buf);
#endif
}

// Read the `n` strings of an attribute or dataset stored with file type `ftype` (fixed-length
// or variable-length) through `read(memtype, buffer)`.
template <class Read>
std::vector<std::string> read_text(const File& f, const std::string& what, hid_t ftype, hid_t space,
                                   std::size_t n, Read read) {
  if (H5Tget_class(ftype) != H5T_STRING)
    f.fail(fmt::format("{} holds {}, expected a string", what, class_name(H5Tget_class(ftype))));
  std::vector<std::string> out(n);
  if (n == 0) return out;
  if (H5Tis_variable_str(ftype) > 0) {
    Id mem = string_type(H5T_VARIABLE);
    H5Tset_cset(mem.get(), H5Tget_cset(ftype));  // HDF5 converts neither way between the two
    std::vector<char*> buf(n, nullptr);
    if (read(mem.get(), buf.data()) < 0)
      f.fail(fmt::format("cannot read {}: {}", what, error_detail()));
    for (std::size_t k = 0; k < n; ++k) out[k] = buf[k] != nullptr ? buf[k] : "";
    reclaim_strings(mem.get(), space, buf.data());
    return out;
  }
  // One extra byte per string so a string filling its whole fixed width keeps every character.
  const std::size_t width = H5Tget_size(ftype) + 1;
  Id mem = string_type(width);
  H5Tset_cset(mem.get(), H5Tget_cset(ftype));
  std::vector<char> buf(n * width, '\0');
  if (read(mem.get(), buf.data()) < 0)
    f.fail(fmt::format("cannot read {}: {}", what, error_detail()));
  for (std::size_t k = 0; k < n; ++k) {
    const char* s = buf.data() + k * width;
    out[k].assign(s, strnlen(s, width));
  }
  return out;
}

// File access: closing the file closes everything still open in it; file locking is used
// where the file system supports it and skipped (not an error) where it does not, as on
// some cluster file systems.
Id access_plist() {
  Id fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
  H5Pset_fclose_degree(fapl.get(), H5F_CLOSE_STRONG);
#if H5_VERSION_GE(1, 10, 7)
  H5Pset_file_locking(fapl.get(), true, true);
#endif
  return fapl;
}

}  // namespace

std::string error_detail() {
  std::string detail;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, innermost_error, &detail);
  H5Eclear2(H5E_DEFAULT);
  return detail.empty() ? "no detail from HDF5" : detail;
}

void File::fail(const std::string& what) const {
  if (writing_) throw IoError(label_ + ": " + what);
  throw InputError(label_ + ": " + what);
}

File File::create(const std::string& path, const std::string& label) {
  silence_errors();
  Id fapl = access_plist();
  Id f(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.get()), H5Fclose);
  if (!f.valid()) throw IoError(fmt::format("{}: cannot create: {}", label, error_detail()));
  return File(std::move(f), label, true);
}

File File::create(const std::string& path, const std::string& label, const Collective& c) {
  silence_errors();
  Id f(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, c.file_access), H5Fclose);
  if (!f.valid()) throw IoError(fmt::format("{}: cannot create: {}", label, error_detail()));
  File file(std::move(f), label, true);
  file.collective_ = c;
  return file;
}

File File::open(const std::string& path, const std::string& label, bool writable) {
  silence_errors();
  namespace fs = std::filesystem;
  std::error_code ec;
  const auto status = fs::status(path, ec);
  // A path that names no file may be any text the command line was given: it is quoted
  // clipped. One that names a file is at most PATH_MAX (4096) bytes.
  if (!fs::exists(status) || !fs::is_regular_file(status)) {
    std::string named = label;
    if (const std::size_t at = named.find(path); at != std::string::npos)
      named.replace(at, path.size(), clip(path));
    throw InputError(named +
                     (fs::exists(status) ? ": not a regular file" : ": file does not exist"));
  }
  const htri_t is_h5 = H5Fis_hdf5(path.c_str());
  if (is_h5 == 0) throw InputError(label + ": not an HDF5 file (no HDF5 signature found)");
  if (is_h5 < 0) throw InputError(fmt::format("{}: cannot be read: {}", label, error_detail()));
  Id fapl = access_plist();
  Id f(H5Fopen(path.c_str(), writable ? H5F_ACC_RDWR : H5F_ACC_RDONLY, fapl.get()), H5Fclose);
  if (!f.valid()) {
    throw InputError(fmt::format("{}: cannot open as HDF5 (damaged or truncated file?): {}", label,
                                 error_detail()));
  }
  return File(std::move(f), label, writable);
}

void File::close() {
  if (file_.reset() < 0) fail(fmt::format("cannot finish writing the file: {}", error_detail()));
}

Id File::create_dataset(const std::string& dset, hid_t type, hid_t space, hid_t create_plist) {
  Id lcpl(H5Pcreate(H5P_LINK_CREATE), H5Pclose);
  H5Pset_create_intermediate_group(lcpl.get(), 1);
  Id d(H5Dcreate2(file_.get(), dset.c_str(), type, space, lcpl.get(), create_plist, H5P_DEFAULT),
       H5Dclose);
  if (!d.valid()) fail(fmt::format("cannot create dataset '{}': {}", dset, error_detail()));
  return d;
}

void File::write_whole(const std::string& dset, hid_t d, hid_t type, hid_t space,
                       const void* data) {
  herr_t status = 0;
  if (!collective_) {
    status = H5Dwrite(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data);
  } else if (collective_->root) {
    status = H5Dwrite(d, type, H5S_ALL, H5S_ALL, collective_->transfer, data);
  } else {
    // Every process takes part in a collective write; the others select nothing.
    Id none(H5Scopy(space), H5Sclose);
    H5Sselect_none(none.get());
    status = H5Dwrite(d, type, none.get(), none.get(), collective_->transfer, data);
  }
  if (status < 0) fail(fmt::format("cannot write dataset '{}': {}", dset, error_detail()));
}

void File::write_raw(const std::string& dset, hid_t type, const void* data, hsize_t rows,
                     hsize_t cols) {
  const hsize_t dims[2] = {rows, cols};
  Id space(H5Screate_simple(cols == 0 ? 1 : 2, dims, nullptr), H5Sclose);
  Id d = create_dataset(dset, type, space.get());
  // An empty dataset has nothing to write (and HDF5 rejects a null buffer).
  if (rows * std::max<hsize_t>(cols, 1) == 0) return;
  write_whole(dset, d.get(), type, space.get(), data);
}

void File::write_rows_raw(const std::string& dset, hid_t type, const void* data,
                          const std::vector<std::uint64_t>& rows, hsize_t total, hsize_t cols,
                          const void* fill) {
  const int rank = cols == 0 ? 1 : 2;
  const hsize_t width = std::max<hsize_t>(cols, 1);
  const hsize_t dims[2] = {total, cols};
  Id space(H5Screate_simple(rank, dims, nullptr), H5Sclose);
  Id dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  H5Pset_fill_value(dcpl.get(), type, fill);
  // Storage and fill values at creation (parallel HDF5's only choice, kept alike serially): a
  // row no process writes is stored, and reads as `fill`.
  H5Pset_alloc_time(dcpl.get(), H5D_ALLOC_TIME_EARLY);
  H5Pset_fill_time(dcpl.get(), H5D_FILL_TIME_ALLOC);
  Id d = create_dataset(dset, type, space.get(), dcpl.get());
  if (total * width == 0) return;  // the same on every process: none writes
  // Each value by its coordinates, in the order of `data` (a point selection keeps the
  // order it is given; a hyperslab's would be the file's).
  const hsize_t n = rows.size() * width;
  std::vector<hsize_t> at(n * static_cast<hsize_t>(rank));
  for (std::size_t k = 0; k < rows.size(); ++k) {
    if (rows[k] >= total)
      throw std::logic_error(
          fmt::format("{}: row {} of dataset '{}' past its {} rows", label_, rows[k], dset, total));
    for (hsize_t c = 0; c < width; ++c) {
      const hsize_t e = k * width + c;
      if (rank == 1) {
        at[e] = rows[k];
      } else {
        at[2 * e] = rows[k];
        at[2 * e + 1] = c;
      }
    }
  }
  const hsize_t mem_dims[1] = {std::max<hsize_t>(n, 1)};
  Id mem(H5Screate_simple(1, mem_dims, nullptr), H5Sclose);
  if (n == 0) {
    H5Sselect_none(space.get());
    H5Sselect_none(mem.get());
  } else if (H5Sselect_elements(space.get(), H5S_SELECT_SET, n, at.data()) < 0) {
    fail(fmt::format("cannot select the rows of dataset '{}': {}", dset, error_detail()));
  }
  // A process with no rows still takes part (collective); HDF5 wants a buffer all the same.
  const void* buf = n == 0 ? fill : data;
  const hid_t transfer = collective_ ? collective_->transfer : H5P_DEFAULT;
  if (H5Dwrite(d.get(), type, mem.get(), space.get(), transfer, buf) < 0)
    fail(fmt::format("cannot write dataset '{}': {}", dset, error_detail()));
}

void File::write_string(const std::string& dset, const std::string& text) {
  Id type = string_type(text.size() + 1);
  Id space(H5Screate(H5S_SCALAR), H5Sclose);
  Id d = create_dataset(dset, type.get(), space.get());
  write_whole(dset, d.get(), type.get(), space.get(), text.c_str());
}

void File::write_strings(const std::string& dset, const std::vector<std::string>& texts) {
  std::size_t width = 1;
  for (const auto& s : texts) width = std::max(width, s.size() + 1);
  std::vector<char> buf(texts.size() * width, '\0');
  for (std::size_t k = 0; k < texts.size(); ++k)
    std::copy(texts[k].begin(), texts[k].end(), buf.begin() + static_cast<long>(k * width));
  Id type = string_type(width);
  const hsize_t dims[1] = {texts.size()};
  Id space(H5Screate_simple(1, dims, nullptr), H5Sclose);
  Id d = create_dataset(dset, type.get(), space.get());
  if (!texts.empty()) write_whole(dset, d.get(), type.get(), space.get(), buf.data());
}

void File::write_attr_raw(const std::string& obj, const std::string& name, hid_t type,
                          const void* value) {
  Id o(H5Oopen(file_.get(), obj.c_str(), H5P_DEFAULT), H5Oclose);
  Id space(H5Screate(H5S_SCALAR), H5Sclose);
  Id a(o.valid() ? H5Acreate2(o.get(), name.c_str(), type, space.get(), H5P_DEFAULT, H5P_DEFAULT)
                 : -1,
       H5Aclose);
  if (!a.valid() || H5Awrite(a.get(), type, value) < 0)
    fail(fmt::format("cannot write attribute '{}' on '{}': {}", name, obj, error_detail()));
}

void File::write_attr_string(const std::string& obj, const std::string& name,
                             const std::string& s) {
  Id type = string_type(s.size() + 1);
  write_attr_raw(obj, name, type.get(), s.c_str());
}

bool File::exists(const std::string& path) const {
  // H5Lexists wants every intermediate group to exist, so walk the path one link at a time.
  std::string prefix;
  std::size_t start = 0;
  while (start < path.size()) {
    std::size_t end = path.find('/', start);
    if (end == std::string::npos) end = path.size();
    if (end > start) {
      prefix.push_back('/');
      prefix.append(path, start, end - start);
      if (H5Lexists(file_.get(), prefix.c_str(), H5P_DEFAULT) <= 0) {
        H5Eclear2(H5E_DEFAULT);
        return false;
      }
    }
    start = end + 1;
  }
  return true;
}

bool File::has_attr(const std::string& obj, const std::string& name) const {
  if (!exists(obj)) return false;
  Id o(H5Oopen(file_.get(), obj.c_str(), H5P_DEFAULT), H5Oclose);
  return o.valid() && H5Aexists(o.get(), name.c_str()) > 0;
}

Id File::open_dataset(const std::string& dset) const {
  if (!exists(dset)) fail(fmt::format("missing dataset '{}'", dset));
  Id d(H5Dopen2(file_.get(), dset.c_str(), H5P_DEFAULT), H5Dclose);
  if (!d.valid()) fail(fmt::format("'{}' is not a readable dataset: {}", dset, error_detail()));
  return d;
}

Id File::open_attr(const std::string& obj, const std::string& name) const {
  if (!has_attr(obj, name)) fail(fmt::format("missing attribute '{}' on '{}'", name, obj));
  Id o(H5Oopen(file_.get(), obj.c_str(), H5P_DEFAULT), H5Oclose);
  Id a(H5Aopen(o.get(), name.c_str(), H5P_DEFAULT), H5Aclose);
  if (!a.valid())
    fail(fmt::format("cannot open attribute '{}' on '{}': {}", name, obj, error_detail()));
  return a;
}

// A dataset's values are read into memory of their size, so that size must be in the file:
// a crafted dataspace of 2^40 rows over a chunked dataset with no chunk written (HDF5 would
// read fill values), over a few bytes of compact storage, or over storage said to lie past
// the end of the file is refused here, naming the dataset, instead of ending in bad_alloc.
// Values kept in other files (external or virtual storage) are refused: a snapshot is one
// file, and reading another file it names is not a snapshot reader's business.
void File::check_stored(hid_t d, hid_t ftype, const std::string& dset, hsize_t elements) const {
  Id dcpl(H5Dget_create_plist(d), H5Pclose);
  if (!dcpl.valid())
    fail(fmt::format("cannot read the storage of dataset '{}': {}", dset, error_detail()));
  if (H5Pget_layout(dcpl.get()) == H5D_VIRTUAL || H5Pget_external_count(dcpl.get()) > 0)
    fail(fmt::format("dataset '{}' keeps its values in other files; a snapshot holds its own",
                     dset));
  const hsize_t each = H5Tget_size(ftype);
  if (elements == 0 || each == 0) return;
  hsize_t file_bytes = 0;
  if (H5Fget_filesize(file_.get(), &file_bytes) < 0) file_bytes = 0;
  const hsize_t stored = H5Dget_storage_size(d);
  const bool filtered = H5Pget_nfilters(dcpl.get()) > 0;
  const hsize_t backing = std::min(stored, file_bytes);
  const hsize_t most = std::numeric_limits<hsize_t>::max();
  const hsize_t limit = !filtered                               ? backing
                        : backing > most / kMaxCompressionRatio ? most
                                                                : backing * kMaxCompressionRatio;
  if (elements > limit / each)
    fail(fmt::format(
        "dataset '{}' claims {} values of {} bytes, but the file stores {} bytes of them{} "
        "(the file is {} bytes): the file is damaged or crafted",
        dset, elements, each, stored,
        filtered ? fmt::format(" (compressed: at most {} times as much)", kMaxCompressionRatio)
                 : "",
        file_bytes));
}

namespace {

// rows x max(cols, 1) values, or the largest count when that overflows (refused as unstored).
hsize_t element_count(hsize_t rows, hsize_t cols) {
  const hsize_t c = std::max<hsize_t>(cols, 1);
  return rows > std::numeric_limits<hsize_t>::max() / c ? std::numeric_limits<hsize_t>::max()
                                                        : rows * c;
}

}  // namespace

Shape File::shape(const std::string& dset) const {
  Id d = open_dataset(dset);
  Id space(H5Dget_space(d.get()), H5Sclose);
  hsize_t dims[2] = {0, 0};
  const int rank = H5Sget_simple_extent_ndims(space.get());
  if (rank < 1 || rank > 2)
    fail(fmt::format("dataset '{}' has rank {}, expected 1 or 2", dset, rank));
  H5Sget_simple_extent_dims(space.get(), dims, nullptr);
  const Shape s{dims[0], rank == 2 ? dims[1] : 0};
  Id ftype(H5Dget_type(d.get()), H5Tclose);
  check_stored(d.get(), ftype.get(), dset, element_count(s.rows, s.cols));
  return s;
}

Shape File::check_shape(const std::string& dset, hid_t type, hsize_t cols,
                        std::optional<hsize_t> rows, const std::string& rows_why) const {
  Id d = open_dataset(dset);
  Id ftype(H5Dget_type(d.get()), H5Tclose);
  const H5T_class_t have = H5Tget_class(ftype.get()), want = H5Tget_class(type);
  if (have != want)
    fail(fmt::format("dataset '{}' holds {}, expected {}", dset, class_name(have),
                     class_name(want)));
  Id space(H5Dget_space(d.get()), H5Sclose);
  const int rank = H5Sget_simple_extent_ndims(space.get());
  hsize_t dims[2] = {0, 0};
  if (rank >= 0 && rank <= 2) H5Sget_simple_extent_dims(space.get(), dims, nullptr);
  const int want_rank = cols == 0 ? 1 : 2;
  if (rank != want_rank || (cols != 0 && dims[1] != cols)) {
    fail(fmt::format("dataset '{}' has shape {}, expected {}", dset,
                     rank > 2 ? fmt::format("of rank {}", rank) : shape_text(rank, dims),
                     cols == 0 ? std::string("[N]") : fmt::format("[N x {}]", cols)));
  }
  if (rows && dims[0] != *rows) {
    fail(fmt::format("dataset '{}' has {} rows, expected {}{}", dset, dims[0], *rows,
                     rows_why.empty() ? "" : " (" + rows_why + ")"));
  }
  check_stored(d.get(), ftype.get(), dset, element_count(dims[0], cols));
  return {dims[0], cols};
}

void File::read_raw(const std::string& dset, hid_t type, void* out, std::size_t count) const {
  if (count == 0) return;
  Id d = open_dataset(dset);
  if (H5Dread(d.get(), type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out) < 0)
    fail(fmt::format("cannot read dataset '{}': {}", dset, error_detail()));
}

void File::read_block_raw(const std::string& dset, hid_t type, hsize_t cols, hsize_t first,
                          hsize_t count, void* out) const {
  const Shape s = check_shape(dset, type, cols, {}, {});
  if (first > s.rows || count > s.rows - first)
    fail(fmt::format("dataset '{}' has {} rows; cannot read rows [{}, {})", dset, s.rows, first,
                     first + count));
  if (count == 0) return;
  Id d = open_dataset(dset);
  Id file_space(H5Dget_space(d.get()), H5Sclose);
  const int rank = cols == 0 ? 1 : 2;
  const hsize_t start[2] = {first, 0}, size[2] = {count, cols};
  Id mem_space(H5Screate_simple(rank, size, nullptr), H5Sclose);
  if (H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start, nullptr, size, nullptr) < 0 ||
      H5Dread(d.get(), type, mem_space.get(), file_space.get(), H5P_DEFAULT, out) < 0)
    fail(fmt::format("cannot read rows [{}, {}) of dataset '{}': {}", first, first + count, dset,
                     error_detail()));
}

void File::read_attr_raw(const std::string& obj, const std::string& name, hid_t type,
                         void* value) const {
  Id a = open_attr(obj, name);
  Id ftype(H5Aget_type(a.get()), H5Tclose);
  Id space(H5Aget_space(a.get()), H5Sclose);
  const H5T_class_t have = H5Tget_class(ftype.get()), want = H5Tget_class(type);
  if (have != want || H5Sget_simple_extent_npoints(space.get()) != 1) {
    fail(fmt::format("attribute '{}' on '{}' is not a single value of {}", name, obj,
                     class_name(want)));
  }
  if (H5Aread(a.get(), type, value) < 0)
    fail(fmt::format("cannot read attribute '{}' on '{}': {}", name, obj, error_detail()));
}

std::string File::read_attr_string(const std::string& obj, const std::string& name) const {
  Id a = open_attr(obj, name);
  Id ftype(H5Aget_type(a.get()), H5Tclose);
  Id space(H5Aget_space(a.get()), H5Sclose);
  const std::string what = fmt::format("attribute '{}' on '{}'", name, obj);
  if (H5Sget_simple_extent_npoints(space.get()) != 1) fail(what + " is not a single string");
  // The string is read into memory of its declared width, which must be in the file.
  if (H5Tget_size(ftype.get()) > H5Aget_storage_size(a.get()))
    fail(
        fmt::format("{} claims a string of {} bytes, but the file stores {}: the file is "
                    "damaged or crafted",
                    what, H5Tget_size(ftype.get()), H5Aget_storage_size(a.get())));
  return read_text(*this, what, ftype.get(), space.get(), 1,
                   [&](hid_t mem, void* buf) { return H5Aread(a.get(), mem, buf); })[0];
}

std::string File::read_string(const std::string& dset) const {
  Id d = open_dataset(dset);
  Id ftype(H5Dget_type(d.get()), H5Tclose);
  Id space(H5Dget_space(d.get()), H5Sclose);
  const std::string what = fmt::format("dataset '{}'", dset);
  if (H5Sget_simple_extent_npoints(space.get()) != 1) fail(what + " is not a single string");
  check_stored(d.get(), ftype.get(), dset, 1);
  return read_text(*this, what, ftype.get(), space.get(), 1, [&](hid_t mem, void* buf) {
    return H5Dread(d.get(), mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf);
  })[0];
}

std::vector<std::string> File::read_strings(const std::string& dset) const {
  Id d = open_dataset(dset);
  Id ftype(H5Dget_type(d.get()), H5Tclose);
  Id space(H5Dget_space(d.get()), H5Sclose);
  const std::string what = fmt::format("dataset '{}'", dset);
  if (H5Sget_simple_extent_ndims(space.get()) != 1) fail(what + " is not a 1-D list of strings");
  const auto n = static_cast<std::size_t>(H5Sget_simple_extent_npoints(space.get()));
  check_stored(d.get(), ftype.get(), dset, n);
  return read_text(*this, what, ftype.get(), space.get(), n, [&](hid_t mem, void* buf) {
    return H5Dread(d.get(), mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf);
  });
}

}  // namespace sable::h5
