// Crafted Siconos .dat problems claiming more than they hold: every count the reader takes
// from the file is bounded by the values the file holds before anything that size is
// allocated, so a claim of 2^40 contacts or blocks in a few bytes is an InputError naming the
// file and the line or item, not std::bad_alloc.
#include <gtest/gtest.h>

#include <string>

#include "sable/cd/fc_problem.hpp"
#include "sable/core/error.hpp"

namespace {

std::string error_of(const std::string& text) {
  try {
    sable::cd::parse_fc_dat(text, "crafted.dat");
  } catch (const sable::InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError";
  return "";
}

::testing::AssertionResult has(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "\"" << text << "\" lacks \"" << part << "\"";
}

// Guards: 2^40 contacts are refused at their line (the reader reads at most 10^8); 10^8
// contacts in dense storage (a 9 x 10^16-value matrix) and 2^40 blocks in sparse storage,
// claimed by files of a few bytes, end where the file does, naming what was being read.
TEST(Fc3dBounds, ClaimsBeyondTheFileAreRefused) {
  EXPECT_TRUE(has(error_of("3\n1099511627776\n0\n3298534883328\n3298534883328\n"),
                  "crafted.dat, line 2: number of contacts 1099511627776 out of range"));
  EXPECT_TRUE(has(error_of("3\n100000000\n0\n300000000\n300000000\n300000000 300000000\n1 2\n"),
                  "crafted.dat: expected 90000000000000000 values of the dense matrix W, found "
                  "2 (file ends)"));
  EXPECT_TRUE(has(
      error_of("3\n1\n1\n3\n3\n1099511627776\n1\n1\n3\n3\n2\n1099511627776\n0 1099511627776\n0\n"),
      "crafted.dat: expected the column index of block 1, found the end of the file"));
}

}  // namespace
