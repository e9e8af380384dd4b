// The torque and drag on a turning wall, half-turn by half-turn, from a run's series.csv.
//
// Guillard, Forterre & Pouliquen (2015) turn a horizontal cylinder of length L about a vertical
// axis through its middle and report the drag F = 4 M / L from the torque M about that axis
// (the drag acting at the arm L / 4, the centre of each half). Their two regimes are the first
// half-turn (the cylinder meets undisturbed grains) and the stationary state after about a
// turn, so the torque is averaged over half-turns of pi / omega.
//
// Conventions (docs/analysis.md, `drag`):
//  - M is the component along the unit axis of the torque the grains exert ON the wall about
//    its pivot, as the run's series.csv gives it (wall_NAME_t{x,y,z}_Nm);
//  - the wall turns about +axis (right-handed) at omega > 0, so a torque that resists the
//    motion has M < 0; the drag is reported as the magnitude F = 4 |<M>| / L of the half-turn
//    mean, and `torque_opposes_turning` says whether <M> < 0 (a wrong axis direction or sign
//    of omega shows there);
//  - half-turn k (1, 2, ...) holds the rows with t0 + (k-1) P <= t < t0 + k P, P = pi / omega
//    (a row within 1e-9 P of a boundary starts the next half-turn); it is complete when the
//    series reaches its end time; the last, incomplete one is left out and reported apart;
//  - torque_sd is the rows' root-mean-square deviation about their mean (the fluctuation of
//    the signal within the half-turn, not an error of the mean).
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "sable/analysis/report.hpp"

namespace sable {

struct DragOptions {
  std::string series;                   // the run's series.csv
  std::string wall;                     // the turning wall's name
  std::array<double, 3> axis{0, 0, 1};  // normalised on use
  double omega = 0.0;                   // rad/s, > 0
  double length = 0.0;                  // L (m); 0: torque only
  std::optional<double> turn_start;     // t0 (s); default: the series' earliest time
  double stationary_from = 1.0;         // turns after t0
};

// The axial torque against time, read from a series.csv.
struct TorqueSeries {
  std::vector<double> time, torque;
};

struct HalfTurn {
  int index = 0;  // 1 for the first
  double t_start = 0.0, t_end = 0.0;
  std::size_t rows = 0;
  double torque = 0.0, torque_sd = 0.0;  // mean and rms deviation (N m)
};

struct DragResult {
  double half_turn_s = 0.0, turn_start_s = 0.0;
  std::vector<HalfTurn> half_turns;    // the complete ones, in order
  std::optional<HalfTurn> incomplete;  // the last half-turn, left out
  std::size_t rows_before_start = 0;   // rows with t < t0 (the preparation), not used
  // Over the complete half-turns that start at or after `stationary_from` turns.
  std::size_t stationary_first = 0, stationary_count = 0;
  double stationary_torque = 0.0, stationary_se = 0.0;  // mean, standard error (N m)
};

// Reads the time and M = torque . axis of `wall` from `path`. Throws InputError naming the
// file and the column when a needed column is missing (listing the walls the file has), and
// the line when a value is not a number or time goes backwards. A half-written last line (a
// run still writing) is ignored.
TorqueSeries read_torque_series(const std::string& path, const std::string& wall,
                                const std::array<double, 3>& axis);

// Throws InputError (naming opt.series) for a non-positive omega, a series that does not hold
// one complete half-turn after t0, or a complete half-turn without a row.
DragResult drag_per_half_turn(const TorqueSeries& s, const DragOptions& opt);

// drag.csv: half_turn, t_start_s, t_end_s, rows, torque_Nm, torque_sd_Nm[, drag_N].
Table drag_table(const DragResult& r, const DragOptions& opt);
Summary drag_summary(const DragResult& r, const DragOptions& opt);

}  // namespace sable
