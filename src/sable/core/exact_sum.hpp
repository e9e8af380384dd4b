// An exact sum of doubles whose result does not depend on the order of the terms.
//
// Floating-point addition is not associative: a wall's total force summed over its contacts
// in list order changes its last bits when the contacts come in another order, as they do
// when the grains are split among MPI ranks (each rank sums its own, then the ranks' sums are
// added). ExactSum keeps the sum as an integer multiple of 2^-1074 (the smallest subnormal)
// in 32-bit limbs (a long accumulator, after Kulisch), so every term is added without
// rounding and only value() rounds, once: the result is the exact sum correctly rounded to
// the nearest double (ties to even), whatever the order of add() and merge() calls.
// (A result in the subnormal range, below 2^-1022, is rounded twice: to 53 bits, then to
// the subnormal's precision. Forces and energies never come near it.)
//
// Cost: add() is a handful of integer operations (no loop); the accumulator is 560 bytes, so
// it is kept for a few global totals (wall forces and torques, kinetic energy), never per
// grain. Infinities and NaNs are counted apart: value() returns NaN if a NaN or infinities of
// both signs were added, else the infinity, as a naive sum would.
#pragma once

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace sable {

class ExactSum {
 public:
  void add(double x) {
    const auto bits = std::bit_cast<std::uint64_t>(x);
    const auto biased = static_cast<int>((bits >> 52) & 0x7ff);
    std::uint64_t m = bits & ((std::uint64_t{1} << 52) - 1);
    if (biased == 0x7ff) {  // infinity or NaN
      if (m != 0) {
        nan_ = true;
      } else {
        (x > 0 ? pos_inf_ : neg_inf_) = true;
      }
      return;
    }
    if ((bits << 1) == 0) return;  // +0 or -0
    // x = m 2^(p - 1074): subnormals have p = 0 and no hidden bit.
    const auto normal = static_cast<std::uint64_t>(biased != 0);
    m |= normal << 52;
    const int p = biased - static_cast<int>(normal);
    // m 2^(p mod 32) has at most 85 bits: three 32-bit pieces from limb p / 32 up.
    const int k = p >> 5;
    const int shift = p & 31;
    const std::uint64_t low64 = m << shift;  // its bits 0-63 (the shift may drop bits above)
    const auto lo = static_cast<std::int64_t>(low64 & 0xffffffffU);
    const auto mid = static_cast<std::int64_t>(low64 >> 32);
    const auto hi = static_cast<std::int64_t>((m >> 1) >> (63 - shift));  // m >> (64 - shift)
    // Subtract for a negative x, without a branch (signs come at random: a mispredicted
    // branch would cost more than the rest): (v ^ neg) - neg is v or -v.
    const auto neg = -static_cast<std::int64_t>(bits >> 63);
    limb_[k] += (lo ^ neg) - neg;
    limb_[k + 1] += (mid ^ neg) - neg;
    limb_[k + 2] += (hi ^ neg) - neg;
    // Each add moves a limb by less than 2^32: 2^30 of them cannot overflow an int64.
    if (++pending_ == kMaxPending) carry();
  }

  // Adds another accumulator's sum (the reduction of partial sums).
  void merge(const ExactSum& o) {
    ExactSum b = o;
    b.carry();
    carry();
    for (int i = 0; i < kLimbs; ++i) limb_[i] += b.limb_[i];
    pending_ = 1;  // the limbs now hold up to twice a carried limb: carry before 2^30 more adds
    nan_ = nan_ || o.nan_;
    pos_inf_ = pos_inf_ || o.pos_inf_;
    neg_inf_ = neg_inf_ || o.neg_inf_;
  }

  // The exact sum rounded to the nearest double (ties to even); +0 if it is zero.
  double value() const;

  // Adds (-1)^negative (hi 2^64 + lo) 2^(position - 1074), position >= 0 (ExactRun's window).
  void add_integer(bool negative, std::uint64_t hi, std::uint64_t lo, int position) {
    // The 128-bit magnitude shifted by position mod 32 spans five 32-bit pieces.
    const int k = position >> 5, shift = position & 31;
    const std::uint64_t piece[5] = {
        (lo << shift) & 0xffffffffU,
        ((lo << shift) >> 32),
        ((hi << shift) | ((lo >> 1) >> (63 - shift))) & 0xffffffffU,
        ((hi << shift) | ((lo >> 1) >> (63 - shift))) >> 32,
        (hi >> 1) >> (63 - shift),
    };
    for (int i = 0; i < 5; ++i) {
      const auto v = static_cast<std::int64_t>(piece[i]);
      limb_[k + i] += negative ? -v : v;
    }
    if (++pending_ == kMaxPending) carry();
  }

  // The limbs after carrying (every limb but the top one in [0, 2^32)), for tests and for
  // sending an accumulator between processes; equal sums give equal limbs.
  static constexpr int kLimbs = 70;
  // The carried limbs, then whether a NaN, +inf and -inf were added (0 or 1): an array whose
  // element-wise sum over partial sums (an MPI_SUM) unpacks to their total.
  static constexpr int kPacked = kLimbs + 3;
  std::array<std::int64_t, kPacked> packed() const {
    std::array<std::int64_t, kPacked> out{};
    const auto l = carried_limbs();
    for (int i = 0; i < kLimbs; ++i) out[i] = l[i];
    out[kLimbs] = nan_;
    out[kLimbs + 1] = pos_inf_;
    out[kLimbs + 2] = neg_inf_;
    return out;
  }
  static ExactSum from_packed(const std::array<std::int64_t, kPacked>& in) {
    ExactSum s;
    for (int i = 0; i < kLimbs; ++i) s.limb_[i] = in[i];
    s.pending_ = 1 << 20;  // up to 2^20 carried sums added: carry long before an overflow
    s.nan_ = in[kLimbs] != 0;
    s.pos_inf_ = in[kLimbs + 1] != 0;
    s.neg_inf_ = in[kLimbs + 2] != 0;
    return s;
  }
  std::array<std::int64_t, kLimbs> carried_limbs() const {
    ExactSum c = *this;
    c.carry();
    return c.limb_;
  }

 private:
  static constexpr std::uint32_t kMaxPending = std::uint32_t{1} << 30;

  // Moves every limb's excess over 32 bits into the next one (arithmetic shifts: floor
  // division, so a negative sum ends with a negative top limb and the others in [0, 2^32)).
  void carry() {
    carry(limb_);
    pending_ = 0;
  }
  static void carry(std::array<std::int64_t, kLimbs>& l) {
    for (int i = 0; i + 1 < kLimbs; ++i) {
      const std::int64_t c = l[i] >> 32;
      l[i] -= c * (std::int64_t{1} << 32);
      l[i + 1] += c;
    }
  }

  // The largest double is below 2^(2045 + 53 - 1074 + 1), so terms reach limb 65; the
  // limbs above hold the carries of up to 2^64 such terms, with room for the sign.
  std::array<std::int64_t, kLimbs> limb_{};
  std::uint32_t pending_ = 0;
  bool nan_ = false, pos_inf_ = false, neg_inf_ = false;
};

// A fast front for an ExactSum over a run of terms of similar magnitude (a wall's contact
// forces in one step): the terms within 2^30 of the run's first one either way are added, still
// exactly, to a 128-bit fixed-point window kept in registers; the others, and the window every
// 2^13 terms and at the end, go to the ExactSum. 1-2 ns a term against 4-5 for
// ExactSum::add() (bench/micro/bench_exact_sum.cpp). Use it as a local in the loop that adds
// the terms; the sum is in the ExactSum once the ExactRun is destroyed (or flush()).
class ExactRun {
 public:
  explicit ExactRun(ExactSum& sink) : sink_(sink) {}
  ExactRun(const ExactRun&) = delete;
  ExactRun& operator=(const ExactRun&) = delete;
  ~ExactRun() { flush(); }

  void add(double x) {
    const auto bits = std::bit_cast<std::uint64_t>(x);
    const auto biased = static_cast<int>((bits >> 52) & 0x7ff);
    if (lsb_ < 0) {  // the first term sets the window's last bit, 2^30 below its own
      if (biased < 32 || biased == 0x7ff) {
        sink_.add(x);
        return;
      }
      lsb_ = biased - 30;
    }
    // The term is m 2^(biased - 1075) = (m << s) 2^(lsb - 1075): exact in the window when
    // 0 <= s <= 60 (and the term is a normal number); |m << s| < 2^113, so 2^13 of them fit.
    const auto s = static_cast<unsigned>(biased - lsb_);
    if (s > 60 || biased == 0 || biased == 0x7ff) {
      sink_.add(x);
      return;
    }
    const std::uint64_t m = (bits & ((std::uint64_t{1} << 52) - 1)) | (std::uint64_t{1} << 52);
    // m << s as two words (s < 64: no 128-bit shift), negated for a negative term without a
    // branch: (v ^ neg) - neg with neg = 0 or -1.
    const std::uint64_t neg = -(bits >> 63);
    const std::uint64_t lo = (m << s) ^ neg, hi = ((m >> 1) >> (63 - s)) ^ neg;
    acc_ += static_cast<I128>((static_cast<U128>(hi) << 64) | lo) -
            static_cast<I128>(static_cast<std::int64_t>(neg));
    if (++count_ == kFlushEvery) flush();
  }

  void flush() {
    if (count_ == 0) return;
    const bool negative = acc_ < 0;
    const auto mag = static_cast<U128>(negative ? -acc_ : acc_);
    sink_.add_integer(negative, static_cast<std::uint64_t>(mag >> 64),
                      static_cast<std::uint64_t>(mag), lsb_ - 1);
    acc_ = 0;
    count_ = 0;
  }

 private:
  __extension__ using I128 = __int128;
  __extension__ using U128 = unsigned __int128;
  static constexpr int kFlushEvery = 1 << 13;
  ExactSum& sink_;
  I128 acc_ = 0;
  int count_ = 0;
  int lsb_ = -1;  // the biased exponent of the window's last bit (-1: no term yet)
};

inline double ExactSum::value() const {
  if (nan_ || (pos_inf_ && neg_inf_)) return std::numeric_limits<double>::quiet_NaN();
  if (pos_inf_) return std::numeric_limits<double>::infinity();
  if (neg_inf_) return -std::numeric_limits<double>::infinity();
  std::array<std::int64_t, kLimbs> l = carried_limbs();
  const bool negative = l[kLimbs - 1] < 0;
  if (negative) {  // the magnitude: negate every limb and carry again
    for (auto& x : l) x = -x;
    carry(l);
  }
  int t = kLimbs - 1;
  while (t >= 0 && l[t] == 0) --t;
  if (t < 0) return 0.0;
  // The top three limbs as a 96-bit window (head: its top 64 bits once its leading bit is
  // bit 95; the rest, with the limbs below, a sticky bit). limb t < 2^32: the sums of
  // finite doubles end far below the top limb.
  auto limb = [&](int i) { return i >= 0 ? static_cast<std::uint64_t>(l[i]) : 0; };
  const std::uint64_t top = (limb(t) << 32) | limb(t - 1);
  const std::uint64_t below = limb(t - 2);
  const int lz = std::countl_zero(top);  // < 32: limb t is not zero
  std::uint64_t head = top;
  bool sticky = false;
  for (int i = 0; i < t - 2; ++i) sticky = sticky || l[i] != 0;
  if (lz > 0) {
    head = (top << lz) | (below >> (32 - lz));
    sticky = sticky || ((below << lz) & 0xffffffffU) != 0;
  } else {
    sticky = sticky || below != 0;
  }
  // head has its top bit set: the conversion rounds at bit 11, so a sticky bit in bit 0
  // breaks a false tie and changes nothing else.
  if (sticky) head |= 1;
  const int exponent = 32 * (t - 2) + 32 - lz - 1074;
  const double r = std::ldexp(static_cast<double>(head), exponent);
  return negative ? -r : r;
}

}  // namespace sable
