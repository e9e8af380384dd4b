// `sable analyze`: every micromechanical analysis of one snapshot or a series of them.
//
// The command loads each snapshot as a Sample (optionally seen from a rotating frame), runs
// the analyses asked for, and writes into one output directory:
//   summary.json                 every scalar result, the inputs and the options
//   force_pdf_*.csv              normal (compressive, tensile) and tangential force PDFs
//   coordination.csv             histogram of contacts per grain
//   fabric.csv, fabric_azimuth.csv   contact orientations
//   polarization_<selection>.csv     |ft| / (mu fn) histograms (bulk, walls, each wall)
//   particle_stress.csv, pressure_pdf.csv   per-grain stresses (last snapshot), pressure PDF
//   wall_profile_<wall>.csv      wall normal and shear stress against height
//   janssen.csv                  side-wall normal stress with Janssen's fitted profile
//   percolation.csv              per-grain phase and cluster label (last snapshot)
//   fields.vti / fields_line.csv coarse-grained fields (grid / line)
//   series.csv                   per-snapshot scalars when several snapshots are given
//   drag.csv                     a turning wall's torque and drag per half-turn (the run's
//                                series.csv; drag.hpp)
//   load_share.csv               the weight above a level and who carries it (load_share.hpp)
//   dissipation.csv              power put in by each wall and dissipated by the contacts, per
//                                snapshot, in the lab frame (dissipation.hpp)
// With several snapshots, statistics are pooled over all of their contacts, tensors, wall
// profiles and fields are averaged (time averages), and per-grain outputs are the last
// snapshot's. With --plot, scripts/plot_analysis.py draws a PNG next to each table.
#pragma once

#include <iosfwd>
#include <limits>
#include <string>
#include <vector>

namespace sable {

struct SampleLoaders;

struct AnalyzeOptions {
  std::vector<std::string> snapshots;
  std::string out_dir;            // empty: "analysis" beside the first snapshot
  std::vector<std::string> only;  // analyses to run (names in kAnalyses); empty: all
  std::string region;             // "xlo,ylo[,zlo]:xhi,yhi[,zhi]"; empty: the grains' box
  double solid_fraction = 0.0;    // for free volumes; 0: measured over the region
  int bins = 50;
  double reference_force = 0.0;       // f0 for the PDFs (wet samples); 0: the mean force
  double eps = 0.01;                  // polarization: on the cone when |ft| >= (1 - eps) mu fn
  std::vector<std::string> walls;     // wall profiles and polarization; empty: every wall
  double wall_bin = 0.0;              // profile bin height (m); 0: two mean diameters
  std::string grid;                   // "10x10x40" node counts; empty: no grid unless spacing
  double spacing = 0.0;               // grid spacing (m) instead of counts
  std::string line;                   // "x,y[,z]:x,y[,z]:n" nodes along a segment
  std::string kernel = "sphere";      // sphere | gaussian | lucy
  std::string vtk_format = "binary";  // fields.vti: binary | zlib | ascii (io/vtk_xml.hpp)
  double width = 0.0;                 // kernel radius / width (m); 0: two mean diameters
  std::string frame;                  // rotating frame "px,py,pz:ux,uy,uz"; empty: lab frame
  double omega = 0.0;  // the frame's angular velocity, and drag's turning rate (rad/s)
  // drag (drag.hpp): runs when named in `only`, or with `only` empty when drag_wall is given.
  std::string series;        // the run's series.csv; empty: beside the snapshots/ folder
  std::string drag_wall;     // the turning wall
  std::string drag_axis;     // "ux,uy,uz"; empty: the frame's axis, else z
  double drag_length = 0.0;  // L in F = 4 M / L (m); 0: torque only
  double turn_start = std::numeric_limits<double>::quiet_NaN();  // s; NaN: the series' start
  double stationary_from = 1.0;                                  // turns after turn_start
  // load-share (load_share.hpp): runs when named in `only`, or with `only` empty when the
  // level is given.
  double level = std::numeric_limits<double>::quiet_NaN();  // m along -gravity
  bool plot = false;
  std::string plot_script;  // empty: scripts/plot_analysis.py beside the executable's tree
  std::ostream* log = nullptr;
};

inline constexpr const char* kAnalyses[] = {
    "forces", "coordination", "fabric",      "polarization", "particle-stress",
    "stress", "walls",        "percolation", "fields",       "janssen",
    "drag",   "load-share",   "dissipation"};

// Whether `name` runs: named in opt.only, or opt.only empty and (for drag and load-share,
// which need an option of their own) that option given.
bool analysis_wanted(const AnalyzeOptions& opt, const std::string& name);

// Runs the analyses; returns the output directory. Throws InputError for bad options or
// snapshots (naming the file or the option), before anything is written where possible.
// `loaders` read the snapshots (scenario/snapshot_sample.hpp: snapshot_loaders()).
std::string run_analysis(const AnalyzeOptions& opt, const SampleLoaders& loaders);

}  // namespace sable
