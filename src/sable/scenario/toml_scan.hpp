// A lexical pre-scan of a scenario's text, before toml++ sees it.
//
// toml++ builds and destroys nested tables recursively, and bounds the nesting of arrays and
// inline tables (256) but not the parts of a dotted key or a table header: `a.a.a....b = 1`
// with 40,000 parts overflows the stack (a crash, no message). The scan bounds the nesting
// depth of every value instead, counting each part of a table header or dotted key, each
// array and each inline table on the way from the document root. Sable's deepest key
// (`grains[i].region.box.lo[k]`) is 6 levels deep; kMaxTomlDepth leaves ten times that.
//
// The scan follows TOML's lexical rules (strings of the four kinds, comments, bare and quoted
// keys) closely enough never to count less than toml++ nests; on text that is not TOML it
// may count anything, and toml++ then reports the syntax error. It runs in linear time.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace sable::detail {

// Deepest nesting read (table header or dotted-key parts, arrays, inline tables).
inline constexpr std::size_t kMaxTomlDepth = 64;

// Throws InputError("FILE:LINE:COLUMN: ...") naming the limit at the first place where the
// nesting goes deeper than kMaxTomlDepth. `path` names the file in the message.
void scan_toml_depth(std::string_view text, const std::string& path);

}  // namespace sable::detail
