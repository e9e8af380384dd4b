// Hostile scenario input: nesting that overflowed toml++'s stack, a file too large to read,
// grain counts no machine holds, a domain wider than a double. Each is refused with
// InputError naming the file, line and column and the limit (docs/reliability.md, "Bounds on
// input"), or, for the domain, handled.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "input_helpers.hpp"
#include "sable/core/error.hpp"
#include "sable/scenario/build.hpp"
#include "sable/scenario/config.hpp"
#include "sable/scenario/toml_scan.hpp"

namespace sable {
namespace {

namespace fs = std::filesystem;
using test::error_of;
using test::grains;
using test::has;
using test::kHead;
using test::kPath;
using test::kTail;
using test::kValid;
using test::repeat;

// "a.a.a...a" with `parts` parts.
std::string dotted(std::size_t parts) {
  return repeat("a.", parts - 1) + "a";
}

// ---------------------------------------------------------------- nesting (toml++ crashed)

// Guards: a dotted key and a table header of 40,000 parts overflowed the stack inside toml++
// (exit 139, no message; 30,000 parts gave an error). Both are refused before toml++ sees
// them, at the key's line and column, naming the limit.
TEST(InputBounds, DeepDottedKeyAndTableHeaderAreRefusedWhereTheyStart) {
  const std::string key = error_of("x = 1\n" + dotted(40000) + ".b = 1\n");
  EXPECT_TRUE(has(key, "bounds.toml:2:1: nested more than 64 levels deep"));
  EXPECT_TRUE(has(key, "dotted key"));
  const std::string header = error_of("\n\n  [" + dotted(40000) + "]\nb = 1\n");
  EXPECT_TRUE(has(header, "bounds.toml:3:4: nested more than 64 levels deep"));
  const std::string array_header = error_of("[[" + dotted(40000) + "]]\n");
  EXPECT_TRUE(has(array_header, "bounds.toml:1:3: nested more than 64 levels deep"));
}

// Guards: the limit counts every level on the way from the root (a header's parts, a dotted
// key's, arrays, inline tables, keys inside inline tables). 64 levels reach the parser, which
// reports the unknown key; 65 do not.
TEST(InputBounds, SixtyFourLevelsAreReadSixtyFiveAreNot) {
  EXPECT_TRUE(has(error_of(dotted(64) + " = 1\n"), "unknown key a;"));
  EXPECT_TRUE(has(error_of(dotted(65) + " = 1\n"), "nested more than 64 levels deep"));
  EXPECT_TRUE(has(error_of("[" + dotted(60) + "]\na.a.a.a = 1\n"), "unknown key a;"));
  EXPECT_TRUE(has(error_of("[" + dotted(60) + "]\na.a.a.a.a = 1\n"), "bounds.toml:2:1: nested"));
  // [[x]]: the array and its table are two levels.
  EXPECT_TRUE(has(error_of("[[" + dotted(62) + "]]\na.a = 1\n"), "bounds.toml:2:1: nested"));
  // 32 arrays hold the 33rd level's value; the key and 31 inline tables take the rest.
  EXPECT_TRUE(has(error_of("k = " + repeat("[", 63) + repeat("]", 63) + "\n"), "unknown key k"));
  EXPECT_TRUE(has(error_of("k = " + repeat("[", 64) + repeat("]", 64) + "\n"),
                  "bounds.toml:1:68: nested more than 64 levels deep (arrays and inline"));
  EXPECT_TRUE(has(error_of("k = " + repeat("{ a.a = ", 32) + "1" + repeat("}", 32) + "\n"),
                  "bounds.toml:1:"));
  EXPECT_TRUE(has(error_of("k = " + repeat("[{ a = ", 31) + "1" + repeat("}]", 31) + "\n"),
                  "unknown key k"));
  EXPECT_TRUE(has(error_of("k = " + repeat("[{ a = ", 32) + "1" + repeat("}]", 32) + "\n"),
                  "nested more than 64 levels deep"));
}

// Guards: arrays and inline tables 10^5 and 10^6 deep (toml++ stops at 256 by itself) are
// refused by the same limit, in time linear in the text.
TEST(InputBounds, DeepArraysAndInlineTablesAreRefused) {
  for (const std::size_t n : {std::size_t{100000}, std::size_t{1000000}}) {
    EXPECT_TRUE(has(error_of("a = " + repeat("[", n) + repeat("]", n) + "\n"),
                    "bounds.toml:1:68: nested more than 64 levels deep"));
    EXPECT_TRUE(has(error_of("a = " + repeat("{a=", n) + "1" + repeat("}", n) + "\n"),
                    "nested more than 64 levels deep"));
  }
}

// Guards: brackets, braces and dots inside strings and comments are not nesting: a material
// named with 1,000 of each, in each kind of string, beside a comment of them, parses.
TEST(InputBounds, BracketsInStringsAndCommentsAreNotNesting) {
  const std::string deep = repeat("[{a.", 1000);
  for (const std::string& quoted :
       {"\"" + deep + "\"", "'" + deep + "'", "\"\"\"" + deep + "\"\"\"", "'''" + deep + "'''"}) {
    std::string text = kValid;
    text.replace(text.find("\"g\""), 3, quoted + " # " + deep);
    text.replace(text.find("\"g\""), 3, quoted);  // the grains' material
    text.replace(text.find("\"g\""), 3, quoted);  // the wall's
    EXPECT_EQ(parse_scenario(text, kPath).materials[0].material.name, deep) << quoted;
  }
}

// Guards: the scan itself, on text that is not TOML: unterminated strings, stray closers and
// lone quotes end without reading past the text (ASan would see it).
TEST(InputBounds, TheScanEndsOnBrokenText) {
  for (const char* text : {"a = \"", "a = '''", "a = \"\"\"\\", "]]]}}}", "[[", "a.\"", "{a.b",
                           "a = [", "= = =", "a=\"\\", "a = {", "a = { b = [ {"}) {
    EXPECT_NO_THROW(detail::scan_toml_depth(text, kPath)) << text;
  }
}

// ---------------------------------------------------------------- file size

// Guards: a scenario of more than 64 MiB is refused by its size, before it is read (the file
// here is sparse: nothing of it is written or read).
TEST(InputBounds, ScenarioFileOver64MiBIsRefusedUnread) {
  const fs::path p = fs::temp_directory_path() / ("sable_bounds_" + std::to_string(::getpid()));
  std::ofstream(p).close();
  fs::resize_file(p, kMaxScenarioBytes + 1);
  try {
    load_scenario(p.string());
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_TRUE(has(e.what(), p.string() + ": cannot read scenario: the file is 67108865 bytes; "
                                           "at most 67108864 (64 MiB)"));
  }
  fs::remove(p);
  EXPECT_TRUE(has(error_of(std::string(kMaxScenarioBytes + 1, '#')), "at most 67108864"));
}

// ---------------------------------------------------------------- counts

// Guards: a count of 10^12 grains, or counts adding up past 10^8, is refused at its key instead
// of generating until memory runs out; so is a max_attempts past 10^6.
TEST(InputBounds, GrainCountsAreBounded) {
  EXPECT_TRUE(has(error_of(kHead + grains("1000000000000") + kTail),
                  "bounds.toml:17:9: grains[0].count = 1000000000000: expected an integer in "
                  "[1, 100000000]"));
  EXPECT_NO_THROW(parse_scenario(kHead + grains("100000000") + kTail, kPath));
  EXPECT_TRUE(has(error_of(kHead + grains("60000000") + grains("60000000") + kTail),
                  "bounds.toml:18:1: grains[1]: the [[grains]] blocks so far ask for 120000000 "
                  "grains; a scenario may ask for at most 100000000"));
  EXPECT_TRUE(has(error_of(kHead + grains("4", "max_attempts = 1000001\n", "random") + kTail),
                  "bounds.toml:18:16: grains[0].max_attempts = 1000001: expected an integer in "
                  "[1, 1000000]"));
  EXPECT_NO_THROW(
      parse_scenario(kHead + grains("4", "max_attempts = 1000000\n", "random") + kTail, kPath));
}

// Guards: a lattice whose sites all fall outside the region (a jitter of 10^6 m on a 1 m box
// of 2.5 billion sites) gives up after 2^24 + 64 x count sites instead of visiting them all.
TEST(InputBounds, LatticeGivesUpOnSitesOutsideTheRegion) {
  std::string block = grains("4", "jitter = 1e6\n");
  block.replace(block.find("radius = 1e-3"), 13, "radius = 1e-5");
  block.replace(block.find("hi = [0.01, 0.01]"), 17, "hi = [1, 1]");
  const ScenarioConfig cfg = parse_scenario(kHead + block + kTail, kPath);
  World<2> w;
  build_model(cfg, w);
  try {
    build_grains(cfg, w);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_TRUE(has(e.what(),
                    "bounds.toml:12:1: grains: 16777473 lattice sites lie outside the "
                    "region or on a wall for 0 grains placed of 4"));
  }
}

// Guards: a domain as wide as a double holds (its extent overflows to infinity) and grains a
// billionth of it cut no cell count that overflows an int or a product of counts (undefined
// casts, which UBSan reports; a wrapped product sized the cell array too small): the grains
// touch, and their contacts are found.
TEST(InputBounds, HugeDomainsCutFewCells) {
  for (const std::string lohi :
       {"lo = [-1e308, -1e308]\nhi = [1e308, 1e308]", "lo = [0, 0]\nhi = [1e7, 1e7]"}) {
    std::string text = kValid;
    text.replace(text.find("lo = [0, 0]\nhi = [0.01, 0.01]"), 29, lohi);
    const ScenarioConfig cfg = parse_scenario(text, kPath);
    World<2> w;
    build_model(cfg, w);
    build_grains(cfg, w);
    make_solver(cfg, w)->initialize();
    // Four grains of radius 1 mm at a 2 mm pitch touch in a row: three neighbour pairs.
    EXPECT_EQ(w.neighbors.pairs.size(), 3u) << lohi;
  }
}

}  // namespace
}  // namespace sable
