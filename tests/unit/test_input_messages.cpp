// Messages about hostile input quote at most 120 characters of it (sable::clip): names and
// keys of 200,000 characters, long lists of known names, paths that name no file, command-line
// values. A 200,000-character wall name or key made a 200 KB message.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "input_helpers.hpp"
#include "run_helpers.hpp"
#include "sable/core/error.hpp"
#include "sable/scenario/config.hpp"

namespace sable {
namespace {

namespace fs = std::filesystem;
using test::error_of;
using test::grains;
using test::has;
using test::kHead;
using test::kValid;

void expect_short(const std::string& text, const std::string& place) {
  const std::string msg = error_of(text);
  EXPECT_LT(msg.size(), 1024u) << msg.substr(0, 300);
  EXPECT_TRUE(has(msg, place));
  EXPECT_TRUE(has(msg, "... (200000 characters)"));
}

// Guards: every message quotes at most 120 characters of an input (a 200,000-character wall
// name or key made a 200 KB message), with the whole length, and still names the place.
TEST(InputMessages, LongNamesAndKeysAreQuotedClipped) {
  const std::string name(200000, 'w'), key(200000, 'k');
  const std::string wall =
      "[[wall]]\nname = \"" + name + "\"\nmaterial = \"g\"\npoint = [0, 0]\nnormal = [0, 1]\n";
  // A duplicate wall name, an unknown key, an unknown material name.
  expect_short(kHead + grains() + wall + wall + "[[stage]]\nsteps = 1\n",
               "bounds.toml:24:8: wall[1].name = \"wwww");
  expect_short(key + " = 1\n" + kValid, "bounds.toml:1:1: unknown key kkkk");
  std::string text = kValid;
  text.replace(text.find("material = \"g\""), 14, "material = \"" + name + "\"");
  expect_short(text, "bounds.toml:14:12: grains[0].material = \"wwww");
  // A material of that name, and grains naming another: the known names are clipped too.
  text = kValid;
  text.replace(text.find("name = \"g\""), 10, "name = \"" + name + "\"");
  expect_short(text, "expected the name of a [[material]] (known: \"wwww");
  // toml++'s own message quotes the key it cannot redefine (toml++ cuts it at about 500).
  const std::string redefined = error_of(key + " = 1\n" + key + " = 2\n" + kValid);
  EXPECT_LT(redefined.size(), 1024u) << redefined.substr(0, 300);
  EXPECT_TRUE(has(redefined, "bounds.toml:2:200004: TOML syntax error: "));
  // A wall name in a stage's wall_velocity.
  expect_short(kValid + "wall_velocity = { " + key + " = [0, 0] }\n", "unknown wall stage[0]");
}

// Guards: a list of known names (here 2,000 walls) is cut after about 120 characters.
TEST(InputMessages, KnownNamesAreListedClipped) {
  std::string text = kHead + grains();
  for (int k = 0; k < 2000; ++k)
    text += "[[wall]]\nname = \"wall" + std::to_string(k) +
            "\"\nmaterial = \"g\"\npoint = [0, 0]\nnormal = [0, 1]\n";
  const std::string msg =
      error_of(text + "[[stage]]\nsteps = 1\nwall_velocity = { nowhere = [0, 0] }\n");
  EXPECT_LT(msg.size(), 512u) << msg.substr(0, 600);
  EXPECT_TRUE(has(msg, "(known: wall0, wall1, wall2"));
  EXPECT_TRUE(has(msg, ", ... (2000 in all))"));
}

// Guards: a scenario path that names no file, however long, is quoted clipped.
TEST(InputMessages, MissingScenarioPathIsClipped) {
  const std::string path = "/nowhere/" + std::string(200000 - 9, 'p');
  try {
    load_scenario(path);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_LT(msg.size(), 256u);
    EXPECT_TRUE(has(msg, "/nowhere/pppp"));
    EXPECT_TRUE(has(msg, "... (200000 characters): cannot read scenario: no such file"));
  }
}

// Guards: the command line quotes a refused value clipped (CLI11's message and Sable's own
// held the whole 100,000 characters), exit 2.
TEST(InputMessages, CommandLineValuesAreQuotedClipped) {
  if (!fs::exists(SABLE_CLI)) GTEST_SKIP() << SABLE_CLI << " not built";
  const std::string value(100000, 'v');  // one argument may hold at most 128 KiB
  const fs::path log =
      fs::temp_directory_path() / ("sable_bounds_cli_" + std::to_string(::getpid()) + ".log");
  for (const std::string& args : {"fc3d none.dat --local " + value, "fc3d " + value,
                                  "info " + value, "analyze " + value, "check " + value}) {
    std::string out;
    EXPECT_EQ(test::run_cli(args, log, out), 2) << args.substr(0, 40);
    EXPECT_LT(out.size(), 1024u) << out.substr(0, 300);
    EXPECT_TRUE(has(out, "vvvv")) << args.substr(0, 40);
    EXPECT_TRUE(has(out, "... (1000")) << args.substr(0, 40);  // 100,000 and CLI11's words
  }
  fs::remove(log);
}

// An output folder given on the command line is a path of any length (PATH_MAX is 4096): the
// refusal of a folder that is a file quotes 120 characters of it. Before the clip the whole
// 1,200-character path was echoed.
TEST(InputMessages, OutputFolderIsQuotedClipped) {
  if (!fs::exists(SABLE_CLI)) GTEST_SKIP() << SABLE_CLI << " not built";
  const fs::path base =
      fs::temp_directory_path() / ("sable_clip_out_" + std::to_string(::getpid()));
  fs::path deep = base;
  for (int k = 0; k < 6; ++k) deep /= std::string(200, static_cast<char>('a' + k));
  fs::create_directories(deep.parent_path());
  std::ofstream(deep) << "not a folder\n";  // --out names this file
  const fs::path scen = base / "s.toml";
  std::ofstream(scen) << kValid;
  std::string out;
  EXPECT_EQ(test::run_cli("run " + scen.string() + " --out " + deep.string(), base / "log", out),
            2);
  EXPECT_TRUE(has(out, "is a file, expected a folder")) << out.substr(0, 300);
  EXPECT_TRUE(has(out, "characters)")) << out.substr(0, 300);
  EXPECT_LT(out.size(), 600u) << out.substr(0, 300);
  fs::remove_all(base);
}

}  // namespace
}  // namespace sable
