// Scenario texts and checks shared by the tests of hostile scenario input (test_input_bounds,
// test_input_messages).
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "sable/core/error.hpp"
#include "sable/scenario/config.hpp"

namespace sable::test {

inline constexpr const char* kPath = "bounds.toml";

// A small valid 2D scenario in three parts: the head (11 lines), a [[grains]] block (lines
// 12-17, the count on line 17) and the tail (a wall and a stage).
inline const std::string kHead = R"([simulation]
dimension = 2
dt = 1e-5
[domain]
lo = [0, 0]
hi = [0.01, 0.01]
[[material]]
name = "g"
density = 2500.0
young = 5e6
poisson = 0.3
)";
inline const std::string kTail = R"([[wall]]
name = "floor"
material = "g"
point = [0, 0]
normal = [0, 1]
[[stage]]
steps = 1
)";

inline std::string grains(const std::string& count = "4", const std::string& more = "",
                          const std::string& generator = "lattice") {
  return "[[grains]]\ngenerator = \"" + generator +
         "\"\nmaterial = \"g\"\nradius = 1e-3\n"
         "region = { box = { lo = [0, 0], hi = [0.01, 0.01] } }\ncount = " +
         count + "\n" + more;
}

inline const std::string kValid = kHead + grains() + kTail;

// The message of the InputError parsing `text` raises ("" and a test failure if none).
inline std::string error_of(const std::string& text) {
  try {
    parse_scenario(text, kPath);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError";
  return "";
}

inline ::testing::AssertionResult has(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << "\"" << text.substr(0, 2000) << "\" lacks \"" << part << "\"";
}

inline std::string repeat(const std::string& s, std::size_t n) {
  std::string out;
  out.reserve(s.size() * n);
  for (std::size_t k = 0; k < n; ++k) out += s;
  return out;
}

}  // namespace sable::test
