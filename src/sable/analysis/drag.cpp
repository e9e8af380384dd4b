#include "sable/analysis/drag.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <numbers>
#include <sstream>

#include "sable/core/error.hpp"

namespace sable {

namespace {

// A row this close to a half-turn boundary (in half-turns) is taken to start the next one:
// series.csv writes times with 10 significant digits, so a row logged at a boundary reads
// slightly before or after it.
constexpr double kBoundary = 1e-9;

std::vector<std::string> split_commas(const std::string& line) {
  std::vector<std::string> out;
  std::size_t pos = 0;
  while (true) {
    const std::size_t c = line.find(',', pos);
    out.push_back(line.substr(pos, c == std::string::npos ? std::string::npos : c - pos));
    if (c == std::string::npos) return out;
    pos = c + 1;
  }
}

// The walls a series.csv logs torques for, for a message about a missing one.
std::string walls_in(const std::vector<std::string>& header) {
  std::string out;
  for (const auto& h : header)
    if (h.rfind("wall_", 0) == 0 && h.size() > 11 && h.compare(h.size() - 6, 6, "_tz_Nm") == 0)
      out += (out.empty() ? "" : ", ") + h.substr(5, h.size() - 11);
  return out.empty() ? "none" : out;
}

double parse_value(const std::string& text, const std::string& path, std::size_t line,
                   const std::string& column) {
  const char* begin = text.c_str();
  char* end = nullptr;
  const double v = std::strtod(begin, &end);
  if (end == begin || *end != '\0' || !std::isfinite(v))
    throw InputError(fmt::format("{}: line {}, column {}: '{}' is not a finite number", clip(path),
                                 line, column, clip(text)));
  return v;
}

double mean_of(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return s / static_cast<double>(v.size());
}

// Root-mean-square deviation about the mean (two passes, for accuracy).
double rms_deviation(const std::vector<double>& v, double mean) {
  double s = 0.0;
  for (double x : v) s += (x - mean) * (x - mean);
  return std::sqrt(s / static_cast<double>(v.size()));
}

}  // namespace

TorqueSeries read_torque_series(const std::string& path, const std::string& wall,
                                const std::array<double, 3>& axis) {
  std::ifstream in(path);
  if (!in)
    throw InputError(
        fmt::format("{}: no such series file (drag: --series, by default the "
                    "run's series.csv beside its snapshots/ folder)",
                    clip(path)));
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  std::vector<std::string> lines;
  std::size_t pos = 0;
  while (pos < text.size()) {
    const std::size_t nl = text.find('\n', pos);
    if (nl == std::string::npos) break;  // a half-written last line
    lines.push_back(text.substr(pos, nl - pos));
    pos = nl + 1;
  }
  if (lines.empty()) throw InputError(fmt::format("{}: empty, expected a header line", clip(path)));
  const std::vector<std::string> header = split_commas(lines.front());
  auto column = [&](const std::string& name) {
    const auto it = std::find(header.begin(), header.end(), name);
    if (it == header.end())
      throw InputError(fmt::format("{}: no column '{}' (walls with torques in this file: {})",
                                   clip(path), clip(name), clip(walls_in(header))));
    return static_cast<std::size_t>(it - header.begin());
  };
  const std::size_t tcol = column("time_s");
  const double norm = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
  if (!(norm > 0.0) || !std::isfinite(norm))
    throw InputError("option --drag-axis: the axis must be a non-zero vector");
  std::vector<std::pair<std::size_t, double>> parts;  // torque column, axis component
  static constexpr const char* kAxes[] = {"x", "y", "z"};
  for (std::size_t d = 0; d < 3; ++d)
    if (axis[d] != 0.0)
      parts.emplace_back(column(fmt::format("wall_{}_t{}_Nm", wall, kAxes[d])), axis[d] / norm);
  TorqueSeries s;
  for (std::size_t l = 1; l < lines.size(); ++l) {
    if (lines[l].empty()) continue;
    const std::vector<std::string> f = split_commas(lines[l]);
    if (f.size() != header.size())
      throw InputError(fmt::format("{}: line {} has {} values, the header {} columns", clip(path),
                                   l + 1, f.size(), header.size()));
    const double t = parse_value(f[tcol], path, l + 1, "time_s");
    if (!s.time.empty() && t < s.time.back())
      throw InputError(fmt::format("{}: line {}: time {} s is before the previous row's {} s",
                                   clip(path), l + 1, t, s.time.back()));
    double m = 0.0;
    for (const auto& [c, u] : parts) m += u * parse_value(f[c], path, l + 1, header[c]);
    s.time.push_back(t);
    s.torque.push_back(m);
  }
  return s;
}

DragResult drag_per_half_turn(const TorqueSeries& s, const DragOptions& opt) {
  if (!(opt.omega > 0.0) || !std::isfinite(opt.omega))
    throw InputError(fmt::format(
        "option --omega: drag needs the wall's turning rate > 0 rad/s, got {}", opt.omega));
  if (s.time.empty()) throw InputError(fmt::format("{}: no data rows", clip(opt.series)));
  DragResult r;
  r.half_turn_s = std::numbers::pi / opt.omega;
  r.turn_start_s = opt.turn_start ? *opt.turn_start : s.time.front();
  const double p = r.half_turn_s, t0 = r.turn_start_s;
  auto half_turn_of = [&](double t) { return std::floor((t - t0) / p + kBoundary); };
  const double last = half_turn_of(s.time.back());  // the half-turn the series ends in
  if (last < 1.0)
    throw InputError(fmt::format(
        "{}: the series runs from t0 = {} s to {} s, less than one half-turn ({} s at {} "
        "rad/s): no complete half-turn (check --turn-start and --omega)",
        clip(opt.series), t0, s.time.back(), p, opt.omega));
  const auto complete = static_cast<std::size_t>(last);
  std::vector<std::vector<double>> values(complete + 1);
  for (std::size_t k = 0; k < s.time.size(); ++k) {
    const double h = half_turn_of(s.time[k]);
    if (h < 0.0) {
      ++r.rows_before_start;
      continue;
    }
    values[static_cast<std::size_t>(h)].push_back(s.torque[k]);
  }
  for (std::size_t k = 0; k <= complete; ++k) {
    HalfTurn h;
    h.index = static_cast<int>(k) + 1;
    h.t_start = t0 + static_cast<double>(k) * p;
    h.t_end = t0 + static_cast<double>(k + 1) * p;
    h.rows = values[k].size();
    if (h.rows == 0 && k < complete)
      throw InputError(
          fmt::format("{}: half-turn {} (t from {} to {} s) has no row: the series is logged "
                      "less often than every half-turn ({} s); log it more often",
                      clip(opt.series), h.index, h.t_start, h.t_end, p));
    h.torque = h.rows ? mean_of(values[k]) : std::numeric_limits<double>::quiet_NaN();
    h.torque_sd = h.rows ? rms_deviation(values[k], h.torque) : 0.0;
    if (k < complete)
      r.half_turns.push_back(h);
    else
      r.incomplete = h;
  }
  for (const HalfTurn& h : r.half_turns) {
    if (0.5 * (h.index - 1) < opt.stationary_from - kBoundary) {
      ++r.stationary_first;
      continue;
    }
    ++r.stationary_count;
  }
  if (r.stationary_count > 0) {
    std::vector<double> m;
    for (std::size_t k = r.stationary_first; k < r.half_turns.size(); ++k)
      m.push_back(r.half_turns[k].torque);
    r.stationary_torque = mean_of(m);
    // The standard error of the mean of the half-turn means
    // (sample standard deviation / sqrt(n) = rms deviation / sqrt(n - 1)).
    r.stationary_se = m.size() > 1 ? rms_deviation(m, r.stationary_torque) /
                                         std::sqrt(static_cast<double>(m.size() - 1))
                                   : std::numeric_limits<double>::quiet_NaN();
  }
  return r;
}

Table drag_table(const DragResult& r, const DragOptions& opt) {
  std::vector<double> index, t0, t1, rows, m, sd, drag;
  for (const HalfTurn& h : r.half_turns) {
    index.push_back(h.index);
    t0.push_back(h.t_start);
    t1.push_back(h.t_end);
    rows.push_back(static_cast<double>(h.rows));
    m.push_back(h.torque);
    sd.push_back(h.torque_sd);
    drag.push_back(4.0 * std::abs(h.torque) / opt.length);
  }
  Table t;
  t.add("half_turn", index);
  t.add("t_start_s", t0);
  t.add("t_end_s", t1);
  t.add("rows", rows);
  t.add("torque_Nm", m);
  t.add("torque_sd_Nm", sd);
  if (opt.length > 0.0) t.add("drag_N", drag);
  return t;
}

namespace {

Summary torque_and_drag(double torque, double spread, const char* spread_name,
                        const DragOptions& opt) {
  Summary s;
  s.add("torque_Nm", torque);
  s.add(fmt::format("torque_{}_Nm", spread_name), spread);
  if (opt.length > 0.0) {
    s.add("drag_N", 4.0 * std::abs(torque) / opt.length);
    s.add(fmt::format("drag_{}_N", spread_name), 4.0 * spread / opt.length);
  }
  s.add("torque_opposes_turning", torque < 0.0);
  return s;
}

}  // namespace

Summary drag_summary(const DragResult& r, const DragOptions& opt) {
  const double n =
      std::sqrt(opt.axis[0] * opt.axis[0] + opt.axis[1] * opt.axis[1] + opt.axis[2] * opt.axis[2]);
  Summary s;
  s.add("series", opt.series);
  s.add("wall", opt.wall);
  s.add("axis", std::vector<double>{opt.axis[0] / n, opt.axis[1] / n, opt.axis[2] / n});
  s.add("omega_rad_s", opt.omega);
  s.add("half_turn_s", r.half_turn_s);
  s.add("turn_start_s", r.turn_start_s);
  if (opt.length > 0.0) s.add("length_m", opt.length);
  s.add("rows_before_turn_start", r.rows_before_start);
  s.add("half_turns", r.half_turns.size());
  Summary first =
      torque_and_drag(r.half_turns.front().torque, r.half_turns.front().torque_sd, "sd", opt);
  first.add("rows", r.half_turns.front().rows);
  s.add("first_half_turn", first);
  if (r.stationary_count > 0) {
    Summary st = torque_and_drag(r.stationary_torque, r.stationary_se, "se", opt);
    st.add("from_turns", opt.stationary_from);
    st.add("first_half_turn", r.half_turns[r.stationary_first].index);
    st.add("half_turns", r.stationary_count);
    s.add("stationary", st);
  } else {
    Summary st;
    st.add("skipped", fmt::format("no complete half-turn starts at or after {} turns (the series "
                                  "holds {} complete half-turns)",
                                  opt.stationary_from, r.half_turns.size()));
    s.add("stationary", st);
  }
  if (r.incomplete) {
    Summary inc;
    inc.add("half_turn", r.incomplete->index);
    inc.add("t_start_s", r.incomplete->t_start);
    inc.add("t_end_s", r.incomplete->t_end);
    inc.add("rows", r.incomplete->rows);
    inc.add("note", "incomplete: left out of drag.csv and of the averages");
    s.add("incomplete_last_half_turn", inc);
  }
  return s;
}

}  // namespace sable
