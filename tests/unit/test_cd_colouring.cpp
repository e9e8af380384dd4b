// The colouring of the parallel NLGS sweep (cd/colouring.hpp): the invariants that make a
// coloured sweep race-free and its bits independent of the threads (exact checks), and the
// grain problem swept in the coloured order on 1, 2 and 4 threads (state hashes equal).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "run_helpers.hpp"
#include "sable/cd/colouring.hpp"
#include "sable/core/rng.hpp"

namespace {

using sable::cd::SweepColouring;
constexpr std::uint32_t kNone = SweepColouring::kNoBody;

struct Graph {
  std::vector<std::uint32_t> i, j;
  std::vector<std::uint8_t> serial;
};

// n contacts among `bodies` bodies: a tenth with no second body (a wall), a twentieth serial.
Graph random_graph(std::size_t n, std::uint32_t bodies, std::uint64_t seed) {
  sable::Rng rng(seed);
  Graph g;
  for (std::size_t a = 0; a < n; ++a) {
    g.i.push_back(static_cast<std::uint32_t>(rng.below(bodies)));
    g.j.push_back(rng.below(10) == 0 ? kNone : static_cast<std::uint32_t>(rng.below(bodies)));
    g.serial.push_back(rng.below(20) == 0 ? 1 : 0);
  }
  return g;
}

// Every invariant the parallel sweep relies on, exactly.
void check(const SweepColouring& c, const Graph& g, std::size_t block) {
  const std::size_t n = g.i.size();
  std::vector<int> seen(n, 0);
  ASSERT_LE(c.colours(), static_cast<std::size_t>(SweepColouring::kMaxColours));
  for (std::size_t col = 0; col < c.colours(); ++col) {
    std::set<std::uint32_t> bodies_of_colour;
    for (std::size_t b = c.colour_begin(col); b < c.colour_begin(col + 1); ++b) {
      const auto blk = c.block(b);
      ASSERT_FALSE(blk.empty());
      std::set<std::uint32_t> bodies_of_block;
      for (std::size_t k = 0; k < blk.size(); ++k) {
        const std::size_t a = blk[k];
        ASSERT_LT(a, n);
        ++seen[a];
        EXPECT_EQ(g.serial[a], 0) << "a serial contact in a block";
        EXPECT_EQ(a / block, blk[0] / block) << "a block of contacts from two cuts";
        if (k > 0) {
          EXPECT_LT(blk[k - 1], a) << "a block out of index order";
        }
        for (const std::uint32_t body : {g.i[a], g.j[a]})
          if (body != kNone) bodies_of_block.insert(body);
      }
      for (const std::uint32_t body : bodies_of_block)
        EXPECT_TRUE(bodies_of_colour.insert(body).second)
            << "body " << body << " in two blocks of colour " << col;
    }
  }
  const auto tail = c.serial();
  for (std::size_t k = 0; k < tail.size(); ++k) {
    ++seen[tail[k]];
    if (k > 0) {
      EXPECT_LT(tail[k - 1], tail[k]) << "the tail out of index order";
    }
  }
  for (std::size_t a = 0; a < n; ++a) {
    EXPECT_EQ(seen[a], 1) << "contact " << a << " swept " << seen[a] << " times";
    if (g.serial[a]) {
      EXPECT_TRUE(std::find(tail.begin(), tail.end(), a) != tail.end()) << "serial " << a;
    }
  }
}

TEST(SweepColouring, BlocksOfAColourShareNoBodyAndEveryContactRunsOnce) {
  for (const std::size_t block : {1u, 3u, 16u, 256u}) {
    const Graph g = random_graph(5000, 1200, 7 + block);
    SweepColouring c;
    c.build(g.i, g.j, g.serial, 1200, block);
    check(c, g, block);
    // The build reuses its scratch: a second, smaller graph gives the same invariants.
    const Graph h = random_graph(700, 300, 99);
    c.build(h.i, h.j, h.serial, 300, block);
    check(c, h, block);
  }
}

// Contacts on one body: with one contact per block, each needs its own colour, so 64 of them
// are coloured and the rest run in the serial tail.
TEST(SweepColouring, ABodyInMoreThan64BlocksSendsTheRestToTheTail) {
  Graph g;
  for (std::uint32_t a = 0; a < 100; ++a) {
    g.i.push_back(0);
    g.j.push_back(a + 1);
    g.serial.push_back(0);
  }
  SweepColouring c;
  c.build(g.i, g.j, g.serial, 101, 1);
  check(c, g, 1);
  EXPECT_EQ(c.colours(), 64u);
  ASSERT_EQ(c.serial().size(), 36u);
  EXPECT_EQ(c.serial().front(), 64u);  // the first 64 in index order took the colours
}

// Contacts on walls and fixed grains (no body) never conflict: one colour holds them all.
TEST(SweepColouring, ContactsWithoutSharedBodiesTakeOneColour) {
  Graph g;
  for (std::uint32_t a = 0; a < 50; ++a) {
    g.i.push_back(a);
    g.j.push_back(kNone);
    g.serial.push_back(0);
  }
  SweepColouring c;
  c.build(g.i, g.j, g.serial, 50, 1);
  check(c, g, 1);
  EXPECT_EQ(c.colours(), 1u);
  EXPECT_TRUE(c.serial().empty());
}

// A bed of nearly touching spheres on a jittered lattice (1,200 grains) thrown at 0.3 m/s
// onto a layer of fixed grains (which contacts of one colour share), with friction, stepped
// by contact dynamics in the coloured order: some 4,000 contacts in the problem, above the
// size from which the sweep uses the threads; blocks of 8 contacts give many colours.
// `press`: the box's lid 0.2 mm above the bed and stress-controlled (a wall body, whose
// contacts run in the serial tail), pressing at 20 Pa.
std::string coloured_bed(const std::string& out, bool press = false) {
  std::ostringstream s;
  s << "[simulation]\ndimension = 3\nsolver = \"cd\"\nseed = 4\ndt = 2e-4\n"
    << "gravity = [0, 0, -9.81]\n[domain]\nlo = [0, 0, 0]\nhi = [0.012, 0.012, 0.03]\n"
    << "[[material]]\nname = \"g\"\ndensity = 2500.0\nfriction = 0.4\n"
    << "[cd]\nsweep = \"coloured\"\ncolour_block = 8\nlocal_solver = \"exact\"\n"
    << "tolerance = 1e-4\nmax_iterations = 60\n"
    << "[[grains]]\ngenerator = \"lattice\"\nmaterial = \"g\"\nradius = 0.495e-3\n"
    << "spacing = 1.0e-3\njitter = 0.002e-3\ncount = 100\nfixed = true\n"
    << "region = { box = { lo = [0, 0, 0], hi = [0.012, 0.012, 0.001] } }\n"
    << "[[grains]]\ngenerator = \"lattice\"\nmaterial = \"g\"\nradius = 0.495e-3\n"
    << "spacing = 1.0e-3\njitter = 0.002e-3\ncount = 1200\nvelocity = [0, 0, -0.3]\n"
    << "region = { box = { lo = [0, 0, 0.001], hi = [0.012, 0.012, 0.0125] } }\n"
    << "[[wall]]\nname = \"box\"\ntype = \"box\"\nmaterial = \"g\"\nlo = [0, 0, 0]\n"
    << "hi = [0.012, 0.012, " << (press ? "0.0102" : "0.03") << "]\n"
    << "[[stage]]\nname = \"settle\"\nsteps = 10\n"
    << (press ? "wall_stress = { \"box.zhi\" = 20.0 }\nservo_max_velocity = 0.5\n" : "")
    << "[output]\ndir = \"" << out << "\"\ncsv_interval = 10\nsnapshot_interval = 5\n"
    << "vtk_interval = 0\nlog_interval = 0\n";
  return s.str();
}

TEST(CdColoured, BitIdenticalForOneTwoAndFourThreadsAndOnRestart) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "sable_cd_coloured";
  fs::remove_all(dir);
  std::uint64_t hashes[3];
  int k = 0;
  for (const int threads : {1, 2, 4}) {
    const auto r =
        sable::test::run_text(coloured_bed((dir / "unused").string()), {"", false, threads});
    EXPECT_GE(r.grains, 1000u);
    hashes[k++] = r.state_hash;
  }
  EXPECT_EQ(hashes[0], hashes[1]);
  EXPECT_EQ(hashes[0], hashes[2]);
  // Restart: the colouring is rebuilt from the step's contacts, so nothing extra travels.
  sable::test::run_text(coloured_bed((dir / "full").string()), {"", true, 2});
  const fs::path snap = dir / "full" / "snapshots" / "step_0000000005.h5";
  ASSERT_TRUE(fs::exists(snap));
  const auto resumed =
      sable::test::run_text(coloured_bed((dir / "resumed").string()), {snap.string(), true, 2});
  EXPECT_EQ(resumed.state_hash, hashes[0]);
  // The contacts of the problem: enough for the threads to be used (nlgs_impl.hpp's
  // kMinParallelContacts, 2,048).
  const auto cols = sable::test::read_csv_columns(dir / "full" / "series.csv");
  ASSERT_TRUE(cols.count("nlgs_contacts"));
  EXPECT_GE(cols.at("nlgs_contacts").back(), 2048.0);
  fs::remove_all(dir);
}

// With a wall body: its contacts run after the colours, one by one; the same bits on 1 and 2
// threads, and the lid does press on the grains.
TEST(CdColoured, AWallBodysContactsRunLastWithTheSameBits) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "sable_cd_coloured_press";
  fs::remove_all(dir);
  const auto one = sable::test::run_text(coloured_bed((dir / "one").string(), true), {"", true, 1});
  const auto two = sable::test::run_text(coloured_bed((dir / "two").string(), true), {"", true, 2});
  EXPECT_EQ(one.state_hash, two.state_hash);
  const auto cols = sable::test::read_csv_columns(dir / "one" / "series.csv");
  ASSERT_TRUE(cols.count("wall_box.zhi_fz_N"));
  EXPECT_GT(cols.at("wall_box.zhi_fz_N").back(), 0.0);  // pushed up by the grains
  fs::remove_all(dir);
}

}  // namespace
