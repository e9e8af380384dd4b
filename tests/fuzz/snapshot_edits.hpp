// The snapshot fuzz target's pieces: valid seed snapshots written at start-up, and the edits
// an input's bytes decode into (see snapshot.cpp).
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "fuzz_bytes.hpp"

namespace sable::fuzz {

// A few small, valid snapshots in a directory of this process's own (in /dev/shm when it
// exists: the target copies and rewrites one per input), removed at exit.
class SeedSnapshots {
 public:
  SeedSnapshots();
  ~SeedSnapshots();
  SeedSnapshots(const SeedSnapshots&) = delete;
  SeedSnapshots& operator=(const SeedSnapshots&) = delete;

  std::size_t count() const { return paths_.size(); }
  const std::string& path(std::size_t k) const { return paths_[k]; }
  const std::filesystem::path& dir() const { return dir_; }

 private:
  std::filesystem::path dir_;
  std::vector<std::string> paths_;
};

// Applies the edits `in` decodes to the snapshot at `path` (at most 8 of them), in place.
void apply_edits(const std::string& path, Bytes& in);

}  // namespace sable::fuzz
