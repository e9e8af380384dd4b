// Typed, located access to a parsed TOML document, for the scenario parser.
//
// Every accessor checks the type and the range of what it reads and, when something is wrong,
// throws InputError with "FILE:LINE:COLUMN: dotted.key = value: expected ..., found ...". A
// Table remembers its own dotted name ("material[1]") so messages name the full key path.
// Internal to the scenario parser: toml++ is a private dependency of the library.
#pragma once

#include <toml++/toml.h>

#include <cstdint>
#include <initializer_list>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "sable/core/error.hpp"
#include "sable/scenario/config.hpp"

namespace sable::detail {

// A name or path read from the input, quoted in a message (clipped: see sable::clip).
inline std::string in_quotes(const std::string& s) {
  return "\"" + clip(s) + "\"";
}

inline constexpr double kInf = std::numeric_limits<double>::infinity();

// An interval a number must lie in; describe() gives the words used in messages.
struct Range {
  double lo = -kInf;
  double hi = kInf;
  bool lo_open = false;
  bool hi_open = false;
  bool contains(double x) const;
  std::string describe() const;  // "a number", "a number > 0", "a number in [0, 0.5)"
};

inline constexpr Range kAnyNumber{};
inline constexpr Range kPositive{0.0, kInf, true, false};
inline constexpr Range kNonNegative{0.0, kInf, false, false};

// Shortest round-trip text of a double ("0.6", "1e-05").
std::string format_number(double x);
// Compact TOML-like rendering of a value for messages, truncated when long.
std::string show(const toml::node& node);
// "a string", "an integer", "an array of 2 elements", ...
std::string describe_type(const toml::node& node);
// "a, b, c"
std::string join(const std::vector<std::string>& items);
// Names read from the input, for "known: ..." lists: each clipped (sable::clip) and, with
// `quote`, in double quotes; the list cut once past kQuoteLimit characters, with the number
// of names in all.
std::string join_names(const std::vector<std::string>& names, bool quote = false);
bool contains(const std::vector<std::string>& items, const std::string& item);
SourceLoc make_loc(const toml::source_region& region, const std::string& file);

// Parses a whole document; a syntax error becomes InputError("FILE:LINE:COLUMN: ...").
toml::table parse_document(const std::string& text, const std::string& path);
// Throws InputError("FILE:LINE:COLUMN: message").
[[noreturn]] void fail_at(const toml::source_region& region, const std::string& file,
                          const std::string& message);
// "FILE:L:C: key = value: expected WHAT"
[[noreturn]] void fail_value(const toml::node& node, const std::string& key,
                             const std::string& file, const std::string& expected);
// "FILE:L:C: key = value: expected WHAT, found TYPE"
[[noreturn]] void fail_type(const toml::node& node, const std::string& key, const std::string& file,
                            const std::string& expected);

// Conversions of one node, named `key` in messages.
double to_number(const toml::node& node, const std::string& key, const std::string& file,
                 const Range& range = kAnyNumber);
std::uint64_t to_unsigned(const toml::node& node, const std::string& key, const std::string& file,
                          std::uint64_t min = 0);
std::string to_string(const toml::node& node, const std::string& key, const std::string& file);
// An array of exactly n numbers, padded with zeros to 3 components.
Vec3a to_vector(const toml::node& node, const std::string& key, const std::string& file, int n);

// One TOML table with its dotted name (empty for the document root) and file. Every key the
// input names enters the name (and messages) clipped: see sable::clip.
class Table {
 public:
  // `folder`: where the files the table names by relative paths are (meshes, grain data);
  // "" for the folder of `file`.
  Table(const toml::table& table, std::string name, std::string file, std::string folder = "");

  const toml::table& raw() const { return *table_; }
  const std::string& name() const { return name_; }
  const std::string& file() const { return file_; }
  const std::string& folder() const { return folder_; }
  SourceLoc loc() const { return make_loc(table_->source(), file_); }
  std::string key_path(std::string_view key) const;  // "material[1].poisson"

  const toml::node* find(std::string_view key) const;
  bool has(std::string_view key) const { return find(key) != nullptr; }

  // Every key must be one of `allowed`; otherwise the first stranger is an error.
  void check_keys(std::initializer_list<std::string_view> allowed) const;
  // If `key` is present, it is an error: "KEY does not apply REASON".
  void reject(std::string_view key, const std::string& reason) const;
  [[noreturn]] void fail_missing(std::string_view key, const std::string& expected) const;
  [[noreturn]] void fail(std::string_view key, const std::string& expected) const;

  std::optional<double> number(std::string_view key, const Range& range = kAnyNumber) const;
  double number_or(std::string_view key, const Range& range, double fallback) const;
  double required_number(std::string_view key, const Range& range) const;
  std::optional<std::uint64_t> unsigned_int(std::string_view key, std::uint64_t min = 0) const;
  std::uint64_t unsigned_or(std::string_view key, std::uint64_t fallback,
                            std::uint64_t min = 0) const;
  std::optional<std::string> string(std::string_view key) const;
  std::string required_string(std::string_view key) const;
  // A string that must be one of `options`.
  std::string choice(std::string_view key, std::span<const std::string_view> options,
                     const std::string& fallback) const;
  std::string choice(std::string_view key, std::initializer_list<std::string_view> options,
                     const std::string& fallback) const {
    return choice(key, std::span<const std::string_view>(options.begin(), options.size()),
                  fallback);
  }
  bool boolean_or(std::string_view key, bool fallback) const;
  std::optional<Vec3a> vector(std::string_view key, int n) const;
  Vec3a required_vector(std::string_view key, int n) const;
  const toml::array* array(std::string_view key) const;
  std::optional<Table> table(std::string_view key) const;
  // An array of tables ([[key]] or key = [{...}]); entries are named "key[i]".
  std::vector<Table> table_array(std::string_view key) const;

 private:
  const toml::table* table_;
  std::string name_;
  std::string file_;
  std::string folder_;
};

// Error unless hi > lo on every one of the first n axes (reported at `hi_key`).
void check_ordered(const Table& t, std::string_view lo_key, std::string_view hi_key,
                   const Vec3a& lo, const Vec3a& hi, int n);

}  // namespace sable::detail
