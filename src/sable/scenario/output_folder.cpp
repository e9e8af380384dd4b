#include "sable/scenario/output_folder.hpp"

#include <fmt/format.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <filesystem>
#include <iterator>
#include <vector>

#include "sable/core/error.hpp"
#include "sable/io/snapshot.hpp"

namespace sable {
namespace {

namespace fs = std::filesystem;

constexpr const char* kOwnedFiles[] = {"series.csv", "grains.pvd", "contacts.pvd", "walls.pvd",
                                       "polyhedra.pvd"};
constexpr const char* kOwnedDirs[] = {"vtk", "snapshots", "xdmf"};
// Names quoted in a message (every owned entry); the rest counted.
constexpr std::size_t kListed = std::size(kOwnedFiles) + std::size(kOwnedDirs);

std::optional<std::uint64_t> parse_digits(std::string_view s) {
  if (s.empty() || s.size() > 19) return std::nullopt;
  std::uint64_t v = 0;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  if (r.ec != std::errc() || r.ptr != s.data() + s.size()) return std::nullopt;
  return v;
}

// The process id of a temporary `NAME.tmp-PID`, or nullopt for any other name.
std::optional<long> temp_owner(const std::string& name) {
  const auto at = name.rfind(".tmp-");
  if (at == std::string::npos) return std::nullopt;
  const auto pid = parse_digits(std::string_view(name).substr(at + 5));
  if (!pid || *pid == 0 || *pid > 0x7fffffffu) return std::nullopt;
  return static_cast<long>(*pid);
}

// A process that exists (kill(pid, 0) succeeds, or is refused for lack of permission).
bool process_alive(long pid) {
  if (pid == static_cast<long>(::getpid())) return false;  // a stale file of a reused id
  return ::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM;
}

void remove_or_throw(const fs::path& p) {
  std::error_code ec;
  fs::remove_all(p, ec);
  if (ec) throw IoError(fmt::format("cannot delete '{}': {}", clip(p.string()), ec.message()));
}

std::string listing(const std::vector<std::string>& names) {
  std::string s;
  for (std::size_t k = 0; k < names.size() && k < kListed; ++k) s += (k ? ", " : "") + names[k];
  if (names.size() > kListed) s += fmt::format(" and {} more", names.size() - kListed);
  return s;
}

void remove_stale_temporaries(const fs::path& dir,
                              const std::function<void(const std::string&)>& log) {
  std::vector<std::string> removed;
  for (const fs::path& d : {dir, dir / "vtk", dir / "snapshots", dir / "xdmf"}) {
    std::error_code ec;
    if (!fs::is_directory(d, ec)) continue;
    for (const auto& e : fs::directory_iterator(d, ec)) {
      const auto pid = temp_owner(e.path().filename().string());
      if (!pid || !e.is_regular_file(ec) || process_alive(*pid)) continue;
      remove_or_throw(e.path());
      removed.push_back(fs::relative(e.path(), dir, ec).string());
    }
  }
  if (!removed.empty())
    log(fmt::format("{}: deleted {} temporaries of interrupted writes ({})", clip(dir.string()),
                    removed.size(), listing(removed)));
}

// The owned entries present in `dir`: files, and directories that are not empty.
std::vector<std::string> owned_entries(const fs::path& dir) {
  std::vector<std::string> out;
  std::error_code ec;
  for (const char* f : kOwnedFiles)
    if (fs::exists(dir / f, ec)) out.emplace_back(f);
  for (const char* d : kOwnedDirs)
    if (fs::is_directory(dir / d, ec) && !fs::is_empty(dir / d, ec))
      out.push_back(d + std::string("/"));
  return out;
}

// The step of a snapshot: from its name, else from its header; nullopt if unreadable.
std::optional<std::uint64_t> snapshot_step(const fs::path& p) {
  if (auto s = step_in_file_name(p.filename().string())) return s;
  try {
    return read_snapshot_info(p.string()).step;
  } catch (const InputError&) {
    return std::nullopt;
  }
}

// Snapshots, their sidecars and VTK frames of steps after `step` (never `keep`, the snapshot
// being resumed).
std::vector<fs::path> outputs_after(const fs::path& dir, std::uint64_t step, const fs::path& keep) {
  std::vector<fs::path> out;
  std::error_code ec;
  const fs::path kept = fs::weakly_canonical(keep, ec);
  for (const char* sub : kOwnedDirs) {
    if (!fs::is_directory(dir / sub, ec)) continue;
    for (const auto& e : fs::directory_iterator(dir / sub, ec)) {
      const fs::path& p = e.path();
      if (!e.is_regular_file(ec) || temp_owner(p.filename().string())) continue;
      const bool snapshot = p.extension() == ".h5";
      const bool sidecar = p.extension() == ".xmf";  // xdmf/NAME.xmf: snapshots/NAME.h5's
      if (!snapshot && !sidecar && p.extension() != ".vtp") continue;
      std::optional<std::uint64_t> s;
      if (snapshot) {
        s = snapshot_step(p);
      } else if (sidecar) {
        const fs::path h5 = dir / "snapshots" / fs::path(p.filename()).replace_extension(".h5");
        s = fs::exists(h5, ec) ? snapshot_step(h5) : step_in_file_name(h5.filename().string());
      } else {
        s = step_in_file_name(p.filename().string());
      }
      if (s && *s > step && fs::weakly_canonical(p, ec) != kept) out.push_back(p);
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

void prepare_fresh(const OutputFolderRequest& req,
                   const std::function<void(const std::string&)>& log) {
  const fs::path dir(req.dir);
  const auto present = owned_entries(dir);
  if (present.empty()) return;
  if (!req.overwrite)
    throw InputError(fmt::format(
        "output folder '{}' already holds a run's outputs ({}); give another folder (--out or "
        "[output].dir), or --overwrite to delete them first (only series.csv, the .pvd files, "
        "vtk/, snapshots/ and xdmf/ are deleted)",
        clip(req.dir), listing(present)));
  for (const auto& name : present) remove_or_throw(dir / name);
  log(fmt::format("--overwrite: deleted {} in {}", listing(present), clip(req.dir)));
}

void prepare_resume(const OutputFolderRequest& req,
                    const std::function<void(const std::string&)>& log) {
  const fs::path dir(req.dir);
  const auto later = outputs_after(dir, *req.resume_step, req.resume_file);
  if (later.empty()) return;
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& p : later) names.push_back(fs::relative(p, dir, ec).string());
  if (!req.overwrite)
    throw InputError(fmt::format(
        "output folder '{}' holds {} outputs of steps after the resumed step {} ({}): a "
        "continuation of this run that the resume would mix with its own; give another folder "
        "(--out), or --overwrite to delete those files first",
        clip(req.dir), names.size(), *req.resume_step, listing(names)));
  for (const auto& p : later) remove_or_throw(p);
  log(fmt::format("--overwrite: deleted {} outputs of steps after {} in {} ({})", names.size(),
                  *req.resume_step, clip(req.dir), listing(names)));
}

}  // namespace

std::optional<std::uint64_t> step_in_file_name(const std::string& name) {
  const auto dot = name.rfind('.');
  if (dot == std::string::npos) return std::nullopt;
  const std::string_view stem = std::string_view(name).substr(0, dot);
  const auto sep = stem.rfind('_');
  if (sep == std::string_view::npos) return std::nullopt;
  const std::string_view prefix = stem.substr(0, sep);
  const bool known = prefix == "step" || prefix == "crash_step" || prefix == "interrupted_step" ||
                     prefix == "grains" || prefix == "contacts" || prefix == "walls" ||
                     prefix == "polyhedra";
  return known ? parse_digits(stem.substr(sep + 1)) : std::nullopt;
}

void prepare_output_folder(const OutputFolderRequest& req,
                           const std::function<void(const std::string&)>& log) {
  std::error_code ec;
  if (fs::exists(req.dir, ec) && !fs::is_directory(req.dir, ec))
    throw InputError(fmt::format("output folder '{}' is a file, expected a folder", clip(req.dir)));
  remove_stale_temporaries(req.dir, log);
  if (req.resume_step)
    prepare_resume(req, log);
  else
    prepare_fresh(req, log);
}

}  // namespace sable
