#include "sable/scenario/toml_scan.hpp"

#include <fmt/format.h>

#include <vector>

#include "sable/core/error.hpp"

namespace sable::detail {

namespace {

bool is_bare(char c) {
  const auto u = static_cast<unsigned char>(c);
  // Bytes of multi-byte UTF-8 characters count as bare-key characters: counting a part too
  // many is harmless, one too few is not.
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' ||
         c == '-' || u >= 0x80;
}

class Scanner {
 public:
  Scanner(std::string_view text, const std::string& path) : s_(text), path_(path) {}

  // The document: table headers, then keys with their values.
  void run() {
    std::size_t table = 0;  // depth of the current table: its header's parts (+1 for [[...]])
    while (!at_end()) {
      const char c = s_[i_];
      if (c == '#') {
        skip_comment();
      } else if (c == '[') {
        const bool array = peek(1) == '[';
        i_ += array ? 2 : 1;
        const std::size_t base = array ? 1 : 0;
        table = base + scan_key(base);
      } else if (is_bare(c) || c == '"' || c == '\'') {
        const std::size_t depth = table + scan_key(table);
        skip_blanks();
        if (peek() == '=') {
          ++i_;
          scan_value(depth);
        }
      } else {
        ++i_;  // blanks, newlines, closing brackets of headers, and anything toml++ will refuse
      }
    }
  }

 private:
  // One array or inline table open in a value: the depth of the container itself, and the
  // depth of the value being read inside it.
  struct Frame {
    char kind;
    std::size_t open;
    std::size_t inner;
  };

  bool at_end() const { return i_ >= s_.size(); }
  char peek(std::size_t ahead = 0) const { return i_ + ahead < s_.size() ? s_[i_ + ahead] : '\0'; }
  void skip_blanks() {
    while (!at_end() && (s_[i_] == ' ' || s_[i_] == '\t')) ++i_;
  }
  void skip_comment() {
    while (!at_end() && s_[i_] != '\n') ++i_;
  }

  // A string of any of TOML's four kinds, from its opening quote to past its closing one (or
  // to the end of the line, or of the text, when it is not closed: toml++ reports that).
  void skip_string() {
    const char q = s_[i_];
    const bool basic = q == '"';
    if (peek(1) == q && peek(2) == q) {  // multi-line
      i_ += 3;
      while (!at_end()) {
        if (basic && s_[i_] == '\\') {
          i_ += 2;
        } else if (s_[i_] == q && peek(1) == q && peek(2) == q) {
          while (!at_end() && s_[i_] == q) ++i_;  // up to two quotes of content, then the delimiter
          return;
        } else {
          ++i_;
        }
      }
      return;
    }
    ++i_;
    while (!at_end() && s_[i_] != '\n') {
      const char c = s_[i_++];
      if (c == q) return;
      if (basic && c == '\\' && !at_end() && s_[i_] != '\n') ++i_;
    }
  }

  // A possibly dotted key (bare or quoted parts, blanks around the dots) at depth `base`:
  // returns its number of parts, failing as soon as base + parts passes the limit.
  std::size_t scan_key(std::size_t base) {
    const std::size_t start = i_;
    std::size_t parts = 0;
    while (true) {
      skip_blanks();
      if (at_end()) break;
      const char c = s_[i_];
      if (c == '"' || c == '\'') {
        skip_string();
      } else if (is_bare(c)) {
        while (!at_end() && is_bare(s_[i_])) ++i_;
      } else {
        break;
      }
      ++parts;
      if (base + parts > kMaxTomlDepth)
        fail(start, "the parts of this table header or dotted key reach deeper");
      skip_blanks();
      if (peek() != '.') break;
      ++i_;
    }
    return parts;
  }

  // Inside an inline table, after '{' or ',': blanks, then a key and its '='.
  void table_key(Frame& f) {
    while (!at_end() && (s_[i_] == ' ' || s_[i_] == '\t' || s_[i_] == '\r' || s_[i_] == '\n')) ++i_;
    if (peek() == '}') return;
    f.inner = f.open + scan_key(f.open);
    skip_blanks();
    if (peek() == '=') ++i_;
  }

  // A value at `depth`, to the end of its line once every array and inline table is closed.
  void scan_value(std::size_t depth) {
    std::vector<Frame> frames;
    auto inner = [&] { return frames.empty() ? depth : frames.back().inner; };
    while (!at_end()) {
      const char c = s_[i_];
      if (c == '\n' && frames.empty()) return;
      if (c == '#') {
        skip_comment();
      } else if (c == '"' || c == '\'') {
        skip_string();
      } else if (c == '[' || c == '{') {
        const std::size_t open = inner();
        frames.push_back({c, open, open + 1});
        if (open + 1 > kMaxTomlDepth) fail(i_, "arrays and inline tables reach deeper here");
        ++i_;
        if (c == '{') table_key(frames.back());
      } else if (c == ']' || c == '}') {
        ++i_;
        if (frames.empty()) return;
        frames.pop_back();
      } else if (c == ',') {
        ++i_;
        if (!frames.empty() && frames.back().kind == '{') table_key(frames.back());
      } else {
        ++i_;
      }
    }
  }

  [[noreturn]] void fail(std::size_t at, const char* what) const {
    int line = 1, column = 1;
    for (std::size_t k = 0; k < at && k < s_.size(); ++k) {
      if (s_[k] == '\n') {
        ++line;
        column = 1;
      } else if ((static_cast<unsigned char>(s_[k]) & 0xC0) != 0x80) {
        ++column;  // columns count characters, not the bytes of multi-byte ones
      }
    }
    throw InputError(fmt::format(
        "{}:{}:{}: nested more than {} levels deep ({}); TOML tables, dotted-key parts, arrays "
        "and inline tables count one level each, a scenario needs at most 6, and deeper input "
        "is refused before it is parsed",
        clip(path_), line, column, kMaxTomlDepth, what));
  }

  std::string_view s_;
  const std::string& path_;
  std::size_t i_ = 0;
};

}  // namespace

void scan_toml_depth(std::string_view text, const std::string& path) {
  Scanner(text, path).run();
}

}  // namespace sable::detail
