// A colouring of the contacts for a parallel NLGS sweep whose bits do not depend on the thread
// count (block Gauss-Seidel with coloured blocks).
//
// The contacts, in their index order, are cut into blocks of `block` consecutive contacts
// (consecutive contacts of the grain problem sit close in space: the neighbour list runs in
// cell order). Two blocks conflict when they update a common body (a grain with finite mass;
// walls and fixed grains take no update). Blocks are coloured greedily in index order, each
// taking the lowest colour none of its conflicting, already coloured blocks has. A sweep then
// runs colour after colour; the blocks of one colour touch disjoint bodies, so they run in
// parallel, each sweeping its contacts in index order: every contact sees exactly the values
// it would see on one thread, whatever thread runs it. Contacts marked `serial` (those on a
// wall body, whose velocity all its contacts update) and blocks that find no free colour among
// the kMaxColours run last, one by one in index order.
//
// With block = 1 this is the plain contact colouring; larger blocks keep more of the list's
// spatial order inside a block, along which impulses propagate within one sweep.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace sable::cd {

class SweepColouring {
 public:
  static constexpr std::uint32_t kNoBody = std::numeric_limits<std::uint32_t>::max();
  static constexpr int kMaxColours = 64;  // one bit per colour in a body's mask

  // body_i[a], body_j[a]: the bodies contact a updates (kNoBody: none), each < bodies;
  // serial[a] != 0: the contact runs in the serial tail. block >= 1.
  void build(std::span<const std::uint32_t> body_i, std::span<const std::uint32_t> body_j,
             std::span<const std::uint8_t> serial, std::size_t bodies, std::size_t block);

  std::size_t colours() const { return colour_begin_.empty() ? 0 : colour_begin_.size() - 1; }
  // The blocks of colour c: block indices [colour_begin(c), colour_begin(c + 1)).
  std::size_t colour_begin(std::size_t c) const { return colour_begin_[c]; }
  std::size_t blocks() const { return block_begin_.empty() ? 0 : block_begin_.size() - 1; }
  // The contacts of block b, in index order.
  std::span<const std::size_t> block(std::size_t b) const {
    return {order_.data() + block_begin_[b], block_begin_[b + 1] - block_begin_[b]};
  }
  // The contacts swept one by one after the colours, in index order.
  std::span<const std::size_t> serial() const {
    const std::size_t from = block_begin_.empty() ? 0 : block_begin_.back();
    return {order_.data() + from, order_.size() - from};
  }

 private:
  std::vector<std::size_t> order_;         // blocks colour by colour, then the serial tail
  std::vector<std::size_t> block_begin_;   // per block (in colour order), into order_; + end
  std::vector<std::size_t> colour_begin_;  // per colour, into the blocks; + end
  // Scratch, kept between builds so that a step allocates nothing once sizes settle.
  std::vector<std::uint64_t> mask_;    // per body: the colours of the blocks updating it
  std::vector<std::uint8_t> colour_;   // per block in index order (kMaxColours: serial)
  std::vector<std::size_t> count_;     // per colour
  std::vector<std::uint8_t> in_tail_;  // per contact
};

}  // namespace sable::cd
