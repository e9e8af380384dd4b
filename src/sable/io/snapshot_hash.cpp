#include "sable/io/snapshot_hash.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "sable/io/snapshot_pack.hpp"
#include "sable/world/state_hash.hpp"

namespace sable {

namespace {

// How one element of the in-memory type T lies in a row of its dataset (io/snapshot_write.cpp):
// `cols` values of type `File` (0: one value, a 1-D dataset), and how that row becomes T.
template <class T>
struct Row;

template <class T>
requires std::is_arithmetic_v<T>
struct Row<T> {
  using File = T;
  static constexpr hsize_t cols = 0;
  static T get(const File* in) { return in[0]; }
};

template <>
struct Row<ShapeKind> {
  using File = std::uint8_t;
  static constexpr hsize_t cols = 0;
  static ShapeKind get(const File* in) { return static_cast<ShapeKind>(in[0]); }
};

template <>
struct Row<ParticleId> {
  using File = std::uint32_t;
  static constexpr hsize_t cols = 2;  // index, generation
  static ParticleId get(const File* in) { return {in[0], in[1]}; }
};

// Vectors and orientations: rows of doubles, laid out as the writer lays them (Pack: a
// quaternion's w, x, y, z in the file, x, y, z, w in memory).
template <class T>
requires(!std::is_arithmetic_v<T> && requires { snapshot_detail::Pack<T>::cols; }) struct Row<T> {
  using File = double;
  static constexpr hsize_t cols = snapshot_detail::Pack<T>::cols;
  static T get(const File* in) { return snapshot_detail::Pack<T>::get(in); }
};

// The optional datasets load_snapshot stands in for when a file lacks them, each with the
// dataset whose row count it takes ("": none, no rows).
struct Absent {
  std::string_view name, rows_of;
};
constexpr std::array kAbsent{
    Absent{"/particles/order_key", "/particles/x"},
    Absent{"/neighbors/wall_pairs/element", "/neighbors/wall_pairs/i"},
    Absent{"/neighbors/wall_pairs/feature", "/neighbors/wall_pairs/i"},
    Absent{"/neighbors/pairs/bridge", "/neighbors/pairs/i"},
    Absent{"/neighbors/pairs/roll", "/neighbors/pairs/i"},
    Absent{"/neighbors/wall_pairs/roll", "/neighbors/wall_pairs/i"},
    Absent{"/liquid/film", ""},
};

// Row k of absent dataset `name`, as load_snapshot restores it: the slots' order for the
// order key, no bridge, and zero for elements, features and rolling springs.
template <class T>
T absent_row(std::string_view name, std::size_t k) {
  if constexpr (std::is_same_v<T, std::uint64_t>) {
    if (name == "/particles/order_key") return k;
  }
  if constexpr (std::is_same_v<T, double>) {
    if (name == "/neighbors/pairs/bridge") return PairList<3>::kNoBridge;
  }
  if constexpr (std::is_arithmetic_v<T>)
    return T{0};
  else
    return T::Zero();
}

// Hashes one array of `rows` elements as detail::hash_dense hashes it in memory (the count as
// a std::size_t, then the elements' bytes), at most `block` elements at a time, each block's
// elements put in place by `fill(first, count, out)`.
template <class T, class Fill>
void hash_blocks(Hasher& h, std::size_t rows, std::size_t block, Fill&& fill) {
  h.value(rows);
  std::vector<T> elems(std::min(block, rows));
  for (std::size_t first = 0; first < rows; first += block) {
    const std::size_t count = std::min(block, rows - first);
    fill(first, count, elems.data());
    h.bytes(elems.data(), count * sizeof(T));
  }
}

// Hashes load_snapshot's stand-in for dataset `name`, which `f` lacks (kAbsent); a dataset
// without one is an error naming it.
template <class T>
void hash_absent(Hasher& h, const h5::File& f, const std::string& name, std::size_t block) {
  const auto absent =
      std::find_if(kAbsent.begin(), kAbsent.end(), [&](const Absent& a) { return a.name == name; });
  // Only numbers and vectors have stand-ins (ids, shapes and orientations are never optional).
  if constexpr (std::is_arithmetic_v<T> || requires { T::Zero(); }) {
    if (absent != kAbsent.end()) {
      const std::size_t rows =
          absent->rows_of.empty() ? 0 : f.shape(std::string(absent->rows_of)).rows;
      hash_blocks<T>(h, rows, block, [&](std::size_t first, std::size_t count, T* out) {
        for (std::size_t k = 0; k < count; ++k) out[k] = absent_row<T>(name, first + k);
      });
      return;
    }
  }
  f.fail(fmt::format("missing dataset '{}'", name));
}

// Hashes the array stored as dataset `name` of `f` (or load_snapshot's stand-in, if the
// file lacks an optional one) as state_hash hashes it in memory.
template <class T>
void hash_dataset(Hasher& h, const h5::File& f, const std::string& name, std::size_t block) {
  if (!f.exists(name)) return hash_absent<T>(h, f, name, block);
  using File = typename Row<T>::File;
  const h5::Shape shape = f.shape(name);
  hsize_t cols = Row<T>::cols;
  // 2D angles, spins and rolling springs are written as [N x 1] rows, other doubles as [N].
  if constexpr (std::is_same_v<T, double>) cols = shape.cols == 1 ? 1 : 0;
  const hsize_t width = std::max<hsize_t>(cols, 1);
  std::vector<File> raw(std::min<hsize_t>(block, shape.rows) * width);
  hash_blocks<T>(h, shape.rows, block, [&](std::size_t first, std::size_t count, T* out) {
    f.read_block(name, cols, first, count, raw.data());
    for (std::size_t k = 0; k < count; ++k) out[k] = Row<T>::get(raw.data() + k * width);
  });
}

}  // namespace

template <int D>
std::uint64_t state_hash_of_file(const h5::File& f, const World<D>& like, std::size_t block_rows) {
  if (block_rows == 0)
    throw std::invalid_argument("state_hash_of_file: block_rows must be at least 1");
  return state_hash_with(like, [&](Hasher& h, const char* name, const auto& v) {
    using T = typename std::decay_t<decltype(v)>::value_type;
    hash_dataset<T>(h, f, name, block_rows);
  });
}

template std::uint64_t state_hash_of_file<2>(const h5::File&, const World<2>&, std::size_t);
template std::uint64_t state_hash_of_file<3>(const h5::File&, const World<3>&, std::size_t);

}  // namespace sable
