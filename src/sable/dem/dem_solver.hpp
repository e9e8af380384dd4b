// Soft-contact DEM: velocity Verlet over grains, contact forces from the World's contact law.
#pragma once

#include "sable/dem/near_list.hpp"
#include "sable/world/solver.hpp"
#include "sable/world/world.hpp"

namespace sable {

template <int D>
class DemSolver final : public Solver {
 public:
  explicit DemSolver(World<D>& world) : w_(world) {}
  std::string_view name() const override { return "dem"; }
  void initialize() override;
  void step() override;
  const StepDiagnostics& diagnostics() const override { return diag_; }
  const PhaseTimers& timers() const override { return timers_; }

  // Forces and torques at the current positions and velocities (also updates contact history).
  void compute_forces();

 private:
  void kick(double h);
  void kick_drift(double h, double h_drift);
  template <class Normal, bool Roll>
  void pair_forces();
  void split_grains(int threads);
  template <class Normal>
  void wet_pair_forces();
  struct PairPass;
  PairPass pair_pass();
  template <class Normal>
  void wall_forces();
  void accumulate(bool all);
  void prepare_rolling(bool wet);
  void settle_liquid();

  World<D>& w_;
  StepDiagnostics diag_;
  PhaseTimers timers_;
  // Per-contact scratch of the force pass (n x F and overlap), read by the accumulation pass.
  // n x F is written only for the contacts accumulate() reads (every one in wet runs; in dry
  // runs those of gathered grains): elsewhere it may be stale. Apart entries hold zeros.
  std::vector<typename Space<D>::Rot> pair_moment_, wall_moment_;
  std::vector<double> pair_delta_, wall_delta_;  // 0 apart, > 0 overlap, -1 unknown
  // Rolling resistance only: each contact's couple on its first grain (read by accumulate()
  // like n x F; apart entries hold zeros), and per grain 1 / (I + m R^2).
  std::vector<typename Space<D>::Rot> pair_roll_, wall_roll_;
  std::vector<double> roll_inv_ic_;
  // The dry pass's blocks of grains, one per thread, and the grains it leaves to the gather.
  std::vector<std::uint32_t> grain_block_;
  std::vector<std::uint8_t> gathered_;
  // Capillary bridges: per pair, a bridge event of this step (kBridgeFormed / kBridgeBroken),
  // applied in list order after the force pass; events_ counts them (0: nothing to scan).
  std::vector<std::uint8_t> pair_event_;
  std::size_t events_ = 0;
  std::uint64_t scratch_build_ = ~std::uint64_t{0};
  NearList<D> near_;  // the pair entries the force pass visits (dem/near_list.hpp)
};

}  // namespace sable
