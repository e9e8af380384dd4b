#include "sable/io/atomic_file.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <system_error>

#include "sable/core/error.hpp"

namespace sable {

namespace {

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};

std::string os_reason(int err) {
  return err != 0 ? std::strerror(err) : "unknown error";
}

void remove_quietly(const std::string& path) {
  std::error_code ec;
  std::filesystem::remove(path, ec);
}

}  // namespace

std::string atomic_temp_path(const std::string& path) {
  return fmt::format("{}.tmp-{}", path, static_cast<long>(::getpid()));
}

void commit_atomic(const std::string& tmp, const std::string& final_path) {
  std::error_code ec;
  std::filesystem::rename(tmp, final_path, ec);
  if (ec) {
    remove_quietly(tmp);
    throw IoError(fmt::format("cannot move '{}' to '{}': {}", tmp, final_path, ec.message()));
  }
}

void write_atomic(const std::string& path,
                  const std::function<void(const std::string& tmp)>& write) {
  const std::string tmp = atomic_temp_path(path);
  try {
    write(tmp);
  } catch (...) {
    remove_quietly(tmp);
    throw;
  }
  commit_atomic(tmp, path);
}

void write_pieces_atomic(const std::string& path, const std::function<void(const PutText&)>& fill) {
  write_atomic(path, [&](const std::string& tmp) {
    errno = 0;
    std::unique_ptr<std::FILE, FileCloser> f(std::fopen(tmp.c_str(), "wb"));
    if (!f) throw IoError(fmt::format("cannot write '{}': {}", path, os_reason(errno)));
    fill([&](const char* data, std::size_t size) {
      errno = 0;
      if (std::fwrite(data, 1, size, f.get()) != size)
        throw IoError(fmt::format("cannot write '{}': {}", path, os_reason(errno)));
    });
    errno = 0;
    if (std::fflush(f.get()) != 0)
      throw IoError(fmt::format("cannot write '{}': {}", path, os_reason(errno)));
    errno = 0;
    if (std::fclose(f.release()) != 0)
      throw IoError(fmt::format("cannot write '{}': {}", path, os_reason(errno)));
  });
}

void write_text_atomic(const std::string& path, const std::string& text) {
  write_pieces_atomic(path, [&](const PutText& put) { put(text.data(), text.size()); });
}

}  // namespace sable
