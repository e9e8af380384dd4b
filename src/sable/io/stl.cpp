#include "sable/io/stl.hpp"

#include <fmt/format.h>

#include <bit>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <limits>
#include <memory>
#include <string_view>
#include <system_error>
#include <vector>

#include "sable/core/error.hpp"
#include "sable/io/atomic_file.hpp"

namespace sable {

namespace {

using Vec3 = Space<3>::Vec;
using Triangle = SurfaceMesh<3>::Element;

constexpr std::size_t kHeader = 84;       // 80 bytes of header, then the uint32 count
constexpr std::size_t kPerTriangle = 50;  // 12 floats and a uint16

std::string os_reason(int err) {
  return err != 0 ? std::strerror(err) : "unknown error";
}

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};

std::string read_all(const std::string& path) {
  errno = 0;
  std::unique_ptr<std::FILE, FileCloser> f(std::fopen(path.c_str(), "rb"));
  if (!f)
    throw InputError(fmt::format("{}: cannot open STL file: {}", clip(path), os_reason(errno)));
  std::string data;
  char chunk[1 << 16];
  for (;;) {
    errno = 0;
    const std::size_t got = std::fread(chunk, 1, sizeof chunk, f.get());
    data.append(chunk, got);
    if (got < sizeof chunk) break;
  }
  if (std::ferror(f.get()) != 0)
    throw InputError(fmt::format("{}: cannot read STL file: {}", clip(path), os_reason(errno)));
  return data;
}

std::uint32_t le_u32(const char* p) {
  std::uint32_t v = 0;
  for (int k = 3; k >= 0; --k) v = v << 8 | static_cast<unsigned char>(p[k]);
  return v;
}

// The corners read so far, three per triangle, and the map x -> scale x + offset.
struct Soup {
  double scale;
  Vec3 offset;
  std::vector<Vec3> vertices;

  // Adds corner `corner` (0..2) of triangle `triangle` (counted from 0), read as `raw`;
  // `where` names the triangle (and the line) in messages.
  void add(const Vec3& raw, int corner, const std::string& where) {
    if (!raw.allFinite()) {
      throw InputError(
          fmt::format("{}, corner {}: coordinates ({}, {}, {}); expected finite "
                      "numbers",
                      where, corner + 1, raw.x(), raw.y(), raw.z()));
    }
    const Vec3 p = scale * raw + offset;
    if (!p.allFinite()) {
      throw InputError(fmt::format(
          "{}, corner {}: ({}, {}, {}) scaled by {} and moved by ({}, "
          "{}, {}) is beyond double range; expected a smaller scale",
          where, corner + 1, raw.x(), raw.y(), raw.z(), scale, offset.x(), offset.y(), offset.z()));
    }
    vertices.push_back(p);
  }
};

// The triangle count of a binary STL of `size` bytes, or an InputError saying how its size
// disagrees with its header.
std::size_t binary_count(const std::string& data, const std::string& path) {
  const std::size_t size = data.size();
  if (size < kHeader) {
    throw InputError(
        fmt::format("{}: truncated binary STL: {} bytes, shorter than the {}-byte "
                    "header and triangle count",
                    clip(path), size, kHeader));
  }
  const std::uint64_t count = le_u32(data.data() + 80);
  const std::uint64_t expected = kHeader + kPerTriangle * count;
  const std::uint64_t whole = (size - kHeader) / kPerTriangle;
  const std::uint64_t rest = (size - kHeader) % kPerTriangle;
  if (size < expected) {
    throw InputError(fmt::format(
        "{}: truncated binary STL: the header claims {} triangles "
        "({} bytes) but the file has {} bytes; triangle {} (counted "
        "from 1) is {}",
        clip(path), count, expected, size, whole + 1, rest == 0 ? "missing" : "cut short"));
  }
  if (size > expected) {
    throw InputError(
        fmt::format("{}: binary STL whose header says {} triangles ({} bytes), but "
                    "the file has {} bytes: {} triangles and {} bytes more; "
                    "expected a size of 84 + 50 * count (a wrong count, or trailing "
                    "bytes)",
                    clip(path), count, expected, size, whole, rest));
  }
  return count;
}

void read_binary(const std::string& data, const std::string& path, Soup& soup) {
  const std::size_t count = binary_count(data, path);
  soup.vertices.reserve(3 * count);
  for (std::size_t t = 0; t < count; ++t) {
    const char* p = data.data() + kHeader + kPerTriangle * t + 12;  // past the normal
    const std::string where = fmt::format("{}: triangle {} (counted from 1)", clip(path), t + 1);
    for (int k = 0; k < 3; ++k) {
      Vec3 raw;
      for (int i = 0; i < 3; ++i)
        raw[i] = static_cast<double>(std::bit_cast<float>(le_u32(p + 12 * k + 4 * i)));
      soup.add(raw, k, where);
    }
  }
}

bool same_word(std::string_view a, std::string_view keyword) {
  if (a.size() != keyword.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const auto c = static_cast<unsigned char>(a[i]);
    if ((c >= 'A' && c <= 'Z' ? c + ('a' - 'A') : c) != static_cast<unsigned char>(keyword[i]))
      return false;
  }
  return true;
}

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v';
}

// Whether `data` is text: no control characters but blanks and line ends (bytes above 127
// are allowed, for UTF-8 names). Binary STL data has zero bytes in almost every float.
bool is_text(const std::string& data) {
  for (char c : data) {
    const auto u = static_cast<unsigned char>(c);
    if ((u < 0x20 && !is_space(c) && c != '\n') || u == 0x7f) return false;
  }
  return true;
}

// Whether `data` begins with "solid" (after blanks).
bool begins_solid(const std::string& data) {
  std::size_t start = 0;
  while (start < data.size() && (is_space(data[start]) || data[start] == '\n')) ++start;
  return same_word(std::string_view(data).substr(start, 5), "solid");
}

// The ASCII reader: line by line, one token list per non-blank line.
class AsciiStl {
 public:
  AsciiStl(const std::string& data, const std::string& path, Soup& soup)
      : data_(data), path_(path), soup_(soup) {}

  void read() {
    if (!next()) fail_at_end("'solid NAME'");
    if (!is(0, "solid")) fail("'solid NAME' on the first line");
    for (;;) {
      if (!next()) fail_at_end("'endsolid NAME' (the file may be truncated)");
      if (is(0, "endsolid")) {
        if (!next()) return;
        if (!is(0, "solid")) fail("'solid NAME' or the end of the file after 'endsolid'");
        continue;
      }
      if (!is(0, "facet")) fail("'facet normal nx ny nz' or 'endsolid NAME'");
      read_facet();
    }
  }

 private:
  // Moves to the next non-blank line and splits it; false at the end of the file.
  bool next() {
    tokens_.clear();
    while (tokens_.empty()) {
      if (pos_ >= data_.size()) return false;
      std::size_t end = data_.find('\n', pos_);
      if (end == std::string_view::npos) end = data_.size();
      text_ = data_.substr(pos_, end - pos_);
      pos_ = end + 1;
      ++line_;
      std::size_t i = 0;
      while (i < text_.size()) {
        while (i < text_.size() && is_space(text_[i])) ++i;
        const std::size_t b = i;
        while (i < text_.size() && !is_space(text_[i])) ++i;
        if (i > b) tokens_.push_back(text_.substr(b, i - b));
      }
    }
    return true;
  }

  bool is(std::size_t k, std::string_view keyword) const {
    return k < tokens_.size() && same_word(tokens_[k], keyword);
  }

  // "PATH: line L" and, inside a facet, "(triangle N, counted from 1)".
  std::string where() const {
    std::string w = fmt::format("{}: line {}", clip(path_), line_);
    if (in_facet_) w += fmt::format(" (triangle {}, counted from 1)", triangles_);
    return w;
  }

  [[noreturn]] void fail(std::string_view expected, std::string_view found = {}) const {
    const std::string f = found.empty() ? fmt::format("'{}'", clip(text_, 60)) : std::string(found);
    throw InputError(fmt::format("{}: found {}; expected {}", where(), f, expected));
  }

  [[noreturn]] void fail_at_end(std::string_view expected) const {
    std::string w = fmt::format("{}: the file ends after line {}", clip(path_), line_);
    if (in_facet_) w += fmt::format(" inside triangle {} (counted from 1)", triangles_);
    throw InputError(fmt::format("{}; expected {}", w, expected));
  }

  double number(std::string_view token) const {
    std::string_view t = token;
    if (!t.empty() && t[0] == '+') t.remove_prefix(1);
    double v = 0.0;
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (ec == std::errc::result_out_of_range && end == t.data() + t.size())
      return std::numeric_limits<double>::infinity();  // refused as non-finite by Soup::add
    if (ec != std::errc{} || end != t.data() + t.size() || t.empty())
      fail("'vertex x y z' with x, y and z numbers",
           fmt::format("'{}', not a number, in '{}'", clip(token, 40), clip(text_, 60)));
    return v;
  }

  void read_facet() {
    ++triangles_;
    in_facet_ = true;
    if (!next()) fail_at_end("'outer loop'");
    if (tokens_.size() != 2 || !is(0, "outer") || !is(1, "loop")) fail("'outer loop'");
    int corners = 0;
    for (;;) {
      if (!next()) fail_at_end(corners < 3 ? "'vertex x y z'" : "'endloop'");
      if (is(0, "endloop") && tokens_.size() == 1) break;
      if (!is(0, "vertex")) fail(corners < 3 ? "'vertex x y z'" : "'endloop'");
      if (corners == 3)
        fail("'endloop' after three vertices (a facet has exactly 3 vertices)", "a fourth vertex");
      if (tokens_.size() != 4) fail("'vertex x y z'");
      const Vec3 raw(number(tokens_[1]), number(tokens_[2]), number(tokens_[3]));
      soup_.add(raw, corners, where());
      ++corners;
    }
    if (corners != 3) {
      fail("'vertex x y z' (a facet has exactly 3 vertices)",
           fmt::format("'endloop' after {} vertices", corners));
    }
    if (!next()) fail_at_end("'endfacet'");
    if (tokens_.size() != 1 || !is(0, "endfacet")) fail("'endfacet'");
    in_facet_ = false;
  }

  std::string_view data_;
  const std::string& path_;
  Soup& soup_;
  std::size_t pos_ = 0, line_ = 0, triangles_ = 0;
  bool in_facet_ = false;
  std::string_view text_;
  std::vector<std::string_view> tokens_;
};

Vec3 unit_normal(const SurfaceMesh<3>& mesh, const Triangle& t) {
  const Vec3& a = mesh.vertices[t[0]];
  const Vec3 n = (mesh.vertices[t[1]] - a).cross(mesh.vertices[t[2]] - a);
  const double len = n.norm();
  return len > 0.0 && std::isfinite(len) ? Vec3(n / len) : Vec3::Zero();
}

void put_u32(std::string& out, std::uint32_t v) {
  for (int k = 0; k < 4; ++k) out.push_back(static_cast<char>(v >> (8 * k) & 0xff));
}

void put_float(std::string& out, double x, const std::string& path, std::size_t t) {
  const auto f = static_cast<float>(x);
  if (std::isfinite(x) && !std::isfinite(f)) {
    throw IoError(
        fmt::format("cannot write '{}': triangle {} (counted from 1) has the "
                    "coordinate {}, beyond float range (binary STL stores floats; "
                    "write ASCII STL instead)",
                    path, t + 1, x));
  }
  put_u32(out, std::bit_cast<std::uint32_t>(f));
}

}  // namespace

SurfaceMesh<3> read_stl(const std::string& path, double scale, const Vec3& offset) {
  if (!(scale > 0.0) || !std::isfinite(scale))
    throw InputError(
        fmt::format("{}: STL scale {}; expected a finite number > 0", clip(path), scale));
  if (!offset.allFinite())
    throw InputError(fmt::format("{}: STL offset ({}, {}, {}); expected finite numbers", clip(path),
                                 offset.x(), offset.y(), offset.z()));
  const std::string data = read_all(path);
  Soup soup{scale, offset, {}};
  const bool binary =
      data.size() >= kHeader &&
      data.size() == kHeader + kPerTriangle * std::uint64_t{le_u32(data.data() + 80)};
  if (!binary && is_text(data) && begins_solid(data)) {
    AsciiStl(data, path, soup).read();
  } else if (!binary && !data.empty() && is_text(data)) {
    throw InputError(
        fmt::format("{}: not an STL file: text that does not begin with 'solid' "
                    "(expected of ASCII STL), of {} bytes (binary STL has 84 + 50 "
                    "* its triangle count)",
                    clip(path), data.size()));
  } else {
    read_binary(data, path, soup);
  }
  std::vector<Triangle> triangles(soup.vertices.size() / 3);
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const auto v = static_cast<std::uint32_t>(3 * t);
    triangles[t] = {v, v + 1, v + 2};
  }
  return build_surface<3>(std::move(soup.vertices), std::move(triangles), path);
}

void write_stl_ascii(const SurfaceMesh<3>& mesh, const std::string& path,
                     const std::string& solid_name) {
  std::string name = solid_name;
  for (char& c : name)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '_';
  write_pieces_atomic(path, [&](const PutText& put) {
    fmt::memory_buffer out;
    fmt::format_to(std::back_inserter(out), "solid {}\n", name);
    for (const Triangle& t : mesh.elements) {
      const Vec3 n = unit_normal(mesh, t);
      fmt::format_to(std::back_inserter(out),
                     "  facet normal {:.17g} {:.17g} {:.17g}\n    outer loop\n", n.x(), n.y(),
                     n.z());
      for (std::uint32_t v : t) {
        const Vec3& p = mesh.vertices[v];
        fmt::format_to(std::back_inserter(out), "      vertex {:.17g} {:.17g} {:.17g}\n", p.x(),
                       p.y(), p.z());
      }
      fmt::format_to(std::back_inserter(out), "    endloop\n  endfacet\n");
      if (out.size() > (1u << 16)) {
        put(out.data(), out.size());
        out.clear();
      }
    }
    fmt::format_to(std::back_inserter(out), "endsolid {}\n", name);
    put(out.data(), out.size());
  });
}

void write_stl_binary(const SurfaceMesh<3>& mesh, const std::string& path) {
  if (mesh.size() > std::numeric_limits<std::uint32_t>::max())
    throw IoError(
        fmt::format("cannot write '{}': {} triangles, more than binary STL's count "
                    "can hold",
                    path, mesh.size()));
  write_pieces_atomic(path, [&](const PutText& put) {
    std::string out(80, '\0');
    const std::string_view title = "binary STL written by Sable";
    out.replace(0, title.size(), title);
    put_u32(out, static_cast<std::uint32_t>(mesh.size()));
    for (std::size_t t = 0; t < mesh.size(); ++t) {
      const Triangle& tri = mesh.elements[t];
      const Vec3 n = unit_normal(mesh, tri);
      for (int i = 0; i < 3; ++i) put_float(out, n[i], path, t);
      for (std::uint32_t v : tri)
        for (int i = 0; i < 3; ++i) put_float(out, mesh.vertices[v][i], path, t);
      out.append(2, '\0');
      if (out.size() > (1u << 16)) {
        put(out.data(), out.size());
        out.clear();
      }
    }
    put(out.data(), out.size());
  });
}

}  // namespace sable
