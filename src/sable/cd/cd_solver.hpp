// Non-smooth contact dynamics (Moreau-Jean time stepping, NLGS contact solver).
//
// Grains are rigid; at each step the contact impulses r (normal and friction) are the unknowns
// of a frictional contact problem in local form, solved by nonlinear Gauss-Seidel with a
// bi-potential (or exact) local solver. The solver advances the same World as DEM: grains,
// walls, materials and the neighbour lists, whose per-contact `force` slot holds impulse / h
// (so outputs and analyses read CD forces exactly like DEM forces, and the impulses of
// persisting contacts warm-start the next step and travel in snapshots).
#pragma once

#include <vector>

#include "sable/cd/nlgs.hpp"
#include "sable/world/solver.hpp"
#include "sable/world/world.hpp"

namespace sable {

struct CdSettings {
  double theta = 0.5;  // weight of the end-of-step smooth forces in the free velocity
  cd::NlgsSettings nlgs;
  bool warm_start = true;
};

template <int D>
class CdSolver final : public Solver {
 public:
  using Vec = typename Space<D>::Vec;
  using LVec = cd::LVec<D>;
  using LMat = cd::LMat<D>;

  CdSolver(World<D>& world, const CdSettings& settings) : w_(world), s_(settings) {}
  std::string_view name() const override { return "cd"; }
  void initialize() override;
  void step() override;
  const StepDiagnostics& diagnostics() const override { return diag_; }
  const PhaseTimers& timers() const override { return timers_; }
  std::vector<std::string> diagnostic_columns() const override;
  void diagnostic_values(std::vector<double>& row) const override;
  const cd::NlgsResult& last_solve() const { return result_; }

  // The problem NLGS sees: one entry per candidate contact, velocities from the grains.
  // Public so the NLGS template can call it; not part of the user API.
  struct Contacts {
    std::vector<std::uint32_t> i;        // grain slot
    std::vector<std::uint32_t> partner;  // grain slot, or wall index when `wall` is set
    std::vector<std::uint8_t> wall;      // 1 for a grain-wall contact
    std::vector<std::uint32_t> source;   // index into the pair or wall-pair list
    std::vector<LMat> frame;             // columns n, t1 (, t2): local -> world
    std::vector<Vec> arm_i, arm_j;       // centre -> contact point
    std::vector<LMat> w;                 // Delassus diagonal block
    std::vector<double> mu;
    std::vector<double> gap;  // at the start of the step; max(gap, 0) / h joins U_N
    std::vector<LVec> r;      // impulse, local frame
    std::size_t size() const { return i.size(); }
    void clear();
  };
  class Problem;

 private:
  void build_contacts();
  template <bool kWall>
  void add_contact(std::uint32_t i, std::uint32_t partner, std::uint32_t source, const Vec& n,
                   double gap, const Vec& arm_i, const Vec& arm_j, double mu, const Vec& force);
  void store_impulses();
  double max_speed() const;

  World<D>& w_;
  CdSettings s_;
  StepDiagnostics diag_;
  PhaseTimers timers_;
  Contacts c_;
  cd::NlgsResult result_;
};

}  // namespace sable
