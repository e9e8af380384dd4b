#include "sable/cd/colouring.hpp"

#include <algorithm>
#include <bit>

namespace sable::cd {

void SweepColouring::build(std::span<const std::uint32_t> body_i,
                           std::span<const std::uint32_t> body_j,
                           std::span<const std::uint8_t> serial, std::size_t bodies,
                           std::size_t block) {
  const std::size_t n = body_i.size();
  block = std::max<std::size_t>(block, 1);
  const std::size_t nb = (n + block - 1) / block;
  constexpr auto kTail = static_cast<std::uint8_t>(kMaxColours);
  mask_.assign(bodies, 0);
  colour_.assign(nb, kTail);
  auto mask_of = [&](std::uint32_t body) { return body == kNoBody ? 0 : mask_[body]; };
  auto mark = [&](std::uint32_t body, std::uint64_t bit) {
    if (body != kNoBody) mask_[body] |= bit;
  };
  // Greedy, in index order: the lowest colour that no block sharing a body already has.
  std::size_t colours = 0;
  for (std::size_t b = 0; b < nb; ++b) {
    const std::size_t a0 = b * block, a1 = std::min(n, a0 + block);
    std::uint64_t used = 0;
    bool any = false;
    for (std::size_t a = a0; a < a1; ++a) {
      if (serial[a]) continue;
      used |= mask_of(body_i[a]) | mask_of(body_j[a]);
      any = true;
    }
    if (!any || used == ~std::uint64_t{0}) continue;  // nothing to colour, or no colour left
    const int c = std::countr_zero(~used);
    colour_[b] = static_cast<std::uint8_t>(c);
    colours = std::max(colours, static_cast<std::size_t>(c) + 1);
    const std::uint64_t bit = std::uint64_t{1} << c;
    for (std::size_t a = a0; a < a1; ++a) {
      if (serial[a]) continue;
      mark(body_i[a], bit);
      mark(body_j[a], bit);
    }
  }
  // Blocks grouped by colour (a counting sort, stable: index order within a colour).
  count_.assign(colours + 1, 0);
  for (std::size_t b = 0; b < nb; ++b)
    if (colour_[b] != kTail) ++count_[colour_[b] + 1];
  for (std::size_t c = 0; c < colours; ++c) count_[c + 1] += count_[c];
  colour_begin_.assign(count_.begin(), count_.end());
  const std::size_t coloured = colour_begin_.back();
  // block_begin_ first holds, at each sorted position, the block's index; then its offset.
  block_begin_.assign(coloured + 1, 0);
  for (std::size_t b = 0; b < nb; ++b)
    if (colour_[b] != kTail) block_begin_[count_[colour_[b]]++] = b;
  order_.clear();
  order_.reserve(n);
  in_tail_.assign(n, 1);
  for (std::size_t k = 0; k < coloured; ++k) {
    const std::size_t b = block_begin_[k];
    block_begin_[k] = order_.size();
    for (std::size_t a = b * block, a1 = std::min(n, (b + 1) * block); a < a1; ++a) {
      if (serial[a]) continue;
      order_.push_back(a);
      in_tail_[a] = 0;
    }
  }
  block_begin_[coloured] = order_.size();
  for (std::size_t a = 0; a < n; ++a)
    if (in_tail_[a]) order_.push_back(a);
}

}  // namespace sable::cd
