// The bytes of a fuzz input read as a sequence of choices (the structure-aware targets decode
// them into edits). Reading past the end gives zeros, so every input decodes to something and
// a shorter input is a prefix of the same choices.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

namespace sable::fuzz {

class Bytes {
 public:
  Bytes(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}

  bool empty() const { return pos_ >= size_; }
  std::size_t left() const { return empty() ? 0 : size_ - pos_; }

  std::uint8_t byte() { return empty() ? 0 : data_[pos_++]; }
  // An integer in [0, n), n >= 1, from as few bytes as n needs.
  std::uint64_t below(std::uint64_t n) {
    std::uint64_t v = 0;
    for (std::uint64_t range = 1; range < n && range != 0; range <<= 8) v = (v << 8) | byte();
    return n == 0 ? v : v % n;
  }
  std::uint64_t u64() {
    std::uint64_t v = 0;
    for (int k = 0; k < 8; ++k) v = (v << 8) | byte();
    return v;
  }
  // A double from 8 raw bytes (any bit pattern: NaN, infinities, subnormals).
  double raw_double() {
    const std::uint64_t bits = u64();
    double x = 0.0;
    std::memcpy(&x, &bits, sizeof x);
    return x;
  }
  // Up to `most` bytes as a string, its length given by the input.
  std::string text(std::size_t most) {
    const std::size_t n = static_cast<std::size_t>(below(most + 1));
    std::string s;
    for (std::size_t k = 0; k < n && !empty(); ++k) s.push_back(static_cast<char>(byte()));
    return s;
  }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

}  // namespace sable::fuzz
