// The part of the grains a solver steps, seen from the solver: the whole bed in a serial run,
// or, under MPI (src/sable/mpi/), the grains this process owns plus ghost copies of its
// neighbours' grains within reach of its box.
//
// The rules that keep the bits of a serial run whatever the number of processes:
// - a process holds its grains, owned and ghosts, in the global order of the slots
//   (ParticleStore::order_key, then the id): every grain meets its partners in the order the
//   serial run meets them, and every pair is taken with the same first member;
// - ghosts carry the owner's position, velocity, spin and orientation after each drift, are
//   not kicked, drifted or checked (kGhost), and their wall contacts do not count in the
//   walls' totals;
// - every decision taken from all the grains (a list rebuild, a stage's end) is taken from
//   a global maximum or an exact sum (core/exact_sum.hpp), the same on every process.
// A serial run uses this base class, whose hooks do nothing.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "sable/core/exact_sum.hpp"
#include "sable/world/snapshot_part.hpp"
#include "sable/world/wall_totals.hpp"
#include "sable/world/world.hpp"

namespace sable {

// Part of the liquid a bridge formed across two processes took: what grain `giver` (an id
// index) gave from its film to its bridge with grain `partner`.
struct BridgeShare {
  std::uint32_t giver, partner;
  double volume;
};

template <int D>
class Domain {
 public:
  virtual ~Domain() = default;
  // True when the grains are split among processes (some may be ghosts).
  virtual bool distributed() const { return false; }
  // This process's rank (0: the one that writes the outputs) and the number of processes.
  virtual int rank() const { return 0; }
  virtual int size() const { return 1; }
  // After the drift: each ghost gets its owner's x, v, omega and orientation.
  virtual void refresh_ghosts(World<D>& /*w*/) {}
  // Each of values[0 .. n) becomes its largest over every process.
  virtual void max(double* /*values*/, int /*n*/) const {}
  // The number of grains over every process (0: this process's count, a serial run).
  virtual std::uint64_t total_grains() const { return 0; }
  // Before a neighbour-list build: the grains that left this process's box go to their new
  // owners (with their contacts' histories), the ghosts are chosen again, and the slots are
  // put back in the global order.
  virtual void redistribute(World<D>& /*w*/) {}
  // After the build: the contacts among ghosts alone are dropped (no process needs them), and
  // the ghost exchange is set up for the new slots.
  virtual void after_build(World<D>& /*w*/) {}
  // Each of sums[0 .. n) becomes the sum of every process's (exactly: the same bits on each).
  virtual void sum(ExactSum* /*sums*/, int /*n*/) const {}
  void sum(ExactSum& s) const { sum(&s, 1); }
  // The walls' totals summed over every process.
  void reduce(WallTotals<D>& totals) const {
    sum(totals.data(), static_cast<int>(totals.components()));
  }

  // From a World every process built or loaded whole (the same scenario or snapshot, the same
  // bits): keeps this process's share, as a redistribution with nothing to send would.
  virtual void scatter(World<D>& /*w*/) {}
  // Collective: the whole state on process 0 in `whole` (every grain, its slots in the global
  // order, its lists as a serial run holds them), for outputs, snapshots and state hashes;
  // the other processes leave `whole` alone.
  virtual void gather(const World<D>& w, World<D>& whole) const { whole = w; }
  // As gather(), onto every process: wetting a decomposed sample (every process wets the
  // whole sample alike, then keeps its share).
  virtual void gather_everywhere(const World<D>& w, World<D>& whole) const { whole = w; }

  // Wet runs, once a step after the bridges' events (collective): `shares` holds what this
  // process's grains gave to the bridges they formed with ghosts; on return, what the ghosts'
  // owners gave to the same bridges (each film's share is known only where its grain is
  // owned, so a bridge's volume is put together from both).
  virtual void exchange_bridge_shares(const World<D>& /*w*/, std::vector<BridgeShare>& /*shares*/) {
  }

  // Collective: this process's share of a snapshot of the whole state, for the processes to
  // write one file together (world/snapshot_part.hpp). False: no share (a serial run writes
  // its World as it is).
  // `path`: the snapshot's final name (the temporary is named after it).
  virtual bool snapshot_part(const World<D>& /*w*/, const std::string& /*path*/,
                             SnapshotPart<D>& /*part*/) const {
    return false;
  }
  // Collective: returns on every process once every process has called it.
  virtual void barrier() const {}
};

// Kinetic energy over every process (world.hpp's kinetic_energy() of this process's own
// grains, summed exactly): the same bits as a serial run's on every process.
template <int D>
double kinetic_energy(const World<D>& w, const Domain<D>& domain, bool translation_only = false) {
  ExactSum e = kinetic_energy_sum(w, translation_only);
  domain.sum(e);
  return e.value();
}

// Makes the Domain a run's grains are stepped in: a launcher under MPI (apps/sable) hands
// one to the runner through RunOptions::domains; without one a run is serial.
class DomainMaker {
 public:
  virtual ~DomainMaker() = default;
  virtual std::unique_ptr<Domain<2>> make2() const = 0;
  virtual std::unique_ptr<Domain<3>> make3() const = 0;
  template <int D>
  std::unique_ptr<Domain<D>> make() const {
    if constexpr (D == 2)
      return make2();
    else
      return make3();
  }
};

}  // namespace sable
