#include "sable/scenario/toml_reader.hpp"

#include <charconv>
#include <cmath>
#include <sstream>
#include <utility>

#include "sable/core/error.hpp"
#include "sable/scenario/toml_scan.hpp"

namespace sable::detail {

namespace {

// A value is shown in at most about 80 characters; a long string or key in it keeps its
// first 40 and its length (sable::clip).
constexpr std::size_t kShowLimit = 80;
// toml++'s syntax messages quote the input (a key it cannot redefine): bounded like our own,
// with room for toml++'s words around the quote.
constexpr std::size_t kSyntaxQuoteLimit = 2 * kQuoteLimit;

std::string quoted(std::string_view s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

void append_shown(std::string& out, const toml::node& node) {
  if (out.size() > kShowLimit) return;
  if (const auto* arr = node.as_array()) {
    out += '[';
    for (std::size_t i = 0; i < arr->size() && out.size() <= kShowLimit; ++i) {
      if (i > 0) out += ", ";
      append_shown(out, *arr->get(i));
    }
    out += ']';
  } else if (const auto* tbl = node.as_table()) {
    out += "{ ";
    bool first = true;
    for (auto&& [k, v] : *tbl) {
      if (!first) out += ", ";
      first = false;
      out += clip(k.str(), kShowLimit / 2) + " = ";
      append_shown(out, v);
      if (out.size() > kShowLimit) break;
    }
    out += " }";
  } else if (const auto* s = node.as_string()) {
    out += quoted(clip(s->get(), kShowLimit / 2));
  } else if (const auto* i = node.as_integer()) {
    out += std::to_string(i->get());
  } else if (const auto* f = node.as_floating_point()) {
    std::string text = format_number(f->get());
    if (text.find_first_of(".eEni") == std::string::npos) text += ".0";
    out += text;
  } else if (const auto* b = node.as_boolean()) {
    out += b->get() ? "true" : "false";
  } else {
    std::ostringstream os;
    node.visit([&os](auto&& v) { os << v; });
    out += os.str();
  }
}

}  // namespace

bool Range::contains(double x) const {
  const bool above = lo_open ? x > lo : x >= lo;
  const bool below = hi_open ? x < hi : x <= hi;
  return above && below;
}

std::string Range::describe() const {
  const bool has_lo = lo > -kInf;
  const bool has_hi = hi < kInf;
  if (has_lo && has_hi) {
    return "a number in " + std::string(lo_open ? "(" : "[") + format_number(lo) + ", " +
           format_number(hi) + (hi_open ? ")" : "]");
  }
  if (has_lo) return std::string("a number ") + (lo_open ? "> " : ">= ") + format_number(lo);
  if (has_hi) return std::string("a number ") + (hi_open ? "< " : "<= ") + format_number(hi);
  return "a number";
}

std::string format_number(double x) {
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof buf, x);
  return std::string(buf, res.ptr);
}

std::string show(const toml::node& node) {
  std::string out;
  append_shown(out, node);
  if (out.size() > kShowLimit) {
    std::size_t cut = kShowLimit;  // not inside a UTF-8 sequence
    while (cut > 0 && (static_cast<unsigned char>(out[cut]) & 0xC0) == 0x80) --cut;
    out = out.substr(0, cut) + "...";
  }
  return out;
}

std::string describe_type(const toml::node& node) {
  switch (node.type()) {
    case toml::node_type::string:
      return "a string";
    case toml::node_type::integer:
      return "an integer";
    case toml::node_type::floating_point:
      return "a floating-point number";
    case toml::node_type::boolean:
      return "a boolean";
    case toml::node_type::table:
      return "a table";
    case toml::node_type::array: {
      const std::size_t n = node.as_array()->size();
      return "an array of " + std::to_string(n) + (n == 1 ? " element" : " elements");
    }
    case toml::node_type::date:
      return "a date";
    case toml::node_type::time:
      return "a time";
    case toml::node_type::date_time:
      return "a date-time";
    default:
      return "nothing";
  }
}

std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& item : items) out += (out.empty() ? "" : ", ") + item;
  return out;
}

std::string join_names(const std::vector<std::string>& names, bool quote) {
  std::string out;
  for (std::size_t k = 0; k < names.size(); ++k) {
    if (out.size() > kQuoteLimit)
      return out + ", ... (" + std::to_string(names.size()) + " in all)";
    out += (k == 0 ? "" : ", ") + (quote ? quoted(clip(names[k])) : clip(names[k]));
  }
  return out;
}

bool contains(const std::vector<std::string>& items, const std::string& item) {
  for (const auto& i : items) {
    if (i == item) return true;
  }
  return false;
}

toml::table parse_document(const std::string& text, const std::string& path) {
  scan_toml_depth(text, path);  // toml++ has no bound on the parts of a dotted key
#if TOML_EXCEPTIONS
  try {
    return toml::parse(std::string_view(text), std::string_view(path));
  } catch (const toml::parse_error& e) {
    fail_at(e.source(), path, "TOML syntax error: " + clip(e.description(), kSyntaxQuoteLimit));
  }
#else
  toml::parse_result result = toml::parse(std::string_view(text), std::string_view(path));
  if (!result) {
    fail_at(result.error().source(), path,
            "TOML syntax error: " + clip(result.error().description(), kSyntaxQuoteLimit));
  }
  return std::move(result).table();
#endif
}

SourceLoc make_loc(const toml::source_region& region, const std::string& file) {
  return SourceLoc{file, static_cast<int>(region.begin.line),
                   static_cast<int>(region.begin.column)};
}

void fail_at(const toml::source_region& region, const std::string& file,
             const std::string& message) {
  SourceLoc loc = make_loc(region, file);
  if (loc.line <= 0) loc = SourceLoc{file, 1, 1};
  throw InputError(loc.str() + ": " + message);
}

void fail_value(const toml::node& node, const std::string& key, const std::string& file,
                const std::string& expected) {
  fail_at(node.source(), file, key + " = " + show(node) + ": expected " + expected);
}

void fail_type(const toml::node& node, const std::string& key, const std::string& file,
               const std::string& expected) {
  fail_value(node, key, file, expected + ", found " + describe_type(node));
}

double to_number(const toml::node& node, const std::string& key, const std::string& file,
                 const Range& range) {
  double x = 0.0;
  if (const auto* i = node.as_integer()) {
    x = static_cast<double>(i->get());
  } else if (const auto* f = node.as_floating_point()) {
    x = f->get();
  } else {
    fail_type(node, key, file, range.describe());
  }
  if (!std::isfinite(x)) fail_value(node, key, file, "a finite number");
  if (!range.contains(x)) fail_value(node, key, file, range.describe());
  return x;
}

std::uint64_t to_unsigned(const toml::node& node, const std::string& key, const std::string& file,
                          std::uint64_t min) {
  const std::string expected =
      min == 0 ? "a non-negative integer" : "an integer >= " + std::to_string(min);
  const auto* i = node.as_integer();
  if (i == nullptr) fail_type(node, key, file, expected);
  if (i->get() < 0 || static_cast<std::uint64_t>(i->get()) < min) {
    fail_value(node, key, file, expected);
  }
  return static_cast<std::uint64_t>(i->get());
}

std::string to_string(const toml::node& node, const std::string& key, const std::string& file) {
  const auto* s = node.as_string();
  if (s == nullptr) fail_type(node, key, file, "a string");
  return s->get();
}

Vec3a to_vector(const toml::node& node, const std::string& key, const std::string& file, int n) {
  const std::string expected = "an array of " + std::to_string(n) + " numbers";
  const auto* arr = node.as_array();
  if (arr == nullptr || arr->size() != static_cast<std::size_t>(n)) {
    fail_type(node, key, file, expected);
  }
  Vec3a v{0.0, 0.0, 0.0};
  for (std::size_t i = 0; i < arr->size(); ++i) {
    const toml::node& e = *arr->get(i);
    if (!e.is_number()) {
      fail_at(e.source(), file,
              key + " = " + show(node) + ": expected " + expected + ", found " + describe_type(e) +
                  " at index " + std::to_string(i));
    }
    v[i] = to_number(e, key + "[" + std::to_string(i) + "]", file);
  }
  return v;
}

// ---------------------------------------------------------------------------------------------

Table::Table(const toml::table& table, std::string name, std::string file, std::string folder)
    : table_(&table), name_(std::move(name)), file_(std::move(file)), folder_(std::move(folder)) {
  if (folder_.empty()) {  // the file's folder, as std::filesystem::path::parent_path() gives
    const std::size_t slash = file_.rfind('/');
    folder_ = slash == std::string::npos ? "" : file_.substr(0, slash == 0 ? 1 : slash);
  }
}

std::string Table::key_path(std::string_view key) const {
  return name_.empty() ? clip(key) : name_ + "." + clip(key);
}

const toml::node* Table::find(std::string_view key) const {
  return table_->get(key);
}

void Table::check_keys(std::initializer_list<std::string_view> allowed) const {
  for (auto&& [k, v] : *table_) {
    bool ok = false;
    for (std::string_view a : allowed) ok = ok || k.str() == a;
    if (ok) continue;
    std::vector<std::string> names(allowed.begin(), allowed.end());
    fail_at(k.source(), file_,
            "unknown key " + key_path(k.str()) + "; allowed keys" +
                (name_.empty() ? std::string() : " in " + name_) + ": " + join(names));
  }
}

void Table::reject(std::string_view key, const std::string& reason) const {
  if (const toml::node* node = find(key)) {
    fail_at(node->source(), file_, key_path(key) + " does not apply " + reason);
  }
}

void Table::fail_missing(std::string_view key, const std::string& expected) const {
  fail_at(table_->source(), file_,
          "missing required key " + key_path(key) + " (expected " + expected + ")");
}

void Table::fail(std::string_view key, const std::string& expected) const {
  const toml::node* node = find(key);
  if (node == nullptr) fail_missing(key, expected);
  fail_value(*node, key_path(key), file_, expected);
}

std::optional<double> Table::number(std::string_view key, const Range& range) const {
  const toml::node* node = find(key);
  if (node == nullptr) return std::nullopt;
  return to_number(*node, key_path(key), file_, range);
}

double Table::number_or(std::string_view key, const Range& range, double fallback) const {
  return number(key, range).value_or(fallback);
}

double Table::required_number(std::string_view key, const Range& range) const {
  const auto x = number(key, range);
  if (!x) fail_missing(key, range.describe());
  return *x;
}

std::optional<std::uint64_t> Table::unsigned_int(std::string_view key, std::uint64_t min) const {
  const toml::node* node = find(key);
  if (node == nullptr) return std::nullopt;
  return to_unsigned(*node, key_path(key), file_, min);
}

std::uint64_t Table::unsigned_or(std::string_view key, std::uint64_t fallback,
                                 std::uint64_t min) const {
  return unsigned_int(key, min).value_or(fallback);
}

std::optional<std::string> Table::string(std::string_view key) const {
  const toml::node* node = find(key);
  if (node == nullptr) return std::nullopt;
  return to_string(*node, key_path(key), file_);
}

std::string Table::required_string(std::string_view key) const {
  auto s = string(key);
  if (!s) fail_missing(key, "a string");
  if (s->empty()) fail(key, "a non-empty string");
  return *s;
}

std::string Table::choice(std::string_view key, std::span<const std::string_view> options,
                          const std::string& fallback) const {
  const auto s = string(key);
  if (!s) return fallback;
  std::vector<std::string> names;
  for (std::string_view o : options) {
    if (*s == o) return *s;
    names.push_back(quoted(o));
  }
  fail(key, "one of " + join(names));
}

bool Table::boolean_or(std::string_view key, bool fallback) const {
  const toml::node* node = find(key);
  if (node == nullptr) return fallback;
  const auto* b = node->as_boolean();
  if (b == nullptr) fail_type(*node, key_path(key), file_, "a boolean (true or false)");
  return b->get();
}

std::optional<Vec3a> Table::vector(std::string_view key, int n) const {
  const toml::node* node = find(key);
  if (node == nullptr) return std::nullopt;
  return to_vector(*node, key_path(key), file_, n);
}

Vec3a Table::required_vector(std::string_view key, int n) const {
  const auto v = vector(key, n);
  if (!v) fail_missing(key, "an array of " + std::to_string(n) + " numbers");
  return *v;
}

const toml::array* Table::array(std::string_view key) const {
  const toml::node* node = find(key);
  if (node == nullptr) return nullptr;
  if (!node->is_array()) fail_type(*node, key_path(key), file_, "an array");
  return node->as_array();
}

std::optional<Table> Table::table(std::string_view key) const {
  const toml::node* node = find(key);
  if (node == nullptr) return std::nullopt;
  if (!node->is_table()) fail_type(*node, key_path(key), file_, "a table");
  return Table(*node->as_table(), key_path(key), file_, folder_);
}

std::vector<Table> Table::table_array(std::string_view key) const {
  std::vector<Table> out;
  const toml::node* node = find(key);
  if (node == nullptr) return out;
  const std::string path = key_path(key);
  const std::string expected = "an array of tables ([[" + path + "]])";
  if (!node->is_array_of_tables()) fail_type(*node, path, file_, expected);
  const toml::array& arr = *node->as_array();
  for (std::size_t i = 0; i < arr.size(); ++i) {
    out.emplace_back(*arr.get(i)->as_table(), path + "[" + std::to_string(i) + "]", file_, folder_);
  }
  return out;
}

void check_ordered(const Table& t, std::string_view lo_key, std::string_view hi_key,
                   const Vec3a& lo, const Vec3a& hi, int n) {
  static constexpr const char* kAxes[] = {"x", "y", "z"};
  for (int a = 0; a < n; ++a) {
    if (hi[a] > lo[a]) continue;
    t.fail(hi_key, "every component greater than " + t.key_path(lo_key) + " (axis " + kAxes[a] +
                       ": hi = " + format_number(hi[a]) + " <= lo = " + format_number(lo[a]) + ")");
  }
}

}  // namespace sable::detail
