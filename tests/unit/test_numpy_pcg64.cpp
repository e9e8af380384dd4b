// NumpyPcg64 must reproduce numpy.random.default_rng(seed) bit for bit, so that Sable can draw
// the same lattice jitter as the LIGGGHTS benchmark script (shared/peers/liggghts/gen_lattice.py).
#include "sable/generation/numpy_pcg64.hpp"
#include "test_data.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <array>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <string>

namespace {

// Reference values from numpy 1.24.2 (/usr/bin/python3), S = [0, 1, 12345, 2**40+7]:
//  raw:     [int(x) for x in np.random.default_rng(s).bit_generator.random_raw(5)]
//  rnd:     [repr(float(x)) for x in np.random.default_rng(s).random(5)]
//  uni:     [repr(float(x)) for x in np.random.default_rng(s).uniform(-0.06e-3, 0.06e-3, 5)]
//  raw60k:  int(np.random.default_rng(s).bit_generator.random_raw(60000)[-1])
//  uni60k:  repr(float(np.random.default_rng(s).uniform(-0.06e-3, 0.06e-3, 60000)[-1]))
// repr() prints the shortest decimal that round-trips, so the literals below are exact.
struct Reference {
  std::uint64_t seed;
  std::array<std::uint64_t, 5> raw;
  std::array<double, 5> rnd;
  std::array<double, 5> uni;
  std::uint64_t raw60k;
  double uni60k;
};

const std::array<Reference, 4> kRefs = {{
    {0,
     {11749869230777074271ull, 4976686463289251617ull, 755828109848996024ull, 304881062738325533ull,
      15002187965291974971ull},
     {0.6369616873214543, 0.2697867137638703, 0.04097352393619469, 0.016527635528529094,
      0.8132702392002724},
     {1.6435402478574524e-05, -2.7625594348335563e-05, -5.508317712765664e-05,
      -5.801668373657651e-05, 3.759242870403269e-05},
     706010315376379975ull,
     -5.5407252493630516e-05},
    {1,
     {9441442522235856127ull, 17532960557476522086ull, 2659275481604167885ull,
      17499493567006797778ull, 5752274989370667689ull},
     {0.5118216247002567, 0.9504636963259353, 0.14415961271963373, 0.9486494471372439,
      0.31183145201048545},
     {1.4185949640308e-06, 5.405564355911224e-05, -4.270084647364395e-05, 5.383793365646926e-05,
      -2.258022575874175e-05},
     4101513217093244673ull,
     -3.331878275729698e-05},
    {12345,
     {4193609425186963869ull, 5843160025838961886ull, 14708796524633321433ull,
      12474696839993944336ull, 7214697784736971533ull},
     {0.22733602246716966, 0.31675833970975287, 0.7973654573327341, 0.6762546707509746,
      0.391109550601909},
     {-3.271967730393964e-05, -2.198899923482966e-05, 3.56838548799281e-05, 2.1150560490116944e-05,
      -1.3066853927770922e-05},
     15263652806493613928ull,
     3.929331319718905e-05},
    {(std::uint64_t{1} << 40) + 7,  // two 32-bit entropy words: exercises SeedSequence folding
     {15307346044642009514ull, 4709548916763817589ull, 2836937976252648324ull,
      12442412734173460875ull, 13629205658180759656ull},
     {0.829812891829413, 0.25530515834910417, 0.15379071585298754, 0.6745045458676086,
      0.7388407191925654},
     {3.9577547019529565e-05, -2.9363380998107504e-05, -4.15451140976415e-05,
      2.0940545504113024e-05, 2.8660886303107857e-05},
     7336520613379765288ull,
     -1.2274370474933844e-05},
}};

constexpr double kJit = 0.06e-3;  // gen_lattice.py's jitter amplitude

TEST(NumpyPcg64, RawOutputsMatchNumpy) {
  for (const Reference& r : kRefs) {
    sable::NumpyPcg64 g(r.seed);
    for (std::size_t i = 0; i < r.raw.size(); ++i)
      EXPECT_EQ(g.next_u64(), r.raw[i]) << "seed " << r.seed << " draw " << i;
  }
}

TEST(NumpyPcg64, RandomDoublesMatchNumpyExactly) {
  for (const Reference& r : kRefs) {
    sable::NumpyPcg64 g(r.seed);
    for (std::size_t i = 0; i < r.rnd.size(); ++i)
      EXPECT_EQ(g.random(), r.rnd[i]) << "seed " << r.seed << " draw " << i;
  }
}

TEST(NumpyPcg64, UniformMatchesNumpyExactly) {
  for (const Reference& r : kRefs) {
    sable::NumpyPcg64 g(r.seed);
    for (std::size_t i = 0; i < r.uni.size(); ++i)
      EXPECT_EQ(g.uniform(-kJit, kJit), r.uni[i]) << "seed " << r.seed << " draw " << i;
  }
}

// The 60000th draw checks that the state keeps advancing correctly over a long sequence
// (60000 = 3 coordinates x 20000 grains of the benchmark bed).
TEST(NumpyPcg64, SixtyThousandthValueMatchesNumpy) {
  for (const Reference& r : kRefs) {
    sable::NumpyPcg64 raw(r.seed);
    sable::NumpyPcg64 uni(r.seed);
    std::uint64_t lastRaw = 0;
    double lastUni = 0.0;
    for (int i = 0; i < 60000; ++i) {
      lastRaw = raw.next_u64();
      lastUni = uni.uniform(-kJit, kJit);
    }
    EXPECT_EQ(lastRaw, r.raw60k) << "seed " << r.seed;
    EXPECT_EQ(lastUni, r.uni60k) << "seed " << r.seed;
  }
}

// Full check against the live numpy: the whole jitter array of gen_lattice.py, row-major.
TEST(NumpyPcg64, GenLatticeJitterMatchesLiveNumpy) {
  const char* python = "/usr/bin/python3";
  SABLE_NEEDS(std::filesystem::exists(python) &&
                  std::system("/usr/bin/python3 -c 'import numpy' >/dev/null 2>&1") == 0,
              "/usr/bin/python3 with numpy not available; live comparison skipped");

  std::string path = (std::filesystem::temp_directory_path() / "sable_numpy_pcg64_XXXXXX").string();
  const int fd = mkstemp(path.data());
  ASSERT_GE(fd, 0) << "cannot create a temporary file";
  close(fd);

  // %.17g round-trips every double exactly through text.
  const std::string cmd = std::string(python) + " -c \"import numpy as np; np.savetxt('" + path +
                          "', np.random.default_rng(12345).uniform(-0.06e-3, 0.06e-3, "
                          "size=(20000,3)), fmt='%.17g')\"";
  const int rc = std::system(cmd.c_str());
  if (rc != 0) {
    std::filesystem::remove(path);
    FAIL() << "python command failed: " << cmd;
  }

  std::ifstream in(path);
  sable::NumpyPcg64 g(12345);
  int n = 0, mismatches = 0;
  double expected = 0.0;
  while (in >> expected) {
    const double got = g.uniform(-kJit, kJit);
    if (got != expected && mismatches++ < 5)
      ADD_FAILURE() << std::setprecision(17) << "value " << n << ": got " << got << ", numpy "
                    << expected;
    ++n;
  }
  in.close();
  std::filesystem::remove(path);
  EXPECT_EQ(n, 60000);
  EXPECT_EQ(mismatches, 0);
}

}  // namespace
