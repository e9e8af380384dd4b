// Fuzz target: Sable's snapshot reader on damaged and crafted snapshots, structure-aware.
//
// libhdf5 itself is not hardened against arbitrary bytes, and a raw-bytes fuzzer would spend
// its time in HDF5's own parser. Here the input is a script of edits, made with the HDF5 API,
// to one of a few valid snapshots written at start-up (2D DEM, 3D DEM with rolling springs,
// 3D wet DEM with liquid bridges, 2D contact dynamics): values replaced (raw bit patterns,
// indices nudged), datasets resized, retyped, reshaped, dropped, or made chunked with a huge
// extent and nothing stored, attributes rewritten or dropped, the stored scenario text edited.
// The file then goes through what `sable info`, `sable analyze` and `--resume` do: the header,
// the whole state with its hash, the analysis sample. A script may ask for the state hash to
// be rewritten to the edited state's (parsed from the refusal), so that the checks behind the
// hash are reached as a crafted file would reach them.
//
// Bad input must end in sable::InputError; any other exception, a crash or a sanitizer report
// is a finding.
#include <hdf5.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "fuzz_bytes.hpp"
#include "sable/analysis/sample.hpp"
#include "sable/core/error.hpp"
#include "sable/io/snapshot.hpp"
#include "sable/scenario/snapshot_sample.hpp"
#include "sable/scenario/verify.hpp"
#include "snapshot_edits.hpp"

namespace {

namespace fs = std::filesystem;
using sable::fuzz::Bytes;

// The state hash the refusal says the loaded state has, or 0.
std::uint64_t reported_hash(const std::string& problem) {
  const std::string key = "hashes to ";
  const std::size_t at = problem.find(key);
  if (at == std::string::npos) return 0;
  return std::strtoull(problem.c_str() + at + key.size(), nullptr, 16);
}

void rewrite_hash(const std::string& path, std::uint64_t hash) {
  hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  if (f < 0) return;
  hid_t a = H5Aopen_by_name(f, "/", "state_hash", H5P_DEFAULT, H5P_DEFAULT);
  if (a >= 0) {
    H5Awrite(a, H5T_NATIVE_UINT64, &hash);
    H5Aclose(a);
  }
  H5Fclose(f);
}

// What `sable info` does (the header, then the whole state against its hash), or with
// `analyze`, what `sable analyze` does (the analysis sample, which loads the state too). Each
// opens the file twice or three times: an input's time is mostly HDF5 opening files.
void exercise(const std::string& path, bool fix_hash, bool analyze) {
  const bool verbose = std::getenv("SABLE_FUZZ_VERBOSE") != nullptr;
  if (fix_hash || !analyze) {
    sable::SnapshotIntegrity v = sable::verify_snapshot(path);
    if (!v.verified && fix_hash) {
      if (const std::uint64_t h = reported_hash(v.problem); h != 0) {
        rewrite_hash(path, h);
        v = sable::verify_snapshot(path);
      }
    }
    if (verbose)
      std::fprintf(stderr, "snapshot: %s\n", v.verified ? "verified" : v.problem.c_str());
    if (!v.verified || !analyze) return;
  }
  if (sable::snapshot_dimension(path) == 2)
    sable::load_sample<2>(path);
  else
    sable::load_sample<3>(path);
  if (verbose) std::fprintf(stderr, "snapshot: sampled\n");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const sable::fuzz::SeedSnapshots seeds;
  static const std::string work = (seeds.dir() / "work.h5").string();
  Bytes in(data, size);
  const std::size_t seed = static_cast<std::size_t>(in.below(seeds.count()));
  const std::uint8_t flags = in.byte();
  const bool fix_hash = (flags & 1) != 0, analyze = (flags & 2) != 0;
  fs::copy_file(seeds.path(seed), work, fs::copy_options::overwrite_existing);
  sable::fuzz::apply_edits(work, in);
  try {
    exercise(work, fix_hash, analyze);
  } catch (const sable::InputError& e) {
    // SABLE_FUZZ_VERBOSE=1: say why each input was refused (to check a corpus reaches deep).
    if (std::getenv("SABLE_FUZZ_VERBOSE") != nullptr)
      std::fprintf(stderr, "refused: %s\n", e.what());
  }
  return 0;
}
