#include "sable/io/obj.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <string_view>
#include <system_error>

#include "sable/core/error.hpp"

namespace sable {

namespace {

// The next blank-separated token of `line` from `pos` (empty at the end).
std::string_view next_token(std::string_view line, std::size_t& pos) {
  while (pos < line.size() && (line[pos] == ' ' || line[pos] == '\t' || line[pos] == '\r')) ++pos;
  const std::size_t start = pos;
  while (pos < line.size() && line[pos] != ' ' && line[pos] != '\t' && line[pos] != '\r') ++pos;
  return line.substr(start, pos - start);
}

// A whole token as a finite number (from_chars: no locale), or false.
bool finite_number(std::string_view t, double& value) {
  if (!t.empty() && t[0] == '+') t.remove_prefix(1);
  const auto result = std::from_chars(t.data(), t.data() + t.size(), value);
  return !t.empty() && result.ec == std::errc{} && result.ptr == t.data() + t.size() &&
         std::isfinite(value);
}

}  // namespace

std::vector<Eigen::Vector3d> read_obj_vertices(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot open the OBJ file", clip(path)));
  std::vector<Eigen::Vector3d> vertices;
  std::string line;
  for (std::size_t lineno = 1; std::getline(in, line); ++lineno) {
    const std::string_view text(line.data(), std::min(line.find('#'), line.size()));
    std::size_t pos = 0;
    if (next_token(text, pos) != "v") continue;
    Eigen::Vector3d v;
    for (int k = 0; k < 3; ++k)
      if (!finite_number(next_token(text, pos), v[k]))
        throw InputError(
            fmt::format("{}:{}: expected a vertex `v x y z` of three finite numbers, found '{}'",
                        clip(path), lineno, clip(line, 60)));
    for (std::string_view t = next_token(text, pos); !t.empty(); t = next_token(text, pos))
      if (double extra = 0.0; !finite_number(t, extra))
        throw InputError(fmt::format(
            "{}:{}: expected numbers after `v x y z` (a weight or colours), found '{}' in '{}'",
            clip(path), lineno, clip(t, 40), clip(line, 60)));
    vertices.push_back(v);
  }
  if (in.bad()) throw InputError(fmt::format("{}: cannot read the OBJ file", clip(path)));
  if (vertices.empty())
    throw InputError(fmt::format("{}: no vertex (`v x y z` line) in the OBJ file", clip(path)));
  return vertices;
}

}  // namespace sable
