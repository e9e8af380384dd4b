// A thin, exception-safe layer over the HDF5 C API, just what snapshots need.
//
// Every HDF5 identifier lives in an `h5::Id` that closes it on every path, error paths
// included. HDF5's automatic error printing is silenced; a failure becomes an InputError that
// names the file, the dataset or attribute, what was expected, and HDF5's own innermost
// message. Datasets are N x C arrays (or 1-D arrays of N) of native numbers, or strings.
#pragma once

#include <hdf5.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace sable::h5 {

// Owns one HDF5 identifier; closes it with the matching H5?close on destruction.
class Id {
 public:
  using Closer = herr_t (*)(hid_t);
  Id() = default;
  Id(hid_t id, Closer closer) : id_(id), closer_(closer) {}
  Id(const Id&) = delete;
  Id& operator=(const Id&) = delete;
  Id(Id&& o) noexcept : id_(o.id_), closer_(o.closer_) { o.id_ = -1; }
  Id& operator=(Id&& o) noexcept;
  ~Id() { reset(); }

  hid_t get() const { return id_; }
  bool valid() const { return id_ >= 0; }
  // Close now; returns HDF5's status (negative on failure).
  herr_t reset();

 private:
  hid_t id_ = -1;
  Closer closer_ = nullptr;
};

// Turn off HDF5's printing of error stacks to stderr (Sable reports errors itself).
void silence_errors();

// The innermost message on HDF5's error stack (empty when there is none).
std::string error_detail();

template <class T>
hid_t native_type();
template <>
inline hid_t native_type<double>() {
  return H5T_NATIVE_DOUBLE;
}
template <>
inline hid_t native_type<std::uint8_t>() {
  return H5T_NATIVE_UINT8;
}
template <>
inline hid_t native_type<std::uint16_t>() {
  return H5T_NATIVE_UINT16;
}
template <>
inline hid_t native_type<std::uint32_t>() {
  return H5T_NATIVE_UINT32;
}
template <>
inline hid_t native_type<std::uint64_t>() {
  return H5T_NATIVE_UINT64;
}
template <>
inline hid_t native_type<std::int32_t>() {
  return H5T_NATIVE_INT32;
}

// deflate's largest compression ratio: a filtered (compressed) dataset may hold at most this
// many times its stored bytes. Sable writes unfiltered datasets, whose values must all be
// stored (see File::check_stored).
inline constexpr hsize_t kMaxCompressionRatio = 1032;

// Shape of a numeric dataset: rows x cols, cols = 0 for a 1-D dataset.
struct Shape {
  hsize_t rows = 0;
  hsize_t cols = 0;
};

class File {
 public:
  // Several processes write one file together (parallel HDF5; src/sable/mpi makes the
  // property lists). Each of them makes every call, with the same dataset names, shapes and
  // attribute values; a whole dataset's values are written by the root alone, and
  // write_rows() writes each process's own rows.
  struct Collective {
    hid_t file_access;  // the MPI-IO driver on the processes' communicator
    hid_t transfer;     // collective transfers
    bool root;
  };

  // Create (truncate) `path` for writing. `label` names the file in messages (the final
  // name of an atomic write, not its temporary).
  static File create(const std::string& path, const std::string& label);
  static File create(const std::string& path, const std::string& label, const Collective& c);
  // Open an existing file read-only (or read-write) after checking it exists and is HDF5.
  static File open(const std::string& path, const std::string& label, bool writable = false);

  // Flush and close, throwing if HDF5 cannot finish writing the file.
  void close();
  hid_t id() const { return file_.get(); }
  const std::string& label() const { return label_; }
  // Throws with the label: an IoError for a file being written, an InputError for one read.
  [[noreturn]] void fail(const std::string& what) const;

  // --- writing (missing intermediate groups are created)
  template <class T>
  void write(const std::string& dset, const std::vector<T>& data, hsize_t cols = 0) {
    write_raw(dset, native_type<T>(), data.data(), cols == 0 ? data.size() : data.size() / cols,
              cols);
  }
  // `rows` rows of `cols` values each (0: a 1-D dataset) straight from `data`.
  template <class T>
  void write(const std::string& dset, const T* data, hsize_t rows, hsize_t cols) {
    write_raw(dset, native_type<T>(), data, rows, cols);
  }
  // A dataset of `total` rows of `cols` values each (0: 1-D) of which this process writes
  // row rows[k] from the k-th row of `data` (distinct rows); a row no process writes holds
  // `fill`.
  template <class T>
  void write_rows(const std::string& dset, const T* data, const std::vector<std::uint64_t>& rows,
                  hsize_t total, hsize_t cols, T fill = T{}) {
    write_rows_raw(dset, native_type<T>(), data, rows, total, cols, &fill);
  }
  void write_string(const std::string& dset, const std::string& text);
  void write_strings(const std::string& dset, const std::vector<std::string>& texts);
  template <class T>
  void write_attr(const std::string& obj, const std::string& name, T value) {
    write_attr_raw(obj, name, native_type<T>(), &value);
  }
  void write_attr_string(const std::string& obj, const std::string& name, const std::string& s);

  // --- reading
  bool exists(const std::string& path) const;
  bool has_attr(const std::string& obj, const std::string& name) const;
  Shape shape(const std::string& dset) const;
  // Read a dataset of `cols` columns (0: 1-D). With `rows`, the row count must equal it;
  // `rows_why` says why in the message ("one per grain, as /particles/x").
  template <class T>
  std::vector<T> read(const std::string& dset, hsize_t cols, std::optional<hsize_t> rows = {},
                      const std::string& rows_why = {}) const {
    const Shape s = check_shape(dset, native_type<T>(), cols, rows, rows_why);
    std::vector<T> out(s.rows * (cols == 0 ? 1 : cols));
    read_raw(dset, native_type<T>(), out.data(), out.size());
    return out;
  }
  // Rows [first, first + count) of a dataset of `cols` columns (0: 1-D) into `out`, which has
  // room for count * max(cols, 1) values: a block of a dataset too large to hold whole. Reading
  // past the dataset's last row is an error naming it.
  template <class T>
  void read_block(const std::string& dset, hsize_t cols, hsize_t first, hsize_t count,
                  T* out) const {
    read_block_raw(dset, native_type<T>(), cols, first, count, out);
  }
  std::string read_string(const std::string& dset) const;
  std::vector<std::string> read_strings(const std::string& dset) const;
  template <class T>
  T read_attr(const std::string& obj, const std::string& name) const {
    T value{};
    read_attr_raw(obj, name, native_type<T>(), &value);
    return value;
  }
  std::string read_attr_string(const std::string& obj, const std::string& name) const;

 private:
  File(Id file, std::string label, bool writing)
      : file_(std::move(file)), label_(std::move(label)), writing_(writing) {}
  void write_raw(const std::string& dset, hid_t type, const void* data, hsize_t rows, hsize_t cols);
  void write_rows_raw(const std::string& dset, hid_t type, const void* data,
                      const std::vector<std::uint64_t>& rows, hsize_t total, hsize_t cols,
                      const void* fill);
  // A new dataset (its groups made as needed) of `type` over `space`.
  Id create_dataset(const std::string& dset, hid_t type, hid_t space,
                    hid_t create_plist = H5P_DEFAULT);
  // Writes all of dataset `d` (over `space`) from `data`; when processes write together,
  // only the root's values go in.
  void write_whole(const std::string& dset, hid_t d, hid_t type, hid_t space, const void* data);
  void write_attr_raw(const std::string& obj, const std::string& name, hid_t type,
                      const void* value);
  Shape check_shape(const std::string& dset, hid_t type, hsize_t cols, std::optional<hsize_t> rows,
                    const std::string& rows_why) const;
  void read_raw(const std::string& dset, hid_t type, void* out, std::size_t count) const;
  void read_block_raw(const std::string& dset, hid_t type, hsize_t cols, hsize_t first,
                      hsize_t count, void* out) const;
  void read_attr_raw(const std::string& obj, const std::string& name, hid_t type,
                     void* value) const;
  Id open_dataset(const std::string& dset) const;
  // Refuses a dataset whose `elements` values of file type `ftype` are not all in the file,
  // before anything that size is allocated.
  void check_stored(hid_t d, hid_t ftype, const std::string& dset, hsize_t elements) const;
  Id open_attr(const std::string& obj, const std::string& name) const;

  Id file_;
  std::string label_;
  bool writing_;  // created by create(): a failure is an IoError, not bad input
  std::optional<Collective> collective_;
};

}  // namespace sable::h5
