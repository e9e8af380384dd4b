// Tests that need data from outside the repository (../shared: the Siconos reference problems,
// the LIGGGHTS benchmark's bed generator) or a tool the setup script installs (python3 with
// numpy). On a developer's machine without them such a test skips; under CI (the environment
// variable CI set to "true", as CI services set it) it fails, so that a missing checkout of
// shared/ cannot leave a green run that tested nothing.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <string_view>

namespace sable::test {

inline bool in_ci() {
  const char* ci = std::getenv("CI");
  return ci != nullptr && std::string_view(ci) == "true";
}

}  // namespace sable::test

// Skip the test (outside CI) or fail it (CI=true) unless `available`; `why` is streamed.
// A macro because GTEST_SKIP and GTEST_FAIL return from the calling function.
#define SABLE_NEEDS(available, why)                                      \
  do {                                                                   \
    if (!(available)) {                                                  \
      if (::sable::test::in_ci()) GTEST_FAIL() << "CI=true and " << why; \
      GTEST_SKIP() << why;                                               \
    }                                                                    \
  } while (false)
