#include "sable/scenario/runner.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <omp.h>
#include <unistd.h>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "sable/core/error.hpp"
#include "sable/io/csv.hpp"
#include "sable/io/snapshot.hpp"
#include "sable/io/vtk.hpp"
#include "sable/io/xdmf.hpp"
#include "sable/loading/box_state.hpp"
#include "sable/loading/servo.hpp"
#include "sable/scenario/build.hpp"
#include "sable/scenario/output_folder.hpp"
#include "sable/scenario/progress.hpp"
#include "sable/scenario/resume_changes.hpp"
#include "sable/scenario/simulation.hpp"
#include "sable/world/liquid.hpp"

namespace sable {
namespace {

namespace fs = std::filesystem;

// The box the scenario builds (its walls before any step): the strain reference of
// series.csv and the stage lines, the same whether the run started here or resumed.
template <int D>
std::optional<BoxState<D>> scenario_box(const ScenarioConfig& cfg) {
  World<D> w;
  build_model(cfg, w);
  return measure_box(w);
}

// "; box: sigma = (..) Pa, strain = (..), solid fraction .." for the stage lines; empty if none.
template <int D>
std::string box_text(const World<D>& w, const std::optional<BoxState<D>>& ref) {
  const auto b = measure_box(w);
  if (!b || !ref) return {};
  const auto eps = box_strain(*b, *ref);
  return fmt::format(
      "; box: sigma = ({:.4g}) Pa, strain = ({:.4g}) (compression positive, since the run's "
      "start), solid fraction {:.4f}",
      fmt::join(b->stress.data(), b->stress.data() + D, ", "),
      fmt::join(eps.data(), eps.data() + D, ", "), b->solid_fraction);
}

// The contacts carrying a force: grain pairs and grain-wall pairs, as the lists hold them.
struct TouchingContacts {
  std::size_t pairs = 0, walls = 0;
  std::size_t total() const { return pairs + walls; }
  // Contacts per grain, a wall contact counted once.
  double coordination(double grains) const {
    return (2.0 * static_cast<double>(pairs) + static_cast<double>(walls)) / grains;
  }
};

template <int D>
TouchingContacts touching_contacts(const World<D>& w) {
  TouchingContacts t;
  for (const auto& f : w.neighbors.pairs.force) t.pairs += f.squaredNorm() > 0.0 ? 1 : 0;
  for (const auto& f : w.neighbors.wall_pairs.force) t.walls += f.squaredNorm() > 0.0 ? 1 : 0;
  return t;
}

}  // namespace

template <int D>
Simulation<D>::Simulation(ScenarioConfig cfg, const RunOptions& opt)
    : cfg_(std::move(cfg)),
      opt_(opt),
      out_(opt.out_dir.empty() ? cfg_.output.dir : opt.out_dir),
      domain_(opt.domains ? opt.domains->make<D>() : std::make_unique<Domain<D>>()),
      // Under MPI process 0 alone logs, one line per report (the others' clocks would disagree
      // on when a live line is due).
      progress_(root() ? *opt.log : quiet_,
                !domain_->distributed() && opt.live_progress.value_or(isatty(STDERR_FILENO) == 1),
                cfg_.output.log_interval),
      solver_(make_solver(cfg_, world_, domain_.get())),
      box_ref_(scenario_box<D>(cfg_)) {}

template <int D>
Simulation<D>::~Simulation() = default;

template <int D>
void Simulation<D>::save(const std::string& path) const {
  save(path, fs::path(path).replace_extension(".xmf"));
}

// The sidecar after its snapshot: a crash between the two leaves a snapshot without one
// (harmless), never a sidecar naming a missing or older file. It names the snapshot by its
// path relative to the sidecar's folder.
template <int D>
void Simulation<D>::save(const fs::path& path, const fs::path& sidecar) const {
  std::error_code ec;
  const fs::path scenario = fs::absolute(cfg_.path, ec);
  const std::string scenario_path = ec ? std::string() : scenario.string();
  std::size_t grains = 0;
  if (SnapshotPart<D> part; domain_->snapshot_part(world_, path.string(), part)) {
    // A decomposed run: the processes write their rows of one file together; process 0
    // seals it (the state hash) once every one has written.
    save_snapshot_part(part, pos_, cfg_.text, path.string(), scenario_path);
    domain_->barrier();
    if (!root()) return;
    seal_snapshot(part.temp_path, path.string(), world_);
    grains = part.grains;
  } else {
    save_snapshot(world_, pos_, cfg_.text, path.string(), scenario_path);
    grains = world_.particles.size();
  }
  const fs::path folder = sidecar.parent_path().empty() ? fs::path(".") : sidecar.parent_path();
  const fs::path relative = fs::relative(path, folder, ec);
  write_xdmf({(ec || relative.empty() ? fs::absolute(path) : relative).generic_string(), D, grains,
              world_.time},
             sidecar.string());
}

template <int D>
void Simulation<D>::setup() {
  for (const auto& w : cfg_.warnings) progress_.message("warning: " + w);
  build_model(cfg_, world_);
  if (opt_.resume.empty()) {
    build_grains(cfg_, world_);
  } else {
    std::string text;
    pos_ = load_snapshot(opt_.resume, world_, &text);
    if (pos_.stage >= cfg_.stages.size())
      throw InputError(fmt::format("{}: snapshot is at stage {} but {} has only {} stages",
                                   opt_.resume, pos_.stage + 1, cfg_.path, cfg_.stages.size()));
    if (text != cfg_.text) check_changes(text);
    adopt_scenario_steps();
  }
  const auto dt_warning = check_time_step(cfg_, world_);
  // Under MPI each process keeps its share of the whole world it built or loaded; a rebuild
  // the resume asked for (adopt_scenario_steps) stays asked for.
  const bool rebuild = world_.neighbors.x_ref.empty();
  if (domain_->distributed() && !world_.shapes.empty())
    throw InputError(fmt::format(
        "{}: polyhedral grains run on one process (the processes would need the shape table); "
        "run without mpirun, with --threads",
        cfg_.path));
  domain_->scatter(world_);
  if (rebuild) world_.neighbors.x_ref.clear();
  if (opt_.resume.empty()) {
    solver_->initialize();  // its forces' largest overlap: the first row of series.csv
    max_overlap_ = solver_->diagnostics().max_overlap_ratio;
    domain_->max(&max_overlap_, 1);
  }
  if (dt_warning) progress_.message("warning: " + *dt_warning);
  if (opt_.write_outputs) open_outputs(!opt_.resume.empty());
}

// A resume under another scenario text: [output] and [[stage]] may differ; any other change
// is refused unless accepted, and then reported key by key (scenario/resume_changes.hpp).
template <int D>
void Simulation<D>::check_changes(const std::string& snapshot_text) {
  const auto changes =
      scenario_changes(snapshot_text, opt_.resume + " (its scenario)", cfg_.text, cfg_.path);
  if (changes.empty()) {
    progress_.message(fmt::format(
        "{} was written by another version of {}: only [output] and [[stage]] differ; resuming "
        "with the new stages and outputs",
        opt_.resume, cfg_.path));
    return;
  }
  if (!opt_.accept_changes)
    throw InputError(fmt::format(
        "{} was written by a scenario whose physics differs from {}: {}; a resume continues the "
        "snapshot's state, and some of these cannot apply to it (docs/reliability.md, "
        "\"Resuming\"): give --accept-changes to resume anyway, each change reported",
        opt_.resume, cfg_.path, describe_changes(changes)));
  std::vector<ScenarioChange> applied, kept;
  for (const auto& c : changes) (c.kept_because.empty() ? applied : kept).push_back(c);
  if (!applied.empty())
    progress_.message("--accept-changes: applied: " + describe_changes(applied));
  for (const auto& c : kept)
    progress_.message(fmt::format("--accept-changes: not applied, {}: {} ({} -> {})",
                                  c.kept_because, c.key, c.before, c.after));
}

// A resumed run takes its time step and neighbour skin from the scenario, not the snapshot:
// another scenario may continue the state with another solver (a DEM packing relaxed by CD)
// or step. The same scenario gives the same values, so a plain resume stays bit-identical.
// The skin never shrinks below the snapshot's (capillary bridges may have raised it); a
// larger one forces a neighbour rebuild, since the lists only hold pairs within the old one.
template <int D>
void Simulation<D>::adopt_scenario_steps() {
  const double dt = scenario_time_step(cfg_, world_);
  if (dt != world_.dt) {
    progress_.message(fmt::format(
        "resuming with the scenario's dt = {:.6g} s (the snapshot's: {:.6g} s)", dt, world_.dt));
    world_.dt = dt;
  }
  const double skin = scenario_skin(cfg_, world_);
  if (skin > world_.neighbors.skin) {
    world_.neighbors.skin = skin;
    world_.neighbors.x_ref.clear();  // rebuild at the next step
  }
}

template <int D>
void Simulation<D>::open_outputs(bool resuming) {
  if (!root()) {
    if (!resuming) write_frame();  // collective: process 0 gathers the grains
    if (!resuming) write_csv_row();
    return;
  }
  OutputFolderRequest req{out_.string(), std::nullopt, opt_.resume, opt_.overwrite};
  if (resuming) req.resume_step = world_.step;
  prepare_output_folder(req, [this](const std::string& m) { progress_.message(m); });
  for (const char* sub : {"vtk", "snapshots", "xdmf"}) {
    std::error_code ec;
    fs::create_directories(out_ / sub, ec);
    if (ec)
      throw IoError(fmt::format("cannot create the output folder '{}': {}", (out_ / sub).string(),
                                ec.message()));
  }
  std::vector<std::string> cols{"step",
                                "time_s",
                                "kinetic_energy_J",
                                "touching_contacts",
                                "coordination",
                                "max_overlap_over_radius"};
  for (const auto& c : solver_->diagnostic_columns()) cols.push_back(c);
  // Each wall's force, then its torque about its pivot (2D: the force in the plane, the
  // torque about z).
  for (const auto& wall : world_.walls) {
    for (const char* ax : {"x", "y", "z"}) {
      if (D == 2 && ax[0] == 'z') continue;
      cols.push_back(fmt::format("wall_{}_f{}_N", wall.name, ax));
    }
    for (const char* ax : {"x", "y", "z"}) {
      if (D == 2 && ax[0] != 'z') continue;
      cols.push_back(fmt::format("wall_{}_t{}_Nm", wall.name, ax));
    }
  }
  // A box of plane walls (loading/box_state.hpp): its corners, mean wall stresses, strain
  // (compression positive, against the box the scenario builds) and solid fraction.
  if (box_ref_) {
    const char* ax[] = {"x", "y", "z"};
    for (int d = 0; d < D; ++d)
      for (const char* end : {"lo", "hi"}) cols.push_back(fmt::format("box_{}{}_m", ax[d], end));
    for (int d = 0; d < D; ++d) cols.push_back(fmt::format("sigma_{0}{0}_Pa", ax[d]));
    for (int d = 0; d < D; ++d) cols.push_back(fmt::format("strain_{0}{0}", ax[d]));
    cols.push_back("solid_fraction");
  }
  csv_.emplace((out_ / "series.csv").string(), cols,
               resuming ? std::optional<std::uint64_t>(world_.step) : std::nullopt);
  // A resumed series keeps its frames up to the resume point.
  std::vector<std::pair<std::optional<PvdSeries>*, const char*>> series{
      {&grains_pvd_, "grains.pvd"}, {&contacts_pvd_, "contacts.pvd"}, {&walls_pvd_, "walls.pvd"}};
  // The polyhedral grains' faces. The shape table is filled when the grains are built and a
  // snapshot keeps it: a run that has one here has it at every frame.
  if constexpr (D == 3) {
    if (!world_.shapes.empty()) series.emplace_back(&polyhedra_pvd_, "polyhedra.pvd");
  }
  for (auto [pvd, name] : series) {
    const std::string path = (out_ / name).string();
    if (resuming)
      pvd->emplace(path, world_.time);
    else
      pvd->emplace(path);
  }
  if (!resuming) {
    write_frame();
    write_csv_row();
  }
}

template <int D>
ProgressSample Simulation<D>::sample() const {
  const StageConfig& st = cfg_.stages[pos_.stage];
  const World<D>& w = whole();
  ProgressSample s;
  s.stage = st.name.empty() ? fmt::format("stage {}", pos_.stage + 1) : st.name;
  s.step = w.step;
  s.stage_step = pos_.stage_step;
  s.stage_total = st.steps ? *st.steps : st.max_steps;
  s.time = w.time;
  s.kinetic_energy = kinetic_energy(w);
  s.contacts =
      domain_->distributed() ? touching_contacts(w).total() : solver_->diagnostics().touching;
  s.grains = w.particles.size();
  return s;
}

template <int D>
void Simulation<D>::start_stage() {
  const StageConfig& st = cfg_.stages[pos_.stage];
  for (const auto& [name, vel] : st.wall_velocity)
    for (std::size_t k : walls_named(world_, name))
      world_.walls[k].velocity = Space<D>::from_array(vel);
  // A resume in the middle of a stage keeps the snapshot's motion: this runs at stage start only.
  for (const auto& [name, rot] : st.wall_rotation)
    for (auto& wall : world_.walls)
      if (wall.name == name)
        wall.set_rotation(Space<D>::from_array(rot.point), Space<D>::from_array(rot.axis),
                          rot.rate);

  progress_.message(fmt::format("stage {} '{}' begins at step {} (t = {:.6g} s, dt = {:.4g} s)",
                                pos_.stage + 1, st.name, world_.step, world_.time, world_.dt));
  if (st.water_content) wet();
}

// Distribute the stage's liquid, then recompute the forces (the step starts from them).
// Under MPI every process wets the whole sample, gathered, by the same bits, then keeps its
// share: the liquid's shares depend on every pair of the sample (world/liquid.hpp).
template <int D>
void Simulation<D>::wet() {
  const StageConfig& st = cfg_.stages[pos_.stage];
  const LiquidPairs pairs =
      st.liquid_at_contacts_only ? LiquidPairs::kContacts : LiquidPairs::kEligible;
  WettingResult r;
  if (domain_->distributed()) {
    World<D> all;
    domain_->gather_everywhere(world_, all);
    r = wet_grains(all, *st.water_content, st.liquid_density, pairs);
    world_ = std::move(all);
    domain_->scatter(world_);
  } else {
    r = wet_grains(world_, *st.water_content, st.liquid_density, pairs);
  }
  solver_->initialize();
  progress_.message(fmt::format(
      "wetted: water content {:.4g}, liquid volume {:.4g} m^3 in {} bridges ({} at contacts, "
      "debonding distance {:.4g} m, largest rupture distance {:.4g} m, skin {:.4g} m)",
      *st.water_content, r.volume, r.bridges, r.contacts, r.debonding_distance, r.max_rupture,
      world_.neighbors.skin));
}

// The stage's stress-controlled walls; also when resuming in the middle of a stage. A solver
// that moves them as bodies (contact dynamics) drops the last stage's here.
template <int D>
void Simulation<D>::load_servo_targets() {
  servo_.clear();
  for (const auto& [name, stress] : cfg_.stages[pos_.stage].wall_stress)
    for (std::size_t k : walls_named(world_, name)) {
      wall_area(world_, k);  // checks the wall can be stress-controlled (InputError if not)
      servo_.push_back({k, stress});
    }
  if (solver_->moves_wall_bodies()) solver_->set_wall_bodies({});
}

template <int D>
bool Simulation<D>::stage_done() {
  const StageConfig& st = cfg_.stages[pos_.stage];
  if (st.steps) return pos_.stage_step >= *st.steps;
  // Never at the stage's first step: grains placed at rest would end a settling stage at once.
  if (pos_.stage_step > 0 && pos_.stage_step % st.check_interval == 0 &&
      kinetic_energy(world_, *domain_, st.translation_only) < *st.kinetic_energy_below &&
      (!st.stress_tolerance ||
       servo_error(world_, servo_, st.stress_scale) <= *st.stress_tolerance))
    return true;
  if (pos_.stage_step >= st.max_steps) {
    progress_.message(fmt::format(
        "warning: stage '{}' reached max_steps = {} before equilibrium: kinetic energy {:.4g} J "
        "(kinetic_energy_below = {:.4g} J){}{}",
        st.name, st.max_steps, kinetic_energy(world_, *domain_, st.translation_only),
        *st.kinetic_energy_below,
        st.stress_tolerance
            ? fmt::format(", wall stress error {:.3g} (stress_tolerance = {:.3g})",
                          servo_error(world_, servo_, st.stress_scale), *st.stress_tolerance)
            : std::string(),
        box_text(whole(), box_ref_)));
    return true;
  }
  return false;
}

template <int D>
void Simulation<D>::after_step() {
  const auto step = world_.step;
  const auto& o = cfg_.output;
  const auto& diag = solver_->diagnostics();
  if (!warned_overlap_ && max_overlap_ > world_.overlap_warning) {
    warned_overlap_ = true;
    progress_.message(fmt::format(
        "warning: step {}: an overlap reached {:.3g} of the grain radius (overlap_warning = "
        "{:.3g}); the grains may be too soft or the time step too large",
        step, max_overlap_, world_.overlap_warning));
  }
  if (!warned_unconverged_ && !diag.converged) {
    warned_unconverged_ = true;
    progress_.message(
        fmt::format("warning: step {}: the contact solver stopped unconverged after {} iterations "
                    "(residual {:.3g}); raise cd.max_iterations or loosen cd.tolerance",
                    step, diag.iterations, diag.residual));
  }
  if (progress_.due(step)) progress_.report(sample());
  if (!opt_.write_outputs) return;
  if (o.csv_interval > 0 && step % o.csv_interval == 0) write_csv_row();
  if (o.vtk_interval > 0 && step % o.vtk_interval == 0) write_frame();
  if (o.snapshot_interval > 0 && step % o.snapshot_interval == 0)
    write_snapshot(fmt::format("step_{:010d}.h5", step));
}

template <int D>
void Simulation<D>::write_frame() {
  const World<D>& w = whole();
  if (!root()) return;
  const std::string stem = fmt::format("{:010d}.vtp", w.step);
  const VtkEncoding format = cfg_.output.vtk_format;
  write_grains_vtp(w, (out_ / "vtk" / ("grains_" + stem)).string(), format);
  grains_pvd_->add(w.time, "vtk/grains_" + stem);
  if (cfg_.output.vtk_contacts) {
    write_contacts_vtp(w, (out_ / "vtk" / ("contacts_" + stem)).string(), format);
    contacts_pvd_->add(w.time, "vtk/contacts_" + stem);
  }
  if (cfg_.output.vtk_walls && !w.walls.empty()) {
    write_walls_vtp(w, (out_ / "vtk" / ("walls_" + stem)).string(), format);
    walls_pvd_->add(w.time, "vtk/walls_" + stem);
  }
  if constexpr (D == 3) {
    if (polyhedra_pvd_) {
      write_polyhedra_vtp(w, (out_ / "vtk" / ("polyhedra_" + stem)).string(), format);
      polyhedra_pvd_->add(w.time, "vtk/polyhedra_" + stem);
    }
  }
}

template <int D>
void Simulation<D>::write_snapshot(const std::string& file) {
  save(out_ / "snapshots" / file, out_ / "xdmf" / fs::path(file).replace_extension(".xmf"));
}

template <int D>
void Simulation<D>::write_csv_row() {
  const World<D>& w = whole();
  if (!root()) return;
  const TouchingContacts touching = touching_contacts(w);
  const double n = static_cast<double>(std::max<std::size_t>(w.particles.size(), 1));
  std::vector<double> row{static_cast<double>(w.step), w.time,
                          kinetic_energy(w),           static_cast<double>(touching.total()),
                          touching.coordination(n),    max_overlap_};
  solver_->diagnostic_values(row);
  for (const auto& wall : w.walls) {
    for (int d = 0; d < D; ++d) row.push_back(wall.force[d]);
    if constexpr (D == 3)
      row.insert(row.end(), {wall.torque.x(), wall.torque.y(), wall.torque.z()});
    else
      row.push_back(wall.torque);
  }
  if (box_ref_) {
    const auto b = measure_box(w);  // same walls as the reference: a box too
    const auto eps = box_strain(*b, *box_ref_);
    for (int d = 0; d < D; ++d) row.insert(row.end(), {b->lo[d], b->hi[d]});
    for (int d = 0; d < D; ++d) row.push_back(b->stress[d]);
    for (int d = 0; d < D; ++d) row.push_back(eps[d]);
    row.push_back(b->solid_fraction);
  }
  csv_->row(row);
}

template <int D>
std::string Simulation<D>::stage_summary(const StageClock& c) const {
  const double secs =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - c.start).count();
  const World<D>& w = whole();
  const auto steps = w.step - c.step;
  const double grain_steps = static_cast<double>(steps) * static_cast<double>(w.particles.size());
  std::string phases;
  double total = 0.0;
  for (int k = 0; k < static_cast<int>(Phase::kCount); ++k)
    total += solver_->timers().seconds(static_cast<Phase>(k)) - c.phase_seconds[k];
  for (int k = 0; k < static_cast<int>(Phase::kCount); ++k) {
    const double t = solver_->timers().seconds(static_cast<Phase>(k)) - c.phase_seconds[k];
    if (t == 0.0) continue;
    phases += fmt::format("{}{} {:.3g} s ({:.0f}%)", k ? ", " : "", kPhaseNames[k], t,
                          total > 0 ? 100.0 * t / total : 0.0);
  }
  const std::uint64_t remakes = solver_->diagnostics().near_remakes;
  return fmt::format(
      "stage '{}' done: {} steps in {:.2f} s, {:.4g} grain-steps/s ({}); {} neighbour builds{} "
      "so far{}",
      cfg_.stages[pos_.stage].name, steps, secs, secs > 0 ? grain_steps / secs : 0.0, phases,
      w.neighbors.builds, remakes > 0 ? fmt::format(" and {} near-list remakes", remakes) : "",
      box_text(w, box_ref_));
}

template <int D>
void Simulation<D>::start() {
  if (started_) return;
  started_ = true;
  t0_ = std::chrono::steady_clock::now();
  setup();
}

template <int D>
void Simulation<D>::enter_stage() {
  if (pos_.stage_step == 0) start_stage();
  load_servo_targets();
  world_.viscous_rate = cfg_.stages[pos_.stage].viscous_damping;
  servo_max_velocity_ = 0.0;
  stage_clock_.emplace(world_.step, solver_->timers());
}

template <int D>
void Simulation<D>::leave_stage() {
  progress_.report(sample());
  progress_.message(stage_summary(*stage_clock_));
  if (opt_.write_outputs) {
    write_frame();
    write_snapshot(fmt::format("end_of_stage_{}.h5", pos_.stage + 1));
  }
  stage_clock_.reset();
  ++pos_.stage;
  pos_.stage_step = 0;
}

// The step itself: the stress-controlled walls loaded (loading/servo.hpp: the DEM servo, or
// CD wall bodies), the solver's step, then the outputs due.
template <int D>
void Simulation<D>::one_step() {
  if (!servo_.empty()) {
    const StageConfig& st = cfg_.stages[pos_.stage];
    const ServoSettings s{st.servo_gain,
                          servo_max_velocity_ > 0.0 ? servo_max_velocity_ : st.servo_max_velocity,
                          st.stress_scale, st.servo_wall_mass};
    if (solver_->moves_wall_bodies())
      solver_->set_wall_bodies(wall_bodies(world_, servo_, s));
    else
      servo_walls(world_, servo_, s, domain_.get());
  }
  if (!domain_->distributed()) {
    solver_->step();
    max_overlap_ = solver_->diagnostics().max_overlap_ratio;
  } else {
    try {
      solver_->step();
    } catch (const SimulationError& e) {
      agree_after_step(&e);
    }
    agree_after_step(nullptr);
  }
  ++pos_.stage_step;
  after_step();
}

// Under MPI, after each step: the largest overlap, whether a process's grain failed (the
// step ends with its check, after the step's last exchange, so every process gets here) and
// whether a process caught a stop signal, agreed by all; a failure throws on every process
// (the one that saw it says which grain, on its own error output).
template <int D>
void Simulation<D>::agree_after_step(const SimulationError* failure) {
  double m[3] = {solver_->diagnostics().max_overlap_ratio, failure ? 1.0 : 0.0,
                 opt_.stop ? static_cast<double>(*opt_.stop) : 0.0};
  domain_->max(m, 3);
  max_overlap_ = m[0];
  stop_signal_ = static_cast<int>(m[2]);
  if (m[1] == 0.0) return;
  if (failure && !root())
    std::cerr << fmt::format("process {}: {}\n", domain_->rank(), failure->what());
  if (failure && root()) throw *failure;
  throw SimulationError(
      fmt::format("step {}: a grain's state became unsound on {}", world_.step,
                  failure ? fmt::format("process {} (its message above)", domain_->rank())
                          : std::string("another process (its message above)")));
}

template <int D>
bool Simulation<D>::stop_requested() const {
  if (domain_->distributed()) return stop_signal_ != 0;
  return opt_.stop && *opt_.stop != 0;
}

template <int D>
const World<D>& Simulation<D>::whole() const {
  if (!domain_->distributed()) return world_;
  domain_->gather(world_, whole_);
  return whole_;
}

template <int D>
bool Simulation<D>::advance() {
  start();
  try {
    while (!finished()) {
      if (!stage_clock_) enter_stage();
      if (!stage_done()) {
        one_step();
        return true;
      }
      leave_stage();
    }
  } catch (const SimulationError& e) {
    progress_.finish_line();
    if (!opt_.write_outputs) throw;
    throw crashed(e);
  }
  return false;
}

template <int D>
void Simulation<D>::finish_ended_stage() {
  if (!started_ || finished()) return;
  if (!stage_clock_) enter_stage();
  if (stage_done()) leave_stage();
}

template <int D>
RunResult Simulation<D>::run() {
  start();
  while (advance())
    if (stop_requested()) return interrupted();
  return result();
}

// The state of the step that failed, written for a look (crash_step_N.h5), and the error
// that says where.
template <int D>
SimulationError Simulation<D>::crashed(const SimulationError& e) {
  const std::string file = fmt::format("crash_step_{:010d}.h5", world_.step);
  write_snapshot(file);
  return SimulationError(
      fmt::format("{}\nstate written to {}", e.what(), (out_ / "snapshots" / file).string()));
}

template <int D>
RunResult Simulation<D>::result() const {
  const World<D>& w = whole();
  RunResult r;
  r.steps = w.step;
  r.time = w.time;
  r.state_hash = state_hash(w);
  r.grains = w.particles.size();
  r.kinetic_energy = kinetic_energy(w);
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
  return r;
}

// A signal asked the run to stop: the step is complete, so the state is consistent; it is
// written like any snapshot (atomically), and a resume from it continues bit for bit.
template <int D>
RunResult Simulation<D>::interrupted() {
  progress_.finish_line();
  RunResult r = result();
  r.interrupted_by = domain_->distributed() ? stop_signal_ : static_cast<int>(*opt_.stop);
  if (opt_.write_outputs) {
    const std::string file = fmt::format("interrupted_step_{:010d}.h5", world_.step);
    write_snapshot(file);
    r.last_snapshot = (out_ / "snapshots" / file).string();
  }
  return r;
}

// The current stage entered first (its own settings applied), so that the change is not
// replaced by them at the next step.
template <int D>
std::vector<std::size_t> Simulation<D>::named_walls(const std::string& name) {
  start();
  if (!finished() && !stage_clock_) enter_stage();
  auto walls = walls_named(world_, name);
  if (walls.empty()) {
    std::string known;
    for (const auto& w : world_.walls) known += (known.empty() ? "" : ", ") + w.name;
    throw InputError(fmt::format("no wall named '{}' (walls: {})", clip(name), known));
  }
  return walls;
}

template <int D>
void Simulation<D>::set_wall_velocity(const std::string& name, const typename Space<D>::Vec& v) {
  for (std::size_t k : named_walls(name)) world_.walls[k].velocity = v;
}

template <int D>
void Simulation<D>::set_wall_rotation(const std::string& name, const typename Space<D>::Vec& point,
                                      const typename Space<D>::Vec& axis, double rate) {
  for (std::size_t k : named_walls(name)) world_.walls[k].set_rotation(point, axis, rate);
}

template <int D>
void Simulation<D>::set_wall_stress(const std::string& name, double stress, double max_velocity) {
  const auto walls = named_walls(name);
  if (finished()) throw InputError("set_wall_stress: every stage has ended");
  if (!(std::isfinite(stress) && std::isfinite(max_velocity) && max_velocity >= 0.0))
    throw InputError(
        fmt::format("set_wall_stress: stress {} Pa and max_velocity {} m/s: "
                    "expected numbers, max_velocity >= 0",
                    stress, max_velocity));
  if (max_velocity > 0.0) servo_max_velocity_ = max_velocity;
  if (servo_max_velocity_ <= 0.0 && cfg_.stages[pos_.stage].servo_max_velocity <= 0.0)
    throw InputError(fmt::format(
        "set_wall_stress: stage '{}' has no servo_max_velocity; give max_velocity (m/s)",
        cfg_.stages[pos_.stage].name));
  for (std::size_t k : walls) {
    wall_area(world_, k);  // checks the wall can be stress-controlled (InputError if not)
    auto it = std::find_if(servo_.begin(), servo_.end(),
                           [k](const ServoTarget& t) { return t.wall == k; });
    if (it == servo_.end())
      servo_.push_back({k, stress});
    else
      it->stress = stress;
  }
}

template class Simulation<2>;
template class Simulation<3>;

namespace {

template <int D>
std::string describe(const ScenarioConfig& cfg) {
  World<D> w;
  build_model(cfg, w);
  build_grains(cfg, w);
  std::string warnings;
  for (const auto& m : cfg.warnings) warnings += "\nwarning: " + m;
  if (const auto m = check_time_step(cfg, w)) warnings += "\nwarning: " + *m;
  return fmt::format("{}: {}D, {} grains, {} walls, {} materials, {} stages, dt = {:.4g} s{}{}",
                     cfg.path, D, w.particles.size(), w.walls.size(), w.materials.size(),
                     cfg.stages.size(), w.dt, cfg.sim.dt ? "" : " (automatic)", warnings);
}

}  // namespace

RunResult run_scenario(const ScenarioConfig& cfg, const RunOptions& opt) {
  if (opt.threads > 0) omp_set_num_threads(opt.threads);
  if (cfg.sim.dimension == 2) return Simulation<2>(cfg, opt).run();
  return Simulation<3>(cfg, opt).run();
}

std::string describe_scenario(const ScenarioConfig& cfg) {
  return cfg.sim.dimension == 2 ? describe<2>(cfg) : describe<3>(cfg);
}

}  // namespace sable
