// The Python module `sable._sable` (pybind11): scenarios, simulations stepped from Python,
// numpy views of the grains, contacts and walls as arrays, snapshots. python/sable/__init__.py
// re-exports it; docs/python.md is the tutorial.
//
// The module drives scenario/simulation.hpp, the object `sable run` drives, so a run from
// Python and the CLI give the same bits. The GIL is released while the simulation steps, a
// chunk of at most kChunkSeconds at a time; between chunks Python's signal handlers run, so
// Ctrl-C raises KeyboardInterrupt with the simulation at the end of a complete step (it can
// go on, or be saved).
#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <omp.h>

#include <chrono>
#include <memory>
#include <optional>
#include <ostream>
#include <streambuf>
#include <string>
#include <variant>

#include "sable/analysis/analyze.hpp"
#include "sable/core/error.hpp"
#include "sable/io/snapshot.hpp"
#include "sable/scenario/config.hpp"
#include "sable/scenario/simulation.hpp"
#include "sable/scenario/snapshot_sample.hpp"
#include "sable/world/state_hash.hpp"

namespace py = pybind11;

namespace {

using sable::Simulation;
using sable::World;

// Between two looks at Python's signals: short enough that Ctrl-C answers at once, long
// enough that the look costs nothing (a few microseconds a look).
constexpr double kChunkSeconds = 0.05;

// A stream that drops everything: quiet simulations.
class NullBuffer : public std::streambuf {
 protected:
  int overflow(int c) override { return c; }
};

// A read-only numpy view of `count` rows of `cols` doubles (cols 0: a 1D array) at `data`,
// kept alive by `owner` (the Python Simulation).
py::array view(const double* data, std::size_t count, std::size_t cols, const py::object& owner) {
  py::array a = cols == 0
                    ? py::array(py::dtype::of<double>(), {count}, {sizeof(double)}, data, owner)
                    : py::array(py::dtype::of<double>(), {count, cols},
                                {cols * sizeof(double), sizeof(double)}, data, owner);
  a.attr("setflags")(py::arg("write") = false);
  return a;
}

// The stable ids' indices: column 0 of the (index, generation) pairs, a read-only view.
py::array id_view(const std::vector<sable::ParticleId>& ids, const py::object& owner) {
  static_assert(sizeof(sable::ParticleId) == 2 * sizeof(std::uint32_t));
  py::array a(py::dtype::of<std::uint32_t>(), {ids.size()}, {sizeof(sable::ParticleId)},
              reinterpret_cast<const std::uint32_t*>(ids.data()), owner);
  a.attr("setflags")(py::arg("write") = false);
  return a;
}

template <class T>
py::array_t<T> copy_of(const std::vector<T>& v) {
  py::array_t<T> a(static_cast<py::ssize_t>(v.size()));
  std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}

// Rows of D (or 1) doubles from a vector of Eigen vectors (or doubles), copied.
template <class V>
py::array_t<double> rows_of(const std::vector<V>& v) {
  if constexpr (std::is_same_v<V, double>) {
    return copy_of(v);
  } else {
    const auto n = static_cast<py::ssize_t>(v.size());
    const auto cols = static_cast<py::ssize_t>(V::RowsAtCompileTime);
    py::array_t<double> a({n, cols});
    auto m = a.mutable_unchecked<2>();
    for (py::ssize_t k = 0; k < n; ++k)
      for (py::ssize_t c = 0; c < cols; ++c) m(k, c) = v[static_cast<std::size_t>(k)][c];
    return a;
  }
}

// The touching grain pairs: ids, centres' normal (from j to i), contact point (between the
// surfaces, where the overlap's middle is), normal force (positive in compression) and the
// force on i (vector); wall contacts: grain id, wall index, force on the grain.
template <int D>
py::dict contacts_of(const World<D>& w) {
  using Vec = typename sable::Space<D>::Vec;
  const auto& p = w.particles;
  const auto& pl = w.neighbors.pairs;
  std::vector<std::int64_t> id_i, id_j;
  std::vector<Vec> normal, point, force, tangential;
  std::vector<double> fn;
  for (std::size_t k = 0; k < pl.size(); ++k) {
    if (!(pl.force[k].array() != 0.0).any()) continue;
    const std::uint32_t i = pl.i[k], j = pl.j[k];
    const Vec d = p.x[i] - p.x[j];
    const double dist = d.norm();
    const Vec n = dist > 0.0 ? Vec(d / dist) : Vec(Vec::Zero());
    id_i.push_back(p.id[i].index);
    id_j.push_back(p.id[j].index);
    normal.push_back(n);
    // The middle of the overlap (of the gap, for a bridge at a distance) along the normal.
    point.push_back(p.x[j] + n * (0.5 * (dist + p.radius[j] - p.radius[i])));
    force.push_back(pl.force[k]);
    fn.push_back(pl.force[k].dot(n));
    tangential.push_back(pl.force[k] - fn.back() * n);
  }
  const auto& wl = w.neighbors.wall_pairs;
  std::vector<std::int64_t> wid;
  std::vector<std::uint32_t> wall;
  std::vector<Vec> wforce;
  for (std::size_t k = 0; k < wl.size(); ++k) {
    if (!(wl.force[k].array() != 0.0).any()) continue;
    wid.push_back(p.id[wl.i[k]].index);
    wall.push_back(wl.wall[k]);
    wforce.push_back(wl.force[k]);
  }
  py::dict out;
  out["id_i"] = copy_of(id_i);
  out["id_j"] = copy_of(id_j);
  out["normal"] = rows_of(normal);
  out["point"] = rows_of(point);
  out["normal_force"] = copy_of(fn);
  out["force"] = rows_of(force);
  out["tangential_force"] = rows_of(tangential);
  out["wall_grain_id"] = copy_of(wid);
  out["wall_index"] = copy_of(wall);
  out["wall_force"] = rows_of(wforce);
  return out;
}

template <int D>
py::dict walls_of(const World<D>& w) {
  using S = sable::Space<D>;
  std::vector<std::string> names;
  std::vector<typename S::Vec> point, velocity, force;
  std::vector<typename S::Rot> spin, torque;
  std::vector<double> orientation;  // 3D: a quaternion w, x, y, z per wall; 2D: an angle
  for (const auto& wall : w.walls) {
    if constexpr (D == 3)
      orientation.insert(orientation.end(), {wall.orientation.w(), wall.orientation.x(),
                                             wall.orientation.y(), wall.orientation.z()});
    else
      orientation.push_back(wall.orientation);
    names.push_back(wall.name);
    point.push_back(wall.point);
    velocity.push_back(wall.velocity);
    force.push_back(wall.force);
    spin.push_back(wall.spin);
    torque.push_back(wall.torque);
  }
  py::dict out;
  out["names"] = names;
  out["point"] = rows_of(point);
  out["velocity"] = rows_of(velocity);
  out["force"] = rows_of(force);
  out["spin"] = rows_of(spin);
  out["torque"] = rows_of(torque);
  py::array_t<double> q = copy_of(orientation);
  out["orientation"] = D == 3 ? py::array_t<double>(q.reshape(
                                    {static_cast<py::ssize_t>(w.walls.size()), py::ssize_t{4}}))
                              : q;
  return out;
}

py::dict result_dict(const sable::RunResult& r) {
  py::dict d;
  d["steps"] = r.steps;
  d["time"] = r.time;
  d["state_hash"] = r.state_hash;
  d["grains"] = r.grains;
  d["kinetic_energy"] = r.kinetic_energy;
  d["wall_seconds"] = r.wall_seconds;
  return d;
}

struct PyScenario {
  std::shared_ptr<const sable::ScenarioConfig> cfg;
};

class PySimulation {
 public:
  using Sim = std::variant<std::unique_ptr<Simulation<2>>, std::unique_ptr<Simulation<3>>>;

  PySimulation(const PyScenario& sc, const std::string& out_dir, int threads, bool outputs,
               bool overwrite, bool quiet, const std::string& resume, bool accept_changes)
      : null_(&null_buf_) {
    sable::RunOptions opt;
    opt.out_dir = out_dir;
    opt.threads = threads;
    opt.write_outputs = outputs;
    opt.overwrite = overwrite;
    opt.resume = resume;
    opt.accept_changes = accept_changes;
    opt.live_progress = false;
    opt.log = quiet ? &null_ : &std::cerr;
    if (threads > 0) omp_set_num_threads(threads);  // as `sable run --threads`
    if (sc.cfg->sim.dimension == 2)
      sim_ = std::make_unique<Simulation<2>>(*sc.cfg, opt);
    else
      sim_ = std::make_unique<Simulation<3>>(*sc.cfg, opt);
  }

  int dimension() const { return sim_.index() == 0 ? 2 : 3; }

  // f(simulation) for the simulation of either dimension.
  template <class F>
  decltype(auto) with(F&& f) {
    return std::visit([&](auto& s) -> decltype(auto) { return f(*s); }, sim_);
  }

  // Steps until `n` are taken (n < 0: no limit), the scenario ends, or `stop(simulation)`
  // after a step; the GIL released, Python's signals looked at between chunks. After the
  // last step a stage that has ended is left (its end outputs written). Returns the steps.
  template <class Stop>
  std::int64_t advance(std::int64_t n, Stop stop) {
    std::int64_t done = 0;
    bool more = true;
    while (more && (n < 0 || done < n)) {
      {
        py::gil_scoped_release release;
        const auto t0 = std::chrono::steady_clock::now();
        with([&](auto& s) {
          s.start();
          while (n < 0 || done < n) {
            if (!s.advance()) {
              more = false;
              return;
            }
            ++done;
            s.finish_ended_stage();
            if (stop(s)) {
              more = false;
              return;
            }
            if (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() >
                kChunkSeconds)
              return;
          }
        });
      }
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    }
    return done;
  }

 private:
  NullBuffer null_buf_;
  std::ostream null_;
  Sim sim_;
};

// The per-grain arrays as read-only views into the live arrays (see the module's docstring).
template <class Store>
void grain_views(py::dict& out, const Store& p, int dim, const py::object& owner) {
  const auto n = p.size();
  const auto d = static_cast<std::size_t>(dim);
  const std::size_t rot = dim == 3 ? 3 : 0;
  out["positions"] = view(p.x.data()->data(), n, d, owner);
  out["velocities"] = view(p.v.data()->data(), n, d, owner);
  out["forces"] = view(p.f.data()->data(), n, d, owner);
  out["radii"] = view(p.radius.data(), n, 0, owner);
  out["masses"] = view(p.mass.data(), n, 0, owner);
  if constexpr (std::is_same_v<typename Store::Rot, double>) {
    out["angular_velocities"] = view(p.omega.data(), n, rot, owner);
    out["torques"] = view(p.t.data(), n, rot, owner);
  } else {
    out["angular_velocities"] = view(p.omega.data()->data(), n, rot, owner);
    out["torques"] = view(p.t.data()->data(), n, rot, owner);
  }
}

template <class T>
struct DimOf;
template <int D>
struct DimOf<Simulation<D>> {
  static constexpr int value = D;
};

// A Python sequence of `D` numbers as a vector; InputError naming `what` otherwise.
template <int D>
typename sable::Space<D>::Vec vec_of(const std::vector<double>& v, const char* what) {
  if (v.size() != static_cast<std::size_t>(D))
    throw sable::InputError(
        fmt::format("{}: {} numbers given, a {}D vector has {}", what, v.size(), D, D));
  typename sable::Space<D>::Vec out;
  for (int d = 0; d < D; ++d) out[d] = v[static_cast<std::size_t>(d)];
  return out;
}

// `sable analyze` with its options as keywords (AnalyzeOptions, analysis/analyze.hpp);
// returns the output folder. python/sable/__init__.py's analyze() reads the files back.
std::string analyze(const std::vector<std::string>& snapshots, const std::string& out_dir,
                    const py::dict& kw) {
  sable::AnalyzeOptions o;
  o.snapshots = snapshots;
  o.out_dir = out_dir;
  for (auto item : kw) {
    const auto key = item.first.cast<std::string>();
    const py::handle v = item.second;
    if (key == "only")
      o.only = v.cast<std::vector<std::string>>();
    else if (key == "walls")
      o.walls = v.cast<std::vector<std::string>>();
    else if (key == "region")
      o.region = v.cast<std::string>();
    else if (key == "grid")
      o.grid = v.cast<std::string>();
    else if (key == "line")
      o.line = v.cast<std::string>();
    else if (key == "kernel")
      o.kernel = v.cast<std::string>();
    else if (key == "vtk_format")
      o.vtk_format = v.cast<std::string>();
    else if (key == "frame")
      o.frame = v.cast<std::string>();
    else if (key == "series")
      o.series = v.cast<std::string>();
    else if (key == "drag_wall")
      o.drag_wall = v.cast<std::string>();
    else if (key == "drag_axis")
      o.drag_axis = v.cast<std::string>();
    else if (key == "bins")
      o.bins = v.cast<int>();
    else if (key == "solid_fraction")
      o.solid_fraction = v.cast<double>();
    else if (key == "reference_force")
      o.reference_force = v.cast<double>();
    else if (key == "eps")
      o.eps = v.cast<double>();
    else if (key == "wall_bin")
      o.wall_bin = v.cast<double>();
    else if (key == "spacing")
      o.spacing = v.cast<double>();
    else if (key == "width")
      o.width = v.cast<double>();
    else if (key == "omega")
      o.omega = v.cast<double>();
    else if (key == "drag_length")
      o.drag_length = v.cast<double>();
    else if (key == "turn_start")
      o.turn_start = v.cast<double>();
    else if (key == "stationary_from")
      o.stationary_from = v.cast<double>();
    else if (key == "level")
      o.level = v.cast<double>();
    else
      throw sable::InputError(
          fmt::format("analyze: unknown option '{}' (the options of "
                      "`sable analyze --help`, with _ for -)",
                      sable::clip(key)));
  }
  py::gil_scoped_release release;
  return sable::run_analysis(o, sable::snapshot_loaders());
}

// A snapshot's grains, contacts, walls and header, read without a simulation.
template <int D>
py::dict snapshot_dict(const std::string& path) {
  World<D> w;
  sable::RunPosition pos;
  sable::load_world(path, w, &pos);
  // The simulation's views of the world's arrays, copied: the world ends here.
  py::dict views, out;
  grain_views(views, w.particles, D, py::none());
  views["ids"] = id_view(w.particles.id, py::none());
  for (auto item : views) out[item.first] = item.second.attr("copy")();
  out["contacts"] = contacts_of(w);
  out["walls"] = walls_of(w);
  out["dimension"] = D;
  out["step"] = w.step;
  out["time"] = w.time;
  out["dt"] = w.dt;
  out["stage"] = pos.stage;
  out["state_hash"] = sable::state_hash(w);
  return out;
}

using SimClass = py::class_<PySimulation>;

void bind_scenario(py::module_& m) {
  py::class_<PyScenario>(m, "Scenario", "A scenario file, parsed and checked.")
      .def_static(
          "load",
          [](const std::string& path) {
            return PyScenario{
                std::make_shared<const sable::ScenarioConfig>(sable::load_scenario(path))};
          },
          py::arg("path"), "Read and check a scenario file (raises InputError naming the line).")
      .def_static(
          "from_string",
          [](const std::string& text, const std::string& path, const std::string& folder) {
            return PyScenario{std::make_shared<const sable::ScenarioConfig>(
                sable::parse_scenario(text, path, folder))};
          },
          py::arg("text"), py::arg("path") = "<string>", py::arg("folder") = ".",
          "Check a scenario given as text; `path` names it in messages, relative files are "
          "looked for in `folder`.")
      .def_static(
          "from_snapshot",
          [](const std::string& path) {
            return PyScenario{
                std::make_shared<const sable::ScenarioConfig>(sable::snapshot_scenario(path))};
          },
          py::arg("path"), "The scenario a snapshot was written by (stored inside it).")
      .def_property_readonly("dimension", [](const PyScenario& s) { return s.cfg->sim.dimension; })
      .def_property_readonly("solver", [](const PyScenario& s) { return s.cfg->sim.solver; })
      .def_property_readonly("path", [](const PyScenario& s) { return s.cfg->path; })
      .def_property_readonly("text", [](const PyScenario& s) { return s.cfg->text; })
      .def_property_readonly("stages", [](const PyScenario& s) {
        std::vector<std::string> names;
        for (const auto& st : s.cfg->stages) names.push_back(st.name);
        return names;
      });
}

// Building, stepping and saving a simulation.
void bind_stepping(SimClass& c) {
  c.def(py::init<const PyScenario&, const std::string&, int, bool, bool, bool, const std::string&,
                 bool>(),
        py::arg("scenario"), py::kw_only(), py::arg("out_dir") = "", py::arg("threads") = 0,
        py::arg("outputs") = true, py::arg("overwrite") = false, py::arg("quiet") = true,
        py::arg("resume") = "", py::arg("accept_changes") = false,
        "Build the model. out_dir overrides [output].dir; outputs=False writes no file; "
        "resume: a snapshot to continue from (as `sable run --resume`).")
      .def(
          "step",
          [](PySimulation& s, std::int64_t n) {
            return s.advance(n, [](const auto&) { return false; });
          },
          py::arg("n") = 1, "Take up to n steps (fewer if the scenario ends); returns how many.")
      .def(
          "run_stage",
          [](PySimulation& s, const std::optional<std::string>& name) {
            const auto last = s.with([&](auto& sim) {
              sim.start();
              const auto& stages = sim.config().stages;
              const std::uint32_t now = sim.position().stage;
              if (!name) return now;
              for (std::uint32_t k = 0; k < stages.size(); ++k) {
                if (stages[k].name != *name) continue;
                if (k < now)
                  throw sable::InputError(fmt::format("run_stage: stage '{}' has ended", *name));
                return k;
              }
              std::string known;
              for (const auto& st : stages) known += (known.empty() ? "" : ", ") + st.name;
              throw sable::InputError(fmt::format("run_stage: no stage named '{}' (stages: {})",
                                                  sable::clip(*name), known));
            });
            return s.advance(-1, [last](const auto& sim) { return sim.position().stage > last; });
          },
          py::arg("name") = py::none(),
          "Run to the end of the current stage, or of the stage `name` (the stages before it "
          "too), its end outputs written; returns the steps taken.")
      .def(
          "run",
          [](PySimulation& s) {
            s.advance(-1, [](const auto&) { return false; });
            return result_dict(s.with([](auto& sim) { return sim.result(); }));
          },
          "Run every stage left; returns steps, time, state_hash, grains, kinetic_energy.")
      .def(
          "save",
          [](PySimulation& s, const std::string& path) {
            s.with([&](auto& sim) { sim.save(path); });
          },
          py::arg("path"), "Write a snapshot of the current state (and its .xmf sidecar).");
}

// The grains (views), contacts and walls (new arrays).
void bind_arrays(SimClass& c) {
  c.def(
       "grains",
       [](py::object self) {
         auto& s = self.cast<PySimulation&>();
         py::dict out;
         s.with([&](auto& sim) {
           sim.start();
           grain_views(out, sim.world().particles, s.dimension(), self);
           out["ids"] = id_view(sim.world().particles.id, self);
         });
         return out;
       },
       "positions, velocities, angular_velocities, forces, torques, radii, masses and ids "
       "(the stable ids' indices, uint32): read-only views of the live arrays.")
      .def(
          "contacts",
          [](PySimulation& s) {
            return s.with([](auto& sim) { return contacts_of(sim.world()); });
          },
          "The touching contacts (new arrays): id_i, id_j, normal (from j to i), point, "
          "normal_force, force and tangential_force (on i); wall_grain_id, wall_index, "
          "wall_force.")
      .def(
          "walls",
          [](PySimulation& s) { return s.with([](auto& sim) { return walls_of(sim.world()); }); },
          "The walls: names, point, orientation (3D: quaternion w, x, y, z; 2D: angle), "
          "velocity, force, spin, torque (new arrays).");
}

// Walls driven between steps.
void bind_wall_control(SimClass& c) {
  c.def(
       "set_wall_velocity",
       [](PySimulation& s, const std::string& name, const std::vector<double>& v) {
         s.with([&](auto& sim) {
           constexpr int D = DimOf<std::remove_cvref_t<decltype(sim)>>::value;
           sim.set_wall_velocity(name, vec_of<D>(v, "velocity"));
         });
       },
       py::arg("name"), py::arg("velocity"),
       "Move the walls `name` names (a wall, or a box's six) at this velocity (m/s), for the "
       "rest of the current stage.")
      .def(
          "set_wall_rotation",
          [](PySimulation& s, const std::string& name, const std::vector<double>& point,
             const std::vector<double>& axis, double rate) {
            s.with([&](auto& sim) {
              constexpr int D = DimOf<std::remove_cvref_t<decltype(sim)>>::value;
              sim.set_wall_rotation(name, vec_of<D>(point, "point"), vec_of<D>(axis, "axis"), rate);
            });
          },
          py::arg("name"), py::arg("point"), py::arg("axis"), py::arg("rate"),
          "Turn the walls `name` names about the axis through `point` at `rate` rad/s, for the "
          "rest of the current stage (2D: axis is ignored but must have 2 numbers).")
      .def(
          "set_wall_stress",
          [](PySimulation& s, const std::string& name, double stress, double max_velocity) {
            s.with([&](auto& sim) { sim.set_wall_stress(name, stress, max_velocity); });
          },
          py::arg("name"), py::arg("stress"), py::arg("max_velocity") = 0.0,
          "Drive the walls `name` names to this normal stress (Pa) for the rest of the current "
          "stage, with the stage's servo settings; max_velocity (m/s) > 0 replaces its "
          "servo_max_velocity (a stage without stress targets has none: then it is needed).");
}

// Where the run is, as properties.
void bind_state(SimClass& c) {
  c.def_property_readonly("dimension", &PySimulation::dimension)
      .def_property_readonly(
          "steps",
          [](PySimulation& s) { return s.with([](auto& sim) { return sim.world().step; }); })
      .def_property_readonly(
          "time",
          [](PySimulation& s) { return s.with([](auto& sim) { return sim.world().time; }); })
      .def_property_readonly(
          "dt", [](PySimulation& s) { return s.with([](auto& sim) { return sim.world().dt; }); })
      .def_property_readonly(
          "stage",
          [](PySimulation& s) { return s.with([](auto& sim) { return sim.position().stage; }); })
      .def_property_readonly(
          "finished",
          [](PySimulation& s) { return s.with([](auto& sim) { return sim.finished(); }); })
      .def_property_readonly("state_hash",
                             [](PySimulation& s) {
                               return s.with([](auto& sim) {
                                 sim.start();
                                 return sable::state_hash(sim.world());
                               });
                             })
      .def_property_readonly("kinetic_energy", [](PySimulation& s) {
        return s.with([](auto& sim) {
          sim.start();
          return sable::kinetic_energy(sim.world());
        });
      });
}

}  // namespace

PYBIND11_MODULE(_sable, m) {
  m.doc() = R"(Sable's engine: scenarios, simulations, snapshots (docs/python.md).

Arrays of grains (Simulation.grains()) are read-only views into the simulation's own
arrays: no copy, and they follow the simulation as it steps (np.array(a) keeps a value).
Rows are slots: the slot sort may permute them between steps; follow grains by their ids.
Contacts and walls come as new arrays.)";
  m.attr("__version__") = SABLE_VERSION;
  auto& input_error = py::register_exception<sable::InputError>(m, "InputError", PyExc_ValueError);
  auto& simulation_error =
      py::register_exception<sable::SimulationError>(m, "SimulationError", PyExc_RuntimeError);
  py::register_exception<sable::IoError>(m, "IoError", PyExc_OSError);
  simulation_error.attr("__doc__") = "The computation failed (a non-finite or runaway grain).";
  input_error.attr("__doc__") = "A scenario, snapshot or argument that cannot be used; says where.";

  bind_scenario(m);

  SimClass sim(m, "Simulation", "A scenario being run, stepped from Python.");
  bind_stepping(sim);
  bind_arrays(sim);
  bind_wall_control(sim);
  bind_state(sim);

  m.def("_analyze", &analyze, py::arg("snapshots"), py::arg("out_dir"), py::arg("options"),
        "sable analyze; returns the output folder (use sable.analyze()).");
  m.def(
      "load_snapshot",
      [](const std::string& path) {
        const int dim = sable::read_snapshot_info(path).dimension;
        return dim == 2 ? snapshot_dict<2>(path) : snapshot_dict<3>(path);
      },
      py::arg("path"),
      "A snapshot's grains (as Simulation.grains(), copies), contacts, walls and header.");
}
