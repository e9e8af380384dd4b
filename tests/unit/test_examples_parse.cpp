// Every scenario shipped in examples/ and bench/ parses and builds: a key renamed or a range
// tightened in the parser must not silently break the documented examples. A block of more
// than kMaxBuilt grains is built with kMaxBuilt: rotating-cylinder/full.toml's 292,500 took
// 5 s here and 2 min under ASan, where this test runs too; ExampleHashes (Release) builds and
// runs every example at its full size.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "sable/core/error.hpp"
#include "sable/scenario/config.hpp"
#include "sable/scenario/runner.hpp"

namespace fs = std::filesystem;

constexpr std::size_t kMaxBuilt = 20000;

TEST(Examples, EveryShippedScenarioParsesAndBuilds) {
  std::vector<fs::path> files;
  for (const char* dir : {"examples", "bench"})
    for (const auto& e : fs::recursive_directory_iterator(fs::path(SABLE_SOURCE_DIR) / dir))
      if (e.is_regular_file() && e.path().extension() == ".toml") files.push_back(e.path());
  ASSERT_GE(files.size(), 10u) << "the examples were not found";
  for (const auto& f : files) {
    SCOPED_TRACE(f.string());
    try {
      sable::ScenarioConfig cfg = sable::load_scenario(f.string());
      for (auto& g : cfg.grains) g.count = std::min(g.count, kMaxBuilt);
      EXPECT_FALSE(sable::describe_scenario(cfg).empty());
    } catch (const sable::InputError& e) {
      ADD_FAILURE() << e.what();
    }
  }
}
