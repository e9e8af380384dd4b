// The accumulation behind `sable analyze` (analyze.hpp): each analysis takes samples one at a
// time (add) and writes its files at the end (finish). Private to the analysis module.
#pragma once

#include <algorithm>
#include <array>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "sable/analysis/analyze.hpp"
#include "sable/analysis/coarse_grain.hpp"
#include "sable/analysis/dissipation.hpp"
#include "sable/analysis/drag.hpp"
#include "sable/analysis/load_share.hpp"
#include "sable/analysis/report.hpp"
#include "sable/analysis/sample.hpp"
#include "sable/analysis/stress.hpp"
#include "sable/analysis/wall_stress.hpp"

namespace sable {

template <int D>
class AnalysisParts {
 public:
  AnalysisParts(const AnalyzeOptions& opt, const ResultWriter& out,
                std::optional<Region<D>> region);
  void add(const Sample<D>& s);
  // The analyses that read a sample in the lab frame (dissipation), before add() sees it in a
  // turning one.
  void add_lab(const Sample<D>& s);
  // The drag analysis reads the run's series, not the samples: its result is handed in.
  void set_drag(const DragOptions& opt, const DragResult& result) { drag_.emplace(opt, result); }
  void finish();

 private:
  bool wants(const char* name) const {
    return analysis_wanted(opt_, name) && skipped_.count(name) == 0;
  }
  // A sample of polyhedral grains: the analyses that cannot hold for them (dissipation; fields
  // with the sphere kernel) refuse with their message when named in --only, and are skipped
  // (logged and listed in the summary) when every analysis runs.
  void skip_refused(const Sample<D>& s);
  Region<D> region_of(const Sample<D>& s) const;
  void add_contacts(const Sample<D>& s);
  void add_stress(const Sample<D>& s, std::vector<double>& row);
  void add_walls(const Sample<D>& s);
  void add_wall_loads(const Sample<D>& s, std::vector<double>& row);
  void add_fields(const Sample<D>& s);
  void attempt(Summary& into, const std::string& name, const std::function<void()>& body);
  void finish_forces();
  void finish_stress();
  void finish_walls();
  void finish_wall_loads();
  void finish_fields();
  void finish_per_grain();
  void finish_janssen();
  void finish_drag();
  void finish_load_share();
  void finish_dissipation();

  const AnalyzeOptions& opt_;
  const ResultWriter& out_;
  std::optional<Region<D>> region_;
  Summary summary_;
  std::size_t samples_ = 0;
  std::vector<std::string> series_names_;
  std::vector<std::vector<double>> series_;  // rows
  // Pooled contacts: all, and per polarization selection.
  ContactSet<D> all_, bulk_;
  std::map<std::string, ContactSet<D>> by_wall_;
  ContactSet<D> walls_;
  std::vector<std::string> wall_names_;
  // Averaged tensors.
  MeanStress<D> mean_sum_;
  Tensor<D> love_weber_sum_ = Tensor<D>::Zero();
  std::vector<double> pressures_;  // pooled particle pressures
  double nu_sum_ = 0.0;
  std::map<std::string, WallProfile> profiles_;
  std::map<std::string, WallProfileOptions> profile_bins_;
  // The selected walls' forces and torques summed over snapshots; their last pivots.
  struct WallLoad {
    std::string type;
    std::array<double, 3> force{}, torque{}, pivot{};
  };
  std::map<std::string, WallLoad> loads_;
  // Silo balance, summed over snapshots: weight, support by floors, friction of side walls (N).
  double weight_sum_ = 0.0, floor_sum_ = 0.0, friction_sum_ = 0.0, momentum_sum_ = 0.0;
  std::optional<FieldSpec<D>> field_spec_;
  std::optional<Fields<D>> fields_;
  std::optional<Sample<D>> last_;
  std::optional<std::pair<DragOptions, DragResult>> drag_;
  std::vector<LoadShare> load_shares_;          // one per sample
  std::vector<PowerBudget> budgets_;            // one per sample, in the lab frame
  std::map<std::string, std::string> skipped_;  // analysis -> why (polyhedra)
};

// Pressure PDF: p / p_ref over a symmetric range, p_ref the mean |p| of the non-zero ones.
Table pressure_pdf(const std::vector<double>& p, int bins, double& p_ref);

}  // namespace sable
