#include "sable/io/csv.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include "sable/core/error.hpp"
#include "sable/io/atomic_file.hpp"

namespace sable {

namespace {

std::string join(const std::vector<std::string>& cols) {
  std::string s;
  for (std::size_t k = 0; k < cols.size(); ++k) s += (k > 0 ? "," : "") + cols[k];
  return s;
}

std::size_t count_fields(const std::string& line) {
  std::size_t n = 1;
  for (char c : line) n += c == ',' ? 1 : 0;
  return n;
}

// The step in the first column of a data row, or nullopt for a damaged (half-written) line.
std::optional<double> leading_step(const std::string& line) {
  const std::string first = line.substr(0, line.find(','));
  if (first.empty()) return std::nullopt;
  char* end = nullptr;
  const double v = std::strtod(first.c_str(), &end);
  if (end != first.c_str() + first.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::string os_reason() {
  return errno != 0 ? std::strerror(errno) : "unknown error";
}

}  // namespace

CsvLog::CsvLog(std::string path, std::vector<std::string> header,
               std::optional<std::uint64_t> resume_after_step)
    : path_(std::move(path)), header_(std::move(header)) {
  if (header_.empty()) throw std::invalid_argument("CsvLog '" + path_ + "': empty header");
  const bool resume = resume_after_step && std::filesystem::exists(path_);
  if (resume) keep_rows_up_to(*resume_after_step);
  errno = 0;
  file_.reset(std::fopen(path_.c_str(), resume ? "ab" : "wb"));
  if (!file_) {
    throw IoError(fmt::format("cannot open CSV log '{}': {}", path_, os_reason()));
  }
  if (!resume) {
    const std::string line = join(header_) + "\n";
    if (std::fputs(line.c_str(), file_.get()) < 0 || std::fflush(file_.get()) != 0)
      throw IoError(fmt::format("cannot write CSV log '{}': {}", path_, os_reason()));
  }
}

// Rewrite the file (atomically) with its header and the complete rows of steps <= `step`.
void CsvLog::keep_rows_up_to(std::uint64_t step) {
  std::ifstream in(path_);
  if (!in) throw InputError(fmt::format("cannot read CSV log '{}' to resume it", path_));
  std::string line, kept;
  std::getline(in, line);
  if (line != join(header_)) {
    throw InputError(
        fmt::format("CSV log '{}' has columns \"{}\", expected \"{}\"; move it away "
                    "or start a fresh run",
                    path_, line, join(header_)));
  }
  kept = line + "\n";
  const auto last = static_cast<double>(step);
  while (std::getline(in, line)) {
    // A line without its newline was cut off by the interruption: drop it like a later row.
    if (in.eof()) break;
    const auto s = leading_step(line);
    if (!s || count_fields(line) != header_.size()) continue;
    if (*s <= last) kept += line + "\n";
  }
  write_text_atomic(path_, kept);
}

void CsvLog::row(const std::vector<double>& values) {
  if (values.size() != header_.size()) {
    throw std::invalid_argument(fmt::format("CsvLog '{}': row of {} values for {} columns", path_,
                                            values.size(), header_.size()));
  }
  fmt::memory_buffer b;
  for (std::size_t k = 0; k < values.size(); ++k) {
    const double v = values[k];
    if (k > 0) b.push_back(',');
    // Integral values (steps, counts) exactly; {:.10g} would print step 12345678901 as 1.2e10.
    if (v == std::trunc(v) && std::abs(v) < 1e15)
      fmt::format_to(std::back_inserter(b), "{:.0f}", v);
    else
      fmt::format_to(std::back_inserter(b), "{:.10g}", v);
  }
  b.push_back('\n');
  errno = 0;
  if (std::fwrite(b.data(), 1, b.size(), file_.get()) != b.size() || std::fflush(file_.get()) != 0)
    throw IoError(fmt::format("cannot write CSV log '{}': {}", path_, os_reason()));
}

}  // namespace sable
