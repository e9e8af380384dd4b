// Soft-contact DEM: velocity Verlet over grains, contact forces from the World's contact law.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "sable/core/parallel.hpp"
#include "sable/dem/grain_split.hpp"
#include "sable/dem/near_list.hpp"
#include "sable/dem/polyhedral_dem.hpp"
#include "sable/world/domain.hpp"
#include "sable/world/reorder.hpp"
#include "sable/world/solver.hpp"
#include "sable/world/wall_totals.hpp"
#include "sable/world/world.hpp"

namespace sable {

namespace dem_detail {

// Contact slot k is apart. A contact that has just ended forgets its history; slots already
// apart hold zeros and are not written again (most candidates are apart: this saves
// bandwidth). Grain pairs and wall pairs alike, through their arrays' addresses.
template <class Vec, class Rot>
inline void forget_if_ended(Vec* shear, Vec* force, Rot* moment, double* delta, std::size_t k,
                            const Rot& zero) {
  if (delta[k] == 0.0) return;
  shear[k].setZero();
  force[k].setZero();
  moment[k] = zero;
  delta[k] = 0.0;
}

}  // namespace dem_detail

// Laws: the table of normal laws the World's ContactModel::normal indexes (contact/
// registry.hpp); the pair pass is compiled once per law of it. Definitions:
// dem/dem_solver_impl.hpp (instantiated for NormalLaws in dem/dem_solver.cpp).
template <int D, class Laws = NormalLaws>
class DemSolver final : public Solver {
 public:
  explicit DemSolver(World<D>& world) : world_(world) {
    pair_split_.share_tail(kPairTail, kPairChunk);
  }
  std::string_view name() const override { return "dem"; }
  void initialize() override;
  void step() override;
  const StepDiagnostics& diagnostics() const override { return diag_; }
  const PhaseTimers& timers() const override { return timers_; }

  // Forces and torques at the current positions and velocities, no kick (also updates the
  // contact history and the near list): the lists and pair pass stages of step(), with the
  // closing half kick by 0.
  void compute_forces();

  // The process's share of the grains (world/domain.hpp; MPI: mpi/mpi_domain.hpp), set before
  // initialize(); by default the whole bed. Not owned.
  void set_domain(Domain<D>* domain) { domain_ = domain ? domain : &whole_bed_; }

  // Fixed shares of the work per thread (one per thread, normalised) instead of shares that
  // follow the threads' measured speeds (dem/grain_split.hpp). For tests: the results are the
  // same bits for any shares.
  void fix_thread_shares(const std::vector<double>& shares) {
    for (GrainSplit* split : {&opening_split_, &pair_split_, &closing_split_})
      split->fix_shares(shares);
  }
  // The blocks of grains of the step's parallel loops, in step order: the opening loop's, the
  // pair pass's (which closes the grains in dry runs), and the wet runs' closing loop's, when
  // they have been cut (tests, diagnostics).
  std::vector<const GrainSplit*> grain_splits() const {
    std::vector<const GrainSplit*> cut;
    for (const GrainSplit* split : {&opening_split_, &pair_split_, &closing_split_})
      if (split->blocks() > 0) cut.push_back(split);
    return cut;
  }

 private:
  bool polyhedral();  // the World holds polyhedra: polyhedra_ steps it
  // The pair pass shares the last kPairTail of each block's work in chunks of kPairChunk
  // grains, a few us each (see dry_pair_forces): enough to absorb the few-% step-to-step
  // wander of a thread's speed (bench/ab_dense.sh -t 2 measures it: 1.065x in the median).
  static constexpr double kPairTail = 0.05;
  static constexpr std::uint32_t kPairChunk = 64;
  // The dry pass closes its own grains every kCloseChunk grains (their data still in the
  // caches: see dry_pair_forces), and hands out the gathered grains' closing after it in
  // chunks of kGatheredChunk.
  static constexpr std::uint32_t kCloseChunk = 256, kGatheredChunk = 64;

  // The grains' largest squared displacements since the neighbour list's and the near list's
  // reference positions, measured by the opening loop (neighbor_max2 < 0: the neighbour list
  // has no reference for every grain; near_max2 is read only when the near list has one).
  struct Displacements {
    double neighbor_max2 = -1.0, near_max2 = 0.0;
  };

  // The step's stages, in order (step() in dem_solver_impl.hpp), each timed as its Phase.
  Displacements integrate(double h);                  // Phase::kIntegrate
  void update_neighbors(const Displacements* moved);  // Phase::kNeighbors (MPI: kExchange
                                                      // first, the ghosts' motion)
  void build_lists();
  bool pair_pass(double h_kick);  // Phase::kPairPass
  void total_wall_forces();       // Phase::kClosing

  // integrate: the opening grain loop (dem/grain_loops_impl.hpp).
  Displacements kick_and_drift(double h_kick, double h_drift);
  // update_neighbors: the per-entry scratch fitted to the lists, the near list remade.
  void fit_scratch_to_lists();
  void update_near_list(const Displacements* moved);
  void update_mesh_reach(bool remade);
  void skip_far_entries();
  void end_wall_contact(std::size_t k);
  // pair_pass: each grain's rolling factor, then the contact law picked for the pair forces
  // (dry: summed and closed per grain as the pass goes; wet: stored per contact) and, after
  // the bridges' liquid is settled, for the wet runs' closing loop (dem/grain_loops_impl.hpp).
  void prepare_rolling(bool wet);
  bool pair_forces_for_law(double h_kick, bool wet, bool rolling);
  bool closing_loop_for_law(double h_kick);
  template <class Normal, bool Roll>
  bool dry_pair_forces(double h_kick);
  template <class Normal>
  void wet_pair_forces();
  void settle_liquid();
  void move_bridge_liquid();
  void join_bridge_shares();
  template <class Normal>
  bool closing_loop(double h_kick);
  // A grain's closing (dem/grain_loops_impl.hpp): its wall contacts, its sum, the second half
  // kick, the check of its state.
  // (dem/wall_contacts_impl.hpp)
  template <class Normal>
  void wall_contact(std::size_t k, const Wall<D>& wall, const WallFeature<D>& f, double& max_ratio,
                    std::size_t& touching);
  WallFeature<D> mesh_feature(std::uint32_t k, const Wall<D>& wall, const typename Space<D>::Vec& x,
                              double r, double moved, double slack);
  template <class Normal>
  void mesh_contacts(std::uint32_t k0, std::uint32_t k1, const Wall<D>& wall, double& max_ratio,
                     std::size_t& touching);
  template <class Normal>
  void wall_contacts(std::uint32_t g0, std::uint32_t g1, double& max_ratio, std::size_t& touching);
  struct GrainPass;
  GrainPass make_grain_pass(double h_kick);
  template <class Normal>
  int close_passed_grains(const GrainPass& pass, std::uint32_t g0, std::uint32_t g1, double h,
                          double& max_ratio, std::size_t& touching);
  int close_gathered_grains(const GrainPass& pass, const std::uint32_t* g, std::uint32_t g0,
                            std::size_t n, double h);
  int close_gathered_chunks(const GrainPass& pass, std::atomic<std::uint32_t>& next, double h);
  // The loops' blocks of grains.
  void update_pair_split();
  GrainSplit& grain_loop_split(GrainSplit& split);
  struct PairPass;
  PairPass make_pair_pass();
  // Capillary bridges on every pair entry; a contact law with rolling resistance.
  bool wet_run() const {
    return world_.neighbors.bridges &&
           world_.neighbors.pairs.bridge.size() == world_.neighbors.pairs.size();
  }
  bool with_rolling() const { return world_.model.rolling != RollingModel::kNone; }

  World<D>& world_;
  StepDiagnostics diag_;
  PhaseTimers timers_;
  // Per-contact scratch of the force pass (n x F and overlap), read by the gather (GrainPass::sum,
  // dem/grain_loops_impl.hpp). n x F is written only for the contacts the gather reads (every one
  // in wet runs; in dry runs those of gathered grains): elsewhere it may be stale. Apart entries
  // hold zeros.
  std::vector<typename Space<D>::Rot> pair_moment_, wall_moment_;
  std::vector<double> pair_delta_, wall_delta_;  // 0 apart, > 0 overlap, -1 unknown
  Domain<D> whole_bed_;                          // a serial run's (no decomposition)
  Domain<D>* domain_ = &whole_bed_;              // the grains this process steps
  WallTotals<D> wall_totals_;                    // total_wall_forces()' exact sums
  std::unique_ptr<PolyhedralDem> polyhedra_;     // the step of a World with polyhedral grains
  std::vector<std::uint32_t> by_wall_, by_wall_begin_, by_wall_fill_;  // and its entries by wall
  std::vector<typename Space<D>::Rot> by_wall_torque_;                 // and their torques
  // Rolling resistance only: each contact's couple on its first grain (read by the gather
  // like n x F; apart entries hold zeros), and per grain 1 / (I + m R^2).
  std::vector<typename Space<D>::Rot> pair_roll_, wall_roll_;
  std::vector<double> roll_inv_ic_;
  // Mesh contacts only (mesh_contacts): each entry's feature this step, and whether its
  // contact began (it takes an ended contact's history).
  std::vector<WallFeature<D>> feature_;
  std::vector<std::uint8_t> hand_over_;
  // Mesh entries only, remade with the near list (update_mesh_reach): kFar where the element
  // was beyond the grain's radius plus the inner skin (mesh_reach_skin_), the grains since
  // moving less than half that and each mesh (pose mesh_reach_point_/turn_) less than half
  // too, so that it cannot touch; else the index of its may_touch values then, mesh_near_ref_
  // (in entry order: read as a stream), which bound the test while the mesh has not moved
  // (mesh_still_) and the grain is within |x - mesh_x_ref_| of where they were taken.
  // Each near entry's record also keeps its last inactive answer: where it was found and
  // its margin (-1: none), see mesh_feature().
  static constexpr std::uint32_t kFar = ~std::uint32_t{0};
  // With meshes (made with mesh_reach_): per wall entry k, the first entry at or after k
  // that the step visits, all but the far mesh entries (wall_from_[size] = size); empty
  // without meshes. A fine mesh has some 30 entries per grain beside it and 1 to 3 near.
  std::vector<std::uint32_t> wall_from_;
  struct EntryWalk {
    const std::uint32_t* from;  // null: every entry
    std::uint32_t first(std::uint32_t k) const { return from ? from[k] : k; }
    std::uint32_t next(std::uint32_t k) const { return from ? from[k + 1] : k + 1; }
  };
  EntryWalk entry_walk() const { return {wall_from_.empty() ? nullptr : wall_from_.data()}; }
  struct MeshNearRef {
    std::array<double, D + 1> values;
    typename Space<D>::Vec x;
    double margin;
  };
  std::vector<std::uint32_t> mesh_reach_;
  std::vector<MeshNearRef> mesh_near_ref_;
  std::vector<typename Space<D>::Vec> mesh_x_ref_;
  std::vector<typename Space<D>::Vec> mesh_reach_point_;
  std::vector<typename Space<D>::Orientation> mesh_reach_turn_;
  std::vector<std::uint8_t> mesh_still_;
  double mesh_reach_skin_ = 0.0;
  // The blocks of grains of the step's loops, one per thread: each parallel loop has its own,
  // so that its threads finish together (dem/grain_split.hpp). The pair pass's, and the grains
  // it leaves to the gather, are made again after each near-list remake (update_pair_split()).
  GrainSplit opening_split_, pair_split_, closing_split_;
  // Per grain, the pair pass's flags: kGathered, its sum is left to the gather (another
  // block's entries reach it); kInTail, it lies in its block's shared tail, where the
  // other threads may take it (see dry_pair_forces).
  static constexpr std::uint8_t kGathered = 1, kInTail = 2;
  std::vector<std::uint8_t> grain_flags_;
  std::vector<std::uint32_t> gathered_list_;        // the grains flagged kGathered, ascending
  std::uint64_t split_remake_ = ~std::uint64_t{0};  // the near-list remake pair_split_ fits
  // Capillary bridges: per pair, a bridge event of this step (kBridgeFormed / kBridgeBroken),
  // applied in list order after the force pass; events_ counts them (0: nothing to scan).
  std::vector<std::uint8_t> pair_event_;
  std::size_t events_ = 0;
  // settle_liquid()'s scratch: the bridges formed this step with what each grain gave, and
  // (under MPI) the shares exchanged with the ghosts' owners.
  struct FormedBridge {
    std::size_t entry;
    double from_i, from_j;
  };
  std::vector<FormedBridge> formed_;
  std::vector<BridgeShare> shares_;
  std::uint64_t scratch_build_ = ~std::uint64_t{0};  // the neighbour build the scratch fits
  NearList<D> near_;         // the pair entries the force pass visits (dem/near_list.hpp)
  GrainReorder<D> reorder_;  // the grains in cell order at some builds (world/reorder.hpp)
};

}  // namespace sable
