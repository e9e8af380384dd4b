#include "sable/analysis/report.hpp"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>

#include "sable/core/error.hpp"
#include "sable/io/atomic_file.hpp"

namespace sable {

namespace {

std::string quote(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (c == '\n') {
      out += "\\n";
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string number(double v) {
  return std::isfinite(v) ? fmt::format("{:.12g}", v) : "null";
}

}  // namespace

void Table::add(std::string name, std::vector<double> values) {
  if (!columns.empty() && values.size() != rows())
    throw SimulationError(
        fmt::format("table column '{}' has {} rows, the table {}", name, values.size(), rows()));
  names.push_back(std::move(name));
  columns.push_back(std::move(values));
}

std::string Table::csv() const {
  std::string out;
  for (std::size_t c = 0; c < names.size(); ++c) out += (c ? "," : "") + names[c];
  out += '\n';
  for (std::size_t r = 0; r < rows(); ++r) {
    for (std::size_t c = 0; c < columns.size(); ++c) {
      const double v = columns[c][r];
      out += c ? "," : "";
      out += std::isfinite(v) ? fmt::format("{:.12g}", v) : "nan";
    }
    out += '\n';
  }
  return out;
}

Summary& Summary::add(const std::string& key, double v) {
  items_.emplace_back(key, number(v));
  child_.push_back(-1);
  return *this;
}

Summary& Summary::add(const std::string& key, std::int64_t v) {
  items_.emplace_back(key, fmt::format("{}", v));
  child_.push_back(-1);
  return *this;
}

Summary& Summary::add(const std::string& key, bool v) {
  items_.emplace_back(key, v ? "true" : "false");
  child_.push_back(-1);
  return *this;
}

Summary& Summary::add(const std::string& key, const std::string& v) {
  items_.emplace_back(key, quote(v));
  child_.push_back(-1);
  return *this;
}

Summary& Summary::add(const std::string& key, const std::vector<double>& v) {
  std::string s = "[";
  for (std::size_t k = 0; k < v.size(); ++k) s += (k ? ", " : "") + number(v[k]);
  items_.emplace_back(key, s + "]");
  child_.push_back(-1);
  return *this;
}

Summary& Summary::add(const std::string& key, const Summary& v) {
  // Nested objects are rendered with the parent, at the parent's indentation.
  items_.emplace_back(key, "");
  child_.push_back(static_cast<int>(children_.size()));
  children_.push_back(v);
  return *this;
}

std::string Summary::json(int indent) const {
  const std::string pad(static_cast<std::size_t>(indent + 2), ' ');
  std::string out = "{\n";
  for (std::size_t k = 0; k < items_.size(); ++k) {
    const std::string value = child_[k] >= 0
                                  ? children_[static_cast<std::size_t>(child_[k])].json(indent + 2)
                                  : items_[k].second;
    out += pad + quote(items_[k].first) + ": " + value + (k + 1 < items_.size() ? ",\n" : "\n");
  }
  return out + std::string(static_cast<std::size_t>(indent), ' ') + "}";
}

namespace {
std::string canonical(const std::string& p) {
  std::error_code ec;
  const auto c = std::filesystem::weakly_canonical(p, ec);
  return ec ? p : c.string();
}
}  // namespace

ResultWriter::ResultWriter(std::string dir, const std::vector<std::string>& inputs)
    : dir_(std::move(dir)) {
  for (const auto& p : inputs) inputs_.push_back(canonical(p));
}

std::string ResultWriter::path(const std::string& name) const {
  return (std::filesystem::path(dir_) / name).string();
}

void ResultWriter::write(const std::string& name, const std::string& text) const {
  const std::string p = path(name);
  const std::string c = canonical(p);
  for (const auto& in : inputs_)
    if (in == c)
      throw InputError(
          fmt::format("{}: refusing to write an analysis result over an input snapshot", p));
  std::error_code ec;
  std::filesystem::create_directories(std::filesystem::path(p).parent_path(), ec);
  if (ec) throw IoError(fmt::format("{}: cannot create the directory: {}", p, ec.message()));
  write_text_atomic(p, text);
}

}  // namespace sable
