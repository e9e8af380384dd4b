// Time-series CSV logs (energy, wall forces, ...), one row per logged step, flushed at once.
//
// Column names carry their units ("time_s", "wall_force_z_N"); the first column is the step
// number. A resumed run reopens its logs with the snapshot's step: rows after that step were
// written by the interrupted run after its last snapshot and will be written again, so they
// are dropped (as is a half-written last line) before appending.
#pragma once

#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace sable {

class CsvLog {
 public:
  // Without `resume_after_step`: create (or truncate) `path` and write the header. With it:
  // keep the header and the rows whose first column (the step) is <= that step, then append.
  // A missing file is created; an existing one with a different header is an InputError.
  CsvLog(std::string path, std::vector<std::string> header,
         std::optional<std::uint64_t> resume_after_step = std::nullopt);

  // Append one row (as many values as header columns), written with 10 significant digits
  // (integral values exactly), and flush it to the OS.
  void row(const std::vector<double>& values);

  const std::string& path() const { return path_; }
  const std::vector<std::string>& header() const { return header_; }

 private:
  struct Closer {
    void operator()(std::FILE* f) const { std::fclose(f); }
  };
  void keep_rows_up_to(std::uint64_t step);

  std::string path_;
  std::vector<std::string> header_;
  std::unique_ptr<std::FILE, Closer> file_;
};

}  // namespace sable
