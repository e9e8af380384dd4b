#include "sable/analysis/analyze.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <optional>

#include <sys/wait.h>

#include "sable/analysis/analyze_parts.hpp"
#include "sable/analysis/drag.hpp"
#include "sable/analysis/frame.hpp"
#include "sable/core/error.hpp"
#include "sable/io/vtk_xml.hpp"

namespace sable {

namespace fs = std::filesystem;

namespace {

std::vector<double> parse_numbers(const std::string& text, const std::string& option) {
  std::vector<double> out;
  std::size_t pos = 0;
  while (pos <= text.size()) {
    const std::size_t comma = std::min(text.find(',', pos), text.size());
    const std::string item = text.substr(pos, comma - pos);
    try {
      std::size_t used = 0;
      out.push_back(std::stod(item, &used));
      if (used != item.size()) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      throw InputError(
          fmt::format("option {}: '{}' is not a number (in '{}')", option, clip(item), clip(text)));
    }
    pos = comma + 1;
  }
  return out;
}

// "a:b[:c]" -> its parts.
std::vector<std::string> split_colon(const std::string& text) {
  std::vector<std::string> parts;
  std::size_t pos = 0;
  while (true) {
    const std::size_t c = text.find(':', pos);
    parts.push_back(text.substr(pos, c == std::string::npos ? std::string::npos : c - pos));
    if (c == std::string::npos) return parts;
    pos = c + 1;
  }
}

template <int D>
typename Space<D>::Vec parse_point(const std::string& text, const std::string& option) {
  const std::vector<double> v = parse_numbers(text, option);
  if (v.size() != static_cast<std::size_t>(D))
    throw InputError(fmt::format("option {}: '{}' has {} coordinates, a {}D point has {}", option,
                                 clip(text), v.size(), D, D));
  typename Space<D>::Vec p;
  for (int d = 0; d < D; ++d) p[d] = v[static_cast<std::size_t>(d)];
  return p;
}

template <int D>
std::optional<Region<D>> parse_region(const std::string& text) {
  if (text.empty()) return std::nullopt;
  const auto parts = split_colon(text);
  if (parts.size() != 2)
    throw InputError(
        fmt::format("option --region: '{}' is not 'lo:hi' (e.g. 0,0,0:1,1,1)", clip(text)));
  Region<D> r;
  r.lo = parse_point<D>(parts[0], "--region");
  r.hi = parse_point<D>(parts[1], "--region");
  if (!(r.hi.array() > r.lo.array()).all())
    throw InputError(
        fmt::format("option --region: '{}' is empty (every hi must exceed its lo)", clip(text)));
  return r;
}

std::optional<RotatingFrame> parse_frame(const AnalyzeOptions& opt) {
  if (opt.frame.empty()) {
    if (opt.omega != 0.0 && !analysis_wanted(opt, "drag"))
      throw InputError("option --omega needs --frame (the axis) or the drag analysis");
    return std::nullopt;
  }
  const auto parts = split_colon(opt.frame);
  if (parts.size() != 2)
    throw InputError(
        fmt::format("option --frame: '{}' is not 'px,py,pz:ux,uy,uz'", clip(opt.frame)));
  const std::vector<double> p = parse_numbers(parts[0], "--frame"),
                            u = parse_numbers(parts[1], "--frame");
  if (p.size() != 3 || u.size() != 3)
    throw InputError(
        fmt::format("option --frame: '{}' needs a 3D point and a 3D axis", clip(opt.frame)));
  RotatingFrame f;
  f.point = Eigen::Vector3d(p[0], p[1], p[2]);
  f.axis = Eigen::Vector3d(u[0], u[1], u[2]);
  f.omega = opt.omega;
  return f;
}

void check_options(const AnalyzeOptions& opt) {
  if (opt.snapshots.empty()) throw InputError("sable analyze: no snapshot given");
  for (const auto& name : opt.only)
    if (std::find_if(std::begin(kAnalyses), std::end(kAnalyses),
                     [&](const char* a) { return name == a; }) == std::end(kAnalyses)) {
      std::string all;
      for (const char* a : kAnalyses) all += std::string(all.empty() ? "" : ", ") + a;
      throw InputError(
          fmt::format("option --only: unknown analysis '{}' (known: {})", clip(name), all));
    }
  if (opt.bins <= 0) throw InputError(fmt::format("option --bins: {} must be > 0", opt.bins));
  parse_vtk_encoding(opt.vtk_format, "option --vtk-format");
  if (!(opt.eps >= 0.0 && opt.eps < 1.0))
    throw InputError(fmt::format("option --eps: {} must be in [0, 1)", opt.eps));
  if (opt.solid_fraction < 0.0 || opt.solid_fraction > 1.0)
    throw InputError(
        fmt::format("option --solid-fraction: {} must be in (0, 1]", opt.solid_fraction));
  if (opt.width < 0.0) throw InputError(fmt::format("option --width: {} must be > 0", opt.width));
  if (opt.reference_force < 0.0)
    throw InputError(fmt::format("option --reference-force: {} must be >= 0", opt.reference_force));
  for (const auto& s : opt.snapshots) {
    std::error_code ec;
    if (fs::is_directory(s, ec)) {
      const bool run_dir = fs::is_directory(fs::path(s) / "snapshots", ec);
      throw InputError(fmt::format(
          "{}: a folder, expected snapshot files (.h5){}", clip(s),
          run_dir
              ? fmt::format("; its run's snapshots are in {}/snapshots/, e.g. {}/snapshots/*.h5",
                            clip(s), clip(s))
              : ""));
    }
    if (!fs::exists(s, ec)) throw InputError(fmt::format("{}: no such snapshot file", clip(s)));
    if (!fs::is_regular_file(s, ec))
      throw InputError(fmt::format("{}: not a regular file, expected a snapshot (.h5)", clip(s)));
  }
}

// The drag analysis's options, checked, or nothing when it does not run. The series defaults
// to the run's own: snapshots sit in RUN/snapshots/, the series in RUN/series.csv.
std::optional<DragOptions> drag_options(const AnalyzeOptions& opt) {
  if (!analysis_wanted(opt, "drag")) return std::nullopt;
  if (opt.drag_wall.empty())
    throw InputError("the drag analysis needs --drag-wall (the name of the turning wall)");
  if (!(opt.omega > 0.0) || !std::isfinite(opt.omega))
    throw InputError(fmt::format(
        "option --omega: the drag analysis needs the wall's turning rate > 0 rad/s, got {}",
        opt.omega));
  if (!(opt.drag_length >= 0.0) || !std::isfinite(opt.drag_length))
    throw InputError(fmt::format(
        "option --drag-length: {} must be >= 0 m (0: report the torque only)", opt.drag_length));
  if (!(opt.stationary_from >= 0.0) || !std::isfinite(opt.stationary_from))
    throw InputError(
        fmt::format("option --stationary-from: {} must be >= 0 turns", opt.stationary_from));
  DragOptions d;
  d.wall = opt.drag_wall;
  d.omega = opt.omega;
  d.length = opt.drag_length;
  d.stationary_from = opt.stationary_from;
  if (!std::isnan(opt.turn_start)) {
    if (!std::isfinite(opt.turn_start))
      throw InputError(fmt::format("option --turn-start: {} is not a time", opt.turn_start));
    d.turn_start = opt.turn_start;
  }
  d.series =
      !opt.series.empty()
          ? opt.series
          : (fs::path(opt.snapshots.front()).parent_path().parent_path() / "series.csv").string();
  std::string axis_text = opt.drag_axis, option = "--drag-axis";
  if (axis_text.empty() && !opt.frame.empty()) {
    const auto parts = split_colon(opt.frame);
    if (parts.size() == 2) axis_text = parts[1];
    option = "--frame";
  }
  if (!axis_text.empty()) {
    const std::vector<double> u = parse_numbers(axis_text, option);
    if (u.size() != 3 || (u[0] == 0.0 && u[1] == 0.0 && u[2] == 0.0))
      throw InputError(
          fmt::format("option {}: '{}' is not a non-zero axis ux,uy,uz", option, clip(axis_text)));
    d.axis = {u[0], u[1], u[2]};
  }
  return d;
}

void check_load_share(const AnalyzeOptions& opt) {
  if (!analysis_wanted(opt, "load-share")) return;
  if (std::isnan(opt.level))
    throw InputError("the load-share analysis needs --level Z (m, the height of the cut)");
  if (!std::isfinite(opt.level))
    throw InputError(fmt::format("option --level: {} is not a height", opt.level));
}

// Whether any analysis that reads the snapshots runs (drag reads the series only).
bool needs_samples(const AnalyzeOptions& opt) {
  for (const char* a : kAnalyses)
    if (std::string(a) != "drag" && analysis_wanted(opt, a)) return true;
  return false;
}

std::string default_out_dir(const AnalyzeOptions& opt) {
  if (!opt.out_dir.empty()) return opt.out_dir;
  return (fs::path(opt.snapshots.front()).parent_path() / "analysis").string();
}

template <int D>
std::string analyze(const AnalyzeOptions& opt, const std::string& out_dir,
                    const SampleLoaders& loaders) {
  const std::optional<Region<D>> region = parse_region<D>(opt.region);
  const std::optional<RotatingFrame> frame = parse_frame(opt);
  // The series is read before any snapshot, so that its errors come before any output.
  const std::optional<DragOptions> drag = drag_options(opt);
  std::optional<DragResult> dragged;
  if (drag)
    dragged = drag_per_half_turn(read_torque_series(drag->series, drag->wall, drag->axis), *drag);
  const ResultWriter out(out_dir, opt.snapshots);
  AnalysisParts<D> parts(opt, out, region);
  if (drag) parts.set_drag(*drag, *dragged);
  for (std::size_t k = 0; k < opt.snapshots.size() && needs_samples(opt); ++k) {
    if (opt.log)
      *opt.log << fmt::format("[{}/{}] {}\n", k + 1, opt.snapshots.size(), opt.snapshots[k]);
    Sample<D> s = loaders.load<D>(opt.snapshots[k]);
    parts.add_lab(s);  // before a turning frame changes the velocities
    if (frame) s = to_rotating_frame(s, *frame);
    parts.add(s);
  }
  parts.finish();
  return out_dir;
}

void plot(const AnalyzeOptions& opt, const std::string& out_dir) {
  std::string script = opt.plot_script;
  if (script.empty()) throw InputError("--plot: no plotting script is known to this build");
  if (!fs::is_regular_file(script))
    throw InputError(fmt::format("--plot: the plotting script {} is missing", script));
  const std::string cmd = fmt::format("/usr/bin/python3 '{}' '{}'", script, out_dir);
  if (opt.log) *opt.log << "plotting: " << cmd << "\n";
  const int status = std::system(cmd.c_str());
  const int rc = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  if (rc != 0)
    throw SimulationError(fmt::format(
        "--plot: '{}' failed (exit status {}); the numbers are written in {}", cmd, rc, out_dir));
}

}  // namespace

bool analysis_wanted(const AnalyzeOptions& opt, const std::string& name) {
  if (!opt.only.empty()) return std::find(opt.only.begin(), opt.only.end(), name) != opt.only.end();
  if (name == "drag") return !opt.drag_wall.empty();
  if (name == "load-share") return !std::isnan(opt.level);
  return true;
}

std::string run_analysis(const AnalyzeOptions& opt, const SampleLoaders& loaders) {
  check_options(opt);
  check_load_share(opt);
  drag_options(opt);  // its option errors before the snapshots are read
  const int dim = snapshot_dimension(opt.snapshots.front());
  for (const auto& s : opt.snapshots)
    if (snapshot_dimension(s) != dim)
      throw InputError(fmt::format("{}: a {}D snapshot among {}D ones", s, 5 - dim, dim));
  std::string out_dir = default_out_dir(opt);
  if (dim == 2)
    analyze<2>(opt, out_dir, loaders);
  else
    analyze<3>(opt, out_dir, loaders);
  if (opt.plot) plot(opt, out_dir);
  return out_dir;
}

}  // namespace sable
