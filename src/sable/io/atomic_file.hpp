// Atomic file replacement: write everything to a temporary beside the target, then rename.
//
// A run killed mid-write (out of time, out of memory, Ctrl-C) must never leave a half-written
// "latest" snapshot, CSV or VTK file in place of a good one. Every output goes to
// `PATH.tmp-<pid>` first and is moved over PATH with one rename(2), which POSIX makes atomic
// within a file system: a reader sees either the old file or the new one, never a mix.
#pragma once

#include <cstddef>
#include <functional>
#include <string>

namespace sable {

// The temporary a write of `path` goes through: `path.tmp-<pid>`.
std::string atomic_temp_path(const std::string& path);

// Move a finished temporary over its final name (replacing any existing file). On failure the
// temporary is removed and an IoError names both paths and the OS reason.
void commit_atomic(const std::string& tmp, const std::string& final_path);

// Write `path` atomically: `write` fills the temporary it is given; if it throws, the temporary
// is removed, `path` is left untouched and the exception propagates.
void write_atomic(const std::string& path,
                  const std::function<void(const std::string& tmp)>& write);

// Replace `path` with `text`, atomically.
void write_text_atomic(const std::string& path, const std::string& text);

// Replace `path` atomically with what `fill` writes, in as many pieces as it likes, through
// the `put(data, size)` it is given (each piece goes straight to the file: a large output
// need not be held whole in memory). An error names `path` and the OS reason.
using PutText = std::function<void(const char* data, std::size_t size)>;
void write_pieces_atomic(const std::string& path, const std::function<void(const PutText&)>& fill);

}  // namespace sable
