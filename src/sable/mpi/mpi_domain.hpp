// MPI domain decomposition of the grains (the Domain of world/domain.hpp): recursive
// coordinate bisection (mpi/rcb.hpp) of the neighbour list's domain into one box per
// process, remade at every list build; each process steps the grains in its box and holds
// ghost copies of the grains within reach of it (2 R_max + skin: every pair a list build can
// take), with newton off (a pair across two boxes is computed on both, its history kept by
// both). Grains move to their new owner at list builds, with the histories of their
// contacts. Built only when MPI is found (CMake: SABLE_MPI).
#pragma once

#include <mpi.h>

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "sable/mpi/rcb.hpp"
#include "sable/world/domain.hpp"

namespace sable {

template <int D>
class MpiDomain final : public Domain<D> {
 public:
  explicit MpiDomain(MPI_Comm comm);
  int rank() const override { return rank_; }
  int size() const override { return size_; }

  bool distributed() const override { return true; }
  void refresh_ghosts(World<D>& w) override;
  void max(double* values, int n) const override;
  std::uint64_t total_grains() const override { return total_; }
  void redistribute(World<D>& w) override;
  void after_build(World<D>& w) override;
  void sum(ExactSum* sums, int n) const override;
  using Domain<D>::sum;
  void scatter(World<D>& w) override;
  void gather(const World<D>& w, World<D>& whole) const override { gather(w, whole, 0); }
  void gather_everywhere(const World<D>& w, World<D>& whole) const override {
    gather(w, whole, kEveryProcess);
  }
  // gather() onto process `root`, or onto every process (kEveryProcess).
  static constexpr int kEveryProcess = -1;
  void gather(const World<D>& w, World<D>& whole, int root) const;
  void exchange_bridge_shares(const World<D>& w, std::vector<BridgeShare>& shares) override;
  // mpi/mpi_snapshot.cpp: this process's rows of a snapshot all processes write together.
  bool snapshot_part(const World<D>& w, const std::string& path,
                     SnapshotPart<D>& part) const override;
  void barrier() const override;

  // What this process sent, since it was made: for the scaling model (docs/BENCHMARKS.md).
  struct Traffic {
    std::uint64_t steps = 0;           // ghost refreshes (one a step)
    std::uint64_t step_bytes = 0;      // bytes sent by them
    std::uint64_t step_messages = 0;   // non-empty messages sent by them
    std::uint64_t builds = 0;          // redistributions (one a neighbour-list build)
    std::uint64_t build_bytes = 0;     // bytes sent by them (migrants, histories, ghosts)
    std::uint64_t build_messages = 0;  // non-empty messages sent by them
  };
  const Traffic& traffic() const { return traffic_; }
  // This process's box at the last cut.
  const typename Rcb<D>::Box& box() const { return rcb_.box(rank_); }

  // Cuts weighed by measured work (default) or by grain count alone (the scaling model's
  // measurements, or a test that wants the cuts the counts give).
  void set_time_weights(bool on) { time_weights_ = on; }

  // Tests: cut lopsided (the lower half of each cut takes `bias` times its share), which must
  // change no result.
  void set_cut_bias(double bias) { bias_ = bias; }

 private:
  using Clock = std::chrono::steady_clock;
  void cut(const World<D>& w);
  // snapshot_part()'s steps (mpi/mpi_snapshot.cpp): every local grain's global slot (ghosts'
  // from their owners), given the entries each owned grain heads (pairs, walls), with the
  // file rows of its first entries; the share renumbered; parallel HDF5's property lists.
  std::vector<std::uint64_t> global_slots(const World<D>& w,
                                          const std::vector<std::uint32_t>& pairs,
                                          const std::vector<std::uint32_t>& walls,
                                          std::vector<std::uint64_t>& pair_row,
                                          std::vector<std::uint64_t>& wall_row) const;
  void ghost_slots(std::vector<std::uint64_t>& slot) const;
  void fill_part(const World<D>& w, const std::vector<std::uint64_t>& slot,
                 const std::vector<std::uint32_t>& pe, const std::vector<std::uint32_t>& we,
                 std::vector<std::uint64_t>& pair_row, std::vector<std::uint64_t>& wall_row,
                 SnapshotPart<D>& part) const;
  void open_lists(const std::string& path, SnapshotPart<D>& part) const;
  std::vector<std::int64_t> work_weights(const World<D>& w);
  // Times the MPI calls (waiting included) in its scope, so that the time between two cuts
  // less the time in MPI is this process's work.
  class InMpi {
   public:
    explicit InMpi(const MpiDomain& d) : d_(d) {}
    ~InMpi() { d_.mpi_seconds_ += std::chrono::duration<double>(Clock::now() - t0_).count(); }
    InMpi(const InMpi&) = delete;
    InMpi& operator=(const InMpi&) = delete;

   private:
    const MpiDomain& d_;
    Clock::time_point t0_ = Clock::now();
  };
  // The squared reach of a ghost: every pair a list build can take, 2 R_max + skin (a hair
  // more, so that round-off never leaves one out).
  static double ghost_reach2(double rmax, double skin) {
    const double reach = (2.0 * rmax + skin) * (1.0 + 1e-9);
    return reach * reach;
  }
  // f(r) for every process r but `owner` whose box is within reach of x.
  template <class F>
  void for_each_box_near(const typename Space<D>::Vec& x, double reach2, int owner, F&& f) const {
    for (int r = 0; r < size_; ++r)
      if (r != owner && rcb_.distance2(x, r) < reach2) f(r);
  }

  MPI_Comm comm_;
  int rank_ = 0, size_ = 1;
  std::uint64_t total_ = 0;  // grains over every process
  double bias_ = 1.0;
  Rcb<D> rcb_;
  // Per process: the ids of the grains this one sends as ghosts / receives as ghosts (from
  // redistribute), then their slots (after_build), in slot order.
  std::vector<std::vector<std::uint32_t>> send_ids_, recv_ids_, send_slots_, recv_slots_;
  // From after_build(): the processes this one exchanges ghosts with (either way: the
  // relation is symmetric), and the owner of each slot's grain (this process for its own).
  std::vector<int> neighbours_, owner_of_slot_;
  Traffic traffic_;
  // refresh_ghosts()' buffers, kept from step to step.
  static constexpr int kMotionTag = 7301;
  static constexpr int kBridgeTag = 7302;
  static constexpr int kSlotTag = 7303;
  std::vector<std::vector<char>> motion_out_;
  std::vector<std::vector<BridgeShare>> shares_out_;  // exchange_bridge_shares()' buffers
  std::vector<char> motion_in_;
  std::vector<MPI_Request> requests_;
  bool time_weights_ = true;
  Clock::time_point last_cut_ = Clock::now();
  mutable double mpi_seconds_ = 0.0;  // in MPI calls since the last cut
  double cost_ = 0.0;                 // ns of work per list entry, smoothed over the cuts
};

}  // namespace sable
