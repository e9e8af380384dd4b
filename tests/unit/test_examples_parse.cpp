// Every scenario shipped in examples/ and bench/ parses and builds: a key renamed or a range
// tightened in the parser must not silently break the documented examples.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "sable/core/error.hpp"
#include "sable/scenario/config.hpp"
#include "sable/scenario/runner.hpp"

namespace fs = std::filesystem;

TEST(Examples, EveryShippedScenarioParsesAndBuilds) {
  std::vector<fs::path> files;
  for (const char* dir : {"examples", "bench"})
    for (const auto& e : fs::recursive_directory_iterator(fs::path(SABLE_SOURCE_DIR) / dir))
      if (e.is_regular_file() && e.path().extension() == ".toml") files.push_back(e.path());
  ASSERT_GE(files.size(), 10u) << "the examples were not found";
  for (const auto& f : files) {
    SCOPED_TRACE(f.string());
    try {
      const sable::ScenarioConfig cfg = sable::load_scenario(f.string());
      EXPECT_FALSE(sable::describe_scenario(cfg).empty());
    } catch (const sable::InputError& e) {
      ADD_FAILURE() << e.what();
    }
  }
}
