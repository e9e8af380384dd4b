// The `sable` command line: run, check, info, analyze, models, fc3d.
//
// Exit codes (docs/reliability.md): 0 success; 1 the computation failed (NaN, runaway grain:
// a snapshot is written; `fc3d` not converged); 2 bad input (scenario, snapshot, command
// line), with a message naming the place; 3 an output could not be written (disk full, no
// permission); 128 + N: `run` stopped by signal N (SIGHUP, SIGINT, SIGTERM) after finishing
// its step and writing a final snapshot.
#include <fmt/format.h>
#include <hdf5.h>
#include <sys/resource.h>
#include <CLI/CLI.hpp>
#include <charconv>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <iostream>

#include "launch.hpp"
#include "sable/analysis/analyze.hpp"
#include "sable/cd/fc_problem.hpp"
#include "sable/contact/registry.hpp"
#include "sable/core/error.hpp"
#include "sable/io/atomic_file.hpp"
#include "sable/io/snapshot.hpp"
#include "sable/scenario/config.hpp"
#include "sable/scenario/runner.hpp"
#include "sable/scenario/snapshot_sample.hpp"
#include "sable/scenario/verify.hpp"

namespace {

constexpr int kExitFailed = 1;
constexpr int kExitInput = 2;
constexpr int kExitIo = 3;

// The signal that asked `run` to stop (0: none). A signal handler can only set a flag of this
// type; the runner reads it after every step.
volatile std::sig_atomic_t g_stop_signal = 0;

extern "C" void on_stop_signal(int sig) {
  g_stop_signal = sig;
}

// SIGINT, SIGTERM and SIGHUP finish the step and write a snapshot. The handler is reset to
// the default by the first signal (SA_RESETHAND): a second one ends the process at once, and
// the atomic writes still leave no damaged file. SIGXFSZ is ignored so that a file-size limit
// fails the write (EFBIG, an I/O error with the file named) instead of killing the run.
void install_signal_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESETHAND;
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) sigaction(sig, &sa, nullptr);
  std::signal(SIGXFSZ, SIG_IGN);
}

const char* signal_name(int sig) {
  switch (sig) {
    case SIGINT:
      return "SIGINT";
    case SIGTERM:
      return "SIGTERM";
    case SIGHUP:
      return "SIGHUP";
    default:
      return "a signal";
  }
}

// Under MPI every process runs the scenario (apps/sable/launch.hpp); process 0 reports.
int cmd_run(const std::string& file, sable::RunOptions opt, const Launch& launch) {
  const sable::ScenarioConfig cfg = sable::load_scenario(file);
  install_signal_handlers();
  opt.stop = &g_stop_signal;
  opt.domains = launch.domains();
  const sable::RunResult r = sable::run_scenario(cfg, opt);
  if (launch.rank() != 0) return r.interrupted_by != 0 ? 128 + r.interrupted_by : 0;
  if (r.interrupted_by != 0) {
    std::cerr << fmt::format(
        "interrupted by {} at step {} (t = {:.6g} s), state hash {:016x}{}\n",
        signal_name(r.interrupted_by), r.steps, r.time, r.state_hash,
        r.last_snapshot.empty()
            ? std::string()
            : fmt::format("; state written to {}; continue with: sable run {} --resume {}",
                          r.last_snapshot, file, r.last_snapshot));
    return 128 + r.interrupted_by;
  }
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  std::cerr << fmt::format(
      "done: {} grains, {} steps, t = {:.6g} s, kinetic energy {:.4g} J, {:.1f} s wall time, "
      "peak memory {:.1f} MiB{}, state hash {:016x}\n",
      r.grains, r.steps, r.time, r.kinetic_energy, r.wall_seconds,
      static_cast<double>(usage.ru_maxrss) / 1024.0,
      launch.size() > 1 ? fmt::format(" (process 0 of {})", launch.size()) : std::string(),
      r.state_hash);
  return 0;
}

int cmd_check(const std::string& file) {
  const sable::ScenarioConfig cfg = sable::load_scenario(file);
  std::cout << sable::describe_scenario(cfg) << "\nOK\n";
  return 0;
}

// The header, then the whole state loaded and its hash compared (exit 2 if it differs).
int cmd_info(const std::string& file) {
  const sable::SnapshotInfo i = sable::read_snapshot_info(file);
  std::cout << fmt::format(
      "{}\n  dimension   {}\n  step        {}\n  time        {:.9g} s\n  dt          {:.6g} s\n"
      "  grains      {}\n  walls       {}\n  pair lists  {} grain-grain, {} grain-wall candidates\n"
      "  stage       {} (step {} of it)\n  state hash  {:016x}\n",
      file, i.dimension, i.step, i.time, i.dt, i.grains, i.walls, i.pairs, i.wall_pairs,
      i.pos.stage + 1, i.pos.stage_step, i.state_hash);
  const sable::SnapshotIntegrity v = sable::verify_snapshot(file);
  std::cout << (v.verified ? std::string("  integrity   verified (state hash matches)\n")
                           : fmt::format("  integrity   FAILED: {}\n", v.problem));
  return v.verified ? 0 : 2;
}

int cmd_models() {
  for (const auto& m : sable::kContactSubModels)
    std::cout << fmt::format("{:<11} {:<9} {}\n", m.category, m.name, m.summary);
  return 0;
}

struct Fc3dOptions {
  std::string local = "exact";  // 2-4x faster than the bi-potential on the shared problems
  std::string order = "forward";
  double tolerance = 1e-6;
  int max_iterations = 1000;
  double relaxation = 1.0;
  std::uint64_t seed = 1;
  int stagnation_window = sable::cd::NlgsSettings{}.stagnation_window;
  int newton_iterations = 100;
  int repeat = 1;
  std::string reactions;  // file for the solution (empty: none)
};

int cmd_fc3d(const std::string& file, const Fc3dOptions& o) {
  sable::cd::NlgsSettings s;
  s.local = *sable::cd::parse_local_solver(o.local);  // values checked by CLI11
  s.order = *sable::cd::parse_sweep_order(o.order);
  s.criterion = sable::cd::Criterion::kNatural;
  s.tolerance = o.tolerance;
  s.max_iterations = o.max_iterations;
  if (!(o.relaxation > 0.0 && o.relaxation < 2.0))
    throw sable::InputError(fmt::format("--relaxation {}: expected 0 < w < 2", o.relaxation));
  s.relaxation = o.relaxation;
  s.stagnation_window = o.stagnation_window;
  const sable::cd::FcReport r = sable::cd::solve_fc(file, s, o.seed, o.newton_iterations,
                                                    {.count = o.repeat, .time_budget = 0.1});
  std::cout << fmt::format(
      "{}\n  dimension   {}\n  contacts    {}\n  local       {}\n  order       {}{}\n"
      "  iterations  {}{}{}\n  residual    {:.3e}\n  time        {:.9f} s\n{}",
      file, r.dimension, r.contacts, o.local, o.order,
      r.reordered_at < 0 ? ""
                         : fmt::format(", shuffled from sweep {} (stagnating)", r.reordered_at + 1),
      r.iterations,
      r.enumerated ? std::string(" (solved by enumerating the contacts' states)")
      : r.newton_iterations == 0
          ? ""
          : fmt::format(" NLGS sweeps{}, then {} Newton steps{}",
                        r.stagnated ? " (stagnating)" : "", r.newton_iterations,
                        r.newton_restarted ? " (from zero, then from the NLGS's)" : ""),
      r.converged ? "" : fmt::format(" (not converged to {:g})", o.tolerance), r.residual,
      r.seconds,
      r.repeats < 2 ? ""
                    : fmt::format("  warm time   {:.9f} s (median of {} more solves)\n",
                                  r.warm_seconds, r.repeats - 1));
  if (!o.reactions.empty()) {
    // The solution as text, one contact a line, exact to the bit (%.17g): for an independent
    // check of the residual (bench/peers/siconos/).
    std::string text;
    for (std::size_t k = 0; k < r.reactions.size(); ++k)
      text += fmt::format("{:.17g}{}", r.reactions[k],
                          (k + 1) % static_cast<std::size_t>(r.dimension) == 0 ? "\n" : " ");
    sable::write_text_atomic(o.reactions, text);
  }
  if (!std::isfinite(r.residual)) {
    std::cerr << fmt::format("error: {}: the residual is {}: the problem's data is not finite\n",
                             file, r.residual);
    return kExitFailed;
  }
  if (!r.converged) {
    std::cerr << fmt::format(
        "error: {}: not converged: residual {:.3e} above --tolerance {:g} after {} iterations "
        "(raise --max-iterations, or try --local exact or another --order)\n",
        file, r.residual, o.tolerance, r.iterations);
    return kExitFailed;
  }
  return 0;
}

// The --only help, from the table run_analysis checks names against: a help written out by
// hand once omitted an analysis added later.
std::string analyses_help() {
  std::string s = "analyses to run, comma-separated:";
  for (const char* a : sable::kAnalyses) s += std::string(" ") + a;
  return s + " (default: all; drag with --drag-wall, load-share with --level)";
}

// `sable analyze`: options straight into AnalyzeOptions (validated by run_analysis).
CLI::App* add_analyze(CLI::App& app, sable::AnalyzeOptions& a) {
  auto* an = app.add_subcommand("analyze", "micromechanical analysis of snapshots (.h5)");
  an->add_option("SNAPSHOTS", a.snapshots, "one snapshot, or several to average")->required();
  an->add_option("--out", a.out_dir, "output directory (default: analysis/ beside the input)");
  an->add_option("--only", a.only, analyses_help())->delimiter(',');
  an->add_option("--region", a.region, "box lo:hi, e.g. 0,0,0.01:0.1,0.1,0.05 (default: grains)");
  an->add_option("--solid-fraction", a.solid_fraction,
                 "nu for the free volumes (default: measured)");
  an->add_option("--bins", a.bins, "histogram bins (default 50)");
  an->add_option("--reference-force", a.reference_force, "f0 normalising the PDFs (default <f>)");
  an->add_option("--eps", a.eps, "polarization: on the cone if |ft| >= (1 - eps) mu fn (0.01)");
  an->add_option("--walls", a.walls, "walls to profile (default: all)")->delimiter(',');
  an->add_option("--wall-bin", a.wall_bin, "wall-profile bin height in m (default: 2 diameters)");
  an->add_option("--grid", a.grid, "field grid node counts, e.g. 10x10x40");
  an->add_option("--spacing", a.spacing, "field grid spacing in m (default: the kernel width)");
  an->add_option("--line", a.line, "fields along a segment from:to:points, e.g. 0,0,0:0,0,1:50");
  an->add_option("--kernel", a.kernel, "sphere | gaussian | lucy (default sphere)");
  an->add_option("--vtk-format", a.vtk_format,
                 "fields.vti: binary (raw, default) | zlib (compressed) | ascii");
  an->add_option("--width", a.width, "kernel radius/width in m (default: 2 mean diameters)");
  an->add_option("--frame", a.frame, "rotating frame px,py,pz:ux,uy,uz (point and axis)");
  an->add_option("--omega", a.omega,
                 "angular velocity of the rotating frame, and the turning wall's for drag "
                 "(rad/s)");
  an->add_option("--series", a.series,
                 "drag: the run's series.csv (default: beside the snapshots/ folder)");
  an->add_option("--drag-wall", a.drag_wall, "drag: the turning wall (runs drag with no --only)");
  an->add_option("--drag-axis", a.drag_axis,
                 "drag: the turning axis ux,uy,uz (default: --frame's axis, else 0,0,1)");
  an->add_option("--drag-length", a.drag_length,
                 "drag: the body's length L in F = 4 M / L (m; default 0: torque only)");
  an->add_option("--turn-start", a.turn_start,
                 "drag: the time the wall began to turn (s; default: the series' first time)");
  an->add_option("--stationary-from", a.stationary_from,
                 "drag: the stationary window starts this many turns in (default 1)");
  an->add_option("--level", a.level,
                 "load-share: height of the cut along -gravity (m; runs it with no --only)");
  an->add_flag("--plot", a.plot, "draw PNG figures next to the tables (python3-matplotlib)");
  return an;
}

int cmd_analyze(sable::AnalyzeOptions a) {
  a.log = &std::cerr;
  if (a.plot_script.empty()) {
    const char* env = std::getenv("SABLE_PLOT_SCRIPT");
    a.plot_script = env ? env : SABLE_SOURCE_DIR "/scripts/plot_analysis.py";
  }
  const std::string dir = sable::run_analysis(a, sable::snapshot_loaders());
  std::cerr << "analysis written to " << dir << "\n";
  return 0;
}

std::string version_text() {
  unsigned maj = 0, min = 0, rel = 0;
  H5get_libversion(&maj, &min, &rel);
  return fmt::format("sable {} ({} build, {} {}, HDF5 {}.{}.{})", SABLE_VERSION, SABLE_BUILD_TYPE,
#if defined(__clang__)
                     "clang", __clang_version__,
#else
                     "GCC", __VERSION__,
#endif
                     maj, min, rel);
}

// Checks of numeric options, said in words: CLI11's PositiveNumber and NonNegativeNumber print
// their range as a 309-digit number.
std::string clipped(const std::string& text) {
  return text.size() > 40 ? text.substr(0, 40) + "..." : text;
}

CLI::Validator integer_in(long lo, long hi, const std::string& what) {
  return CLI::Validator(
      [=](const std::string& text) -> std::string {
        long n = 0;
        const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), n);
        if (ec != std::errc() || end != text.data() + text.size() || n < lo || n > hi)
          return fmt::format("'{}': expected {} from {} to {}", clipped(text), what, lo, hi);
        return {};
      },
      fmt::format("{}-{}", lo, hi));
}

CLI::Validator non_negative(const std::string& what) {
  return CLI::Validator(
      [=](const std::string& text) -> std::string {
        double x = 0.0;
        const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), x);
        if (ec != std::errc() || end != text.data() + text.size() || !(x >= 0.0) ||
            !std::isfinite(x))
          return fmt::format("'{}': expected {}, a finite number >= 0", clipped(text), what);
        return {};
      },
      ">= 0");
}

}  // namespace

// Runs the command, turning an error into its message and exit status. Under MPI a process's
// error ends every process (the others would wait for it at their next exchange).
template <class F>
int guarded(const Launch& launch, F&& command) {
  std::string text;
  int code = 0;
  try {
    return command();
  } catch (const sable::InputError& e) {
    text = fmt::format("error: {}", e.what());
    code = kExitInput;
  } catch (const sable::SimulationError& e) {
    text = fmt::format("simulation failed: {}", e.what());
    code = kExitFailed;
  } catch (const sable::IoError& e) {
    text = fmt::format("error: cannot write output: {}", e.what());
    code = kExitIo;
  } catch (const std::bad_alloc&) {
    text = "error: out of memory";
    code = kExitFailed;
  } catch (const std::exception& e) {
    text = fmt::format("error: {}", e.what());
    code = kExitInput;
  }
  std::cerr << launch.prefix() << text << '\n' << std::flush;
  if (launch.size() > 1) launch.abort(code);
  return code;
}

int main(int argc, char** argv) {
  Launch launch(argc, argv);
  CLI::App app{"Sable: grain-scale simulation of granular media (DEM and contact dynamics)"};
  app.set_version_flag("--version", version_text());
  app.require_subcommand(1);
  std::string file;
  sable::RunOptions opt;

  auto* run = app.add_subcommand("run", "run a scenario (TOML)");
  run->add_option("FILE", file, "scenario file")->required()->check(CLI::ExistingFile);
  run->add_option("--out", opt.out_dir, "output directory (default: [output].dir)");
  run->add_option("--threads", opt.threads, "OpenMP threads")
      ->check(integer_in(1, 4096, "a number of threads"));
  run->add_option("--resume", opt.resume, "resume from this snapshot (.h5)")
      ->check(CLI::ExistingFile);
  run->add_flag("--overwrite", opt.overwrite,
                "delete the output folder's outputs of another run (fresh run), or those after "
                "the resumed step (resume), instead of refusing");
  run->add_flag("--accept-changes", opt.accept_changes,
                "resume although the scenario's physics differs from the snapshot's");
  auto* check = app.add_subcommand("check", "validate a scenario and generate its grains, no run");
  check->add_option("FILE", file, "scenario file")->required();
  auto* info = app.add_subcommand("info", "describe a snapshot");
  info->add_option("SNAPSHOT", file, "snapshot file (.h5)")->required();
  sable::AnalyzeOptions analyze_opt;
  auto* analyze = add_analyze(app, analyze_opt);
  auto* models = app.add_subcommand("models", "list the contact sub-models");
  Fc3dOptions fc3d_opt;
  auto* fc3d = app.add_subcommand(
      "fc3d", "solve a frictional-contact problem, 2D or 3D (Siconos .dat, FCLIB .hdf5)");
  fc3d->add_option("FILE", file, "problem file (.dat or FCLIB HDF5)")->required();
  fc3d->add_option("--local", fc3d_opt.local, "local solver (default: exact)")
      ->check(CLI::IsMember({"bipotential", "exact"}));
  fc3d->add_option("--tolerance", fc3d_opt.tolerance, "natural-map residual to reach")
      ->check(non_negative("a residual"));
  fc3d->add_option("--max-iterations", fc3d_opt.max_iterations, "NLGS sweeps at most")
      ->check(integer_in(1, 1L << 30, "a number of sweeps"));
  fc3d->add_option("--order", fc3d_opt.order, "sweep order")
      ->check(CLI::IsMember({"forward", "alternating", "shuffled"}));
  fc3d->add_option("--relaxation", fc3d_opt.relaxation, "relaxation w, 0 < w < 2");
  fc3d->add_option("--seed", fc3d_opt.seed, "random seed of the shuffled order");
  fc3d->add_option("--stagnation-window", fc3d_opt.stagnation_window,
                   "sweeps without the residual halving before the order turns shuffled (0: "
                   "never)")
      ->check(CLI::NonNegativeNumber);
  fc3d->add_option("--repeat", fc3d_opt.repeat,
                   "solve N times from zero (the same bits); report the first solve's time and "
                   "the median of the others (further solves only within 0.1 s in all)")
      ->check(CLI::Range(1, 1000));
  fc3d->add_option("--reactions", fc3d_opt.reactions,
                   "write the solution to this file (text, d values a contact)");
  fc3d->add_option("--newton-iterations", fc3d_opt.newton_iterations,
                   "semismooth Newton steps at most where the NLGS stops short (0: none)")
      ->check(CLI::NonNegativeNumber);

  // CLI11 quotes the value it refuses: clipped like every other quote of an input.
  app.failure_message([](const CLI::App*, const CLI::Error& e) {
    return sable::clip(e.what(), 2 * sable::kQuoteLimit) +
           "\nRun with --help for more information.\n";
  });
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : kExitInput;
  }
  return guarded(launch, [&] {
    if (*run) return cmd_run(file, opt, launch);
    if (*check) return cmd_check(file);
    if (*info) return cmd_info(file);
    if (*analyze) return cmd_analyze(analyze_opt);
    if (*models) return cmd_models();
    if (*fc3d) return cmd_fc3d(file, fc3d_opt);
    return 0;
  });
}
