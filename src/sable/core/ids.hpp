// Stable particle ids (index + generation), as in Jolt and Box2D.
//
// Storage slots move (grains are removed, and reordered along a space-filling curve for
// locality); a ParticleId does not. The registry maps an id to its current slot, and the
// generation makes a stale id (of a removed grain) detectable instead of silently aliasing.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

namespace sable {

struct ParticleId {
  std::uint32_t index = std::numeric_limits<std::uint32_t>::max();
  std::uint32_t generation = 0;
  friend bool operator==(const ParticleId&, const ParticleId&) = default;
};

class IdRegistry {
 public:
  static constexpr std::uint32_t kNoSlot = std::numeric_limits<std::uint32_t>::max();

  ParticleId create(std::uint32_t slot) {
    std::uint32_t index;
    if (!free_.empty()) {
      index = free_.back();
      free_.pop_back();
    } else {
      index = static_cast<std::uint32_t>(slot_.size());
      slot_.push_back(kNoSlot);
      generation_.push_back(0);
    }
    slot_[index] = slot;
    return {index, generation_[index]};
  }
  // Destroying a stale id is a no-op: it must never invalidate the live id reusing its index.
  void destroy(ParticleId id) {
    if (!valid(id)) return;
    slot_[id.index] = kNoSlot;
    ++generation_[id.index];
    free_.push_back(id.index);
  }
  bool valid(ParticleId id) const {
    return id.index < slot_.size() && generation_[id.index] == id.generation &&
           slot_[id.index] != kNoSlot;
  }
  std::uint32_t slot(ParticleId id) const { return valid(id) ? slot_[id.index] : kNoSlot; }
  void move(ParticleId id, std::uint32_t new_slot) { slot_[id.index] = new_slot; }
  ParticleId id_at_index(std::uint32_t index) const { return {index, generation_[index]}; }

  // Raw state, for snapshots.
  const std::vector<std::uint32_t>& slots() const { return slot_; }
  const std::vector<std::uint32_t>& generations() const { return generation_; }
  const std::vector<std::uint32_t>& free_list() const { return free_; }
  void restore(std::vector<std::uint32_t> slots, std::vector<std::uint32_t> generations,
               std::vector<std::uint32_t> free_list) {
    slot_ = std::move(slots);
    generation_ = std::move(generations);
    free_ = std::move(free_list);
  }

 private:
  std::vector<std::uint32_t> slot_;
  std::vector<std::uint32_t> generation_;
  std::vector<std::uint32_t> free_;
};

}  // namespace sable
