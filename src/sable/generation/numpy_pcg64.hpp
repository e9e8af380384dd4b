// Bit-exact reproduction of numpy.random.default_rng(seed) for an integer seed (numpy 1.24).
//
// Why: benchmark scripts (e.g. LIGGGHTS' gen_lattice.py) build their initial bed with
// rng.uniform(-jit, jit, size=(N, 3)). Drawing the very same numbers here lets a Sable scenario
// start from exactly the same bed, so differences in results come from the solvers alone.
//
// Two published algorithms, written from their descriptions:
//  - SeedSequence (numpy.random.SeedSequence, after M. O'Neill's seed_seq_fe): the seed is
//    split into 32-bit words, hashed into a 4-word entropy pool, and the pool is hashed again
//    to produce the generator's state words.
//  - PCG64 = PCG XSL-RR 128/64 (O'Neill 2014): 128-bit LCG state, output is the xor of its two
//    halves rotated by the top 6 bits.
// Only the default path is covered: integer seed, no spawn key, next_u64 / random / uniform.
// numpy's 32-bit buffering (has_uint32) is not needed, since those calls only use 64-bit draws.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace sable {

class NumpyPcg64 {
 public:
  // GCC/Clang extension; __extension__ keeps -Wpedantic quiet.
  __extension__ typedef unsigned __int128 u128;

  explicit NumpyPcg64(std::uint64_t seed) {
    // PCG64 asks SeedSequence for 4 uint64 words: (initstate hi, lo, initseq hi, lo).
    const std::array<std::uint64_t, 4> w = seedSequenceState(seed);
    const u128 initstate = (u128{w[0]} << 64) | w[1];
    const u128 initseq = (u128{w[2]} << 64) | w[3];
    // pcg_setseq_128_srandom_r: the increment must be odd.
    state_ = 0;
    inc_ = (initseq << 1) | 1u;
    step();
    state_ += initstate;
    step();
  }

  // = rng.bit_generator.random_raw(): advance first, then output from the new state.
  std::uint64_t next_u64() {
    step();
    const auto hi = static_cast<std::uint64_t>(state_ >> 64);
    const auto lo = static_cast<std::uint64_t>(state_);
    const auto rot = static_cast<unsigned>(hi >> 58);
    const std::uint64_t x = hi ^ lo;
    return (x >> rot) | (x << ((64u - rot) & 63u));
  }

  // = rng.random(): top 53 bits scaled to [0, 1); exact in double.
  double random() { return static_cast<double>(next_u64() >> 11) * 0x1.0p-53; }

  // = rng.uniform(lo, hi): numpy computes lo + (hi - lo) * random() in this order.
  double uniform(double lo, double hi) { return lo + (hi - lo) * random(); }

 private:
  // 128-bit LCG multiplier of PCG's "setseq_128" variant.
  static constexpr u128 kMult = (u128{2549297995355413924ULL} << 64) | u128{4865540595714422341ULL};

  void step() { state_ = state_ * kMult + inc_; }

  // numpy SeedSequence(seed).generate_state(4, np.uint64) for a non-negative integer seed.
  static std::array<std::uint64_t, 4> seedSequenceState(std::uint64_t seed) {
    constexpr std::uint32_t kInitA = 0x43b0d7e5u, kMultA = 0x931e8875u;
    constexpr std::uint32_t kInitB = 0x8b51f9ddu, kMultB = 0x58f38dedu;
    constexpr std::uint32_t kMixMultL = 0xca01f9ddu, kMixMultR = 0x4973f715u;
    constexpr int kPool = 4;
    constexpr unsigned kXShift = 16;  // half of a 32-bit word

    // The integer is split into little-endian 32-bit words; 0 still yields one word.
    std::vector<std::uint32_t> entropy;
    do {
      entropy.push_back(static_cast<std::uint32_t>(seed));
      seed >>= 32;
    } while (seed != 0);

    // hashmix: the hash constant evolves across calls, so every word is hashed differently.
    std::uint32_t hashConst = kInitA;
    auto hashmix = [&hashConst](std::uint32_t v) {
      v ^= hashConst;
      hashConst *= kMultA;
      v *= hashConst;
      return v ^ (v >> kXShift);
    };
    auto mix = [](std::uint32_t x, std::uint32_t y) {
      const std::uint32_t r = kMixMultL * x - kMixMultR * y;
      return r ^ (r >> kXShift);
    };

    // Fill the pool (missing words hash as 0), then make every word depend on all others,
    // then fold in any words beyond the pool size.
    std::array<std::uint32_t, kPool> pool{};
    for (std::size_t i = 0; i < kPool; ++i) pool[i] = hashmix(i < entropy.size() ? entropy[i] : 0);
    for (std::size_t src = 0; src < kPool; ++src)
      for (std::size_t dst = 0; dst < kPool; ++dst)
        if (src != dst) pool[dst] = mix(pool[dst], hashmix(pool[src]));
    for (std::size_t src = kPool; src < entropy.size(); ++src)
      for (std::size_t dst = 0; dst < kPool; ++dst)
        pool[dst] = mix(pool[dst], hashmix(entropy[src]));

    // generate_state: cycle through the pool with a second hash; pairs of 32-bit words form
    // each uint64 little-endian (numpy views the uint32 array as uint64).
    std::uint32_t hashB = kInitB;
    std::array<std::uint64_t, 4> out{};
    for (std::size_t i = 0; i < 8; ++i) {
      std::uint32_t v = pool[i % kPool] ^ hashB;
      hashB *= kMultB;
      v *= hashB;
      v ^= v >> kXShift;
      out[i / 2] |= std::uint64_t{v} << (32 * (i % 2));
    }
    return out;
  }

  u128 state_ = 0;
  u128 inc_ = 0;
};

}  // namespace sable
