// The byte records MPI processes send each other (grains, their contacts' entries, the ghosts'
// motion) and the assembly of a process's share of the World from them. No MPI here: the
// records and the rules of assembly are tested on one process (tests/unit/test_mpi_records.cpp).
//
// Assembly keeps the rule that makes results independent of the split (world/domain.hpp):
// the slots are sorted by (order_key, id index), the global order, so a pair's first member
// and every grain's order of partners are those of a serial run.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "sable/world/world.hpp"

namespace sable::mpi_records {

// A pair entry by ids, with its history; a wall entry likewise.
template <int D>
struct PairRecord {
  ParticleId a, b;
  typename Space<D>::Vec shear, force;
  typename Space<D>::Rot roll;
  double bridge;
};
template <int D>
struct WallRecord {
  ParticleId a;
  std::uint32_t wall, element, feature;
  typename Space<D>::Vec shear, force;
  typename Space<D>::Rot roll;
};

// A process's grains and its lists' entries by ids, before they are installed into a World.
template <int D>
struct LocalState {
  ParticleStore<D> particles;
  std::vector<double> film;  // each grain's liquid film, as the particles (zeros: a dry world)
  std::vector<typename Space<D>::Vec> x_ref;  // empty: the positions (a build follows)
  std::vector<PairRecord<D>> pairs;
  std::vector<WallRecord<D>> wall_pairs;
};

template <int D>
std::size_t grain_record_bytes();
// Appends grain k of p (every per-grain array) and its liquid film (film[k]; 0 when `film`
// does not hold it: a dry world, or a grain added since the liquid last moved).
template <int D>
void put_grain(std::vector<char>& out, const ParticleStore<D>& p, const std::vector<double>& film,
               std::uint32_t k);
// Appends every grain record of `bytes` to s's grains and films, as ghosts or as owned grains.
template <int D>
void read_grains(const std::vector<char>& bytes, LocalState<D>& s, bool ghosts);

// True when entry e holds something a new build would not restore (a history, a force, a
// bridge).
template <int D>
bool carries_history(const PairList<D>& pl, std::size_t e);
template <int D>
void put_pair(std::vector<char>& out, const World<D>& w, std::size_t e);
template <int D>
void put_wall_pair(std::vector<char>& out, const World<D>& w, std::size_t e);
template <int D>
void read_pairs(const std::vector<char>& bytes, std::vector<PairRecord<D>>& out);
template <int D>
void read_wall_pairs(const std::vector<char>& bytes, std::vector<WallRecord<D>>& out);

// The grains of w for which keep(slot) holds, with every entry of the lists that has one of
// them as a member (a grain entry) or as its grain (a wall entry).
template <int D>
LocalState<D> extract(const World<D>& w, const std::function<bool(std::uint32_t)>& keep);

// Makes `local` the World's grains and lists: slots in the global order, the id registry
// rebuilt, the films (a wet world's), the entries whose grains are both here (not both ghosts; a
// wall entry: its grain owned) in their slots, sorted as a build leaves them. Where an entry comes
// twice, the later one wins (an arrival's over the stale copy of a process that held its grain as a
// ghost).
template <int D>
void install(World<D>& w, LocalState<D>&& local);

// Drops the entries among ghosts alone, and the ghosts' wall entries.
template <int D>
void drop_ghost_entries(World<D>& w);

// A ghost's motion: position, velocity, spin, orientation.
template <int D>
void put_motion(std::vector<char>& out, const ParticleStore<D>& p, std::uint32_t k);
// The bytes put_motion() writes for a grain.
template <int D>
constexpr std::size_t motion_record_bytes() {
  using P = ParticleStore<D>;
  return sizeof(typename decltype(P::x)::value_type) + sizeof(typename decltype(P::v)::value_type) +
         sizeof(typename decltype(P::omega)::value_type) +
         sizeof(typename decltype(P::q)::value_type);
}
template <int D>
const char* get_motion(const char* in, ParticleStore<D>& p, std::uint32_t k);

// This process's owned grains (with their list reference positions), the grain entries whose
// first member it owns and its grains' wall entries: its part of the whole state.
template <int D>
void put_owned(const World<D>& w, std::vector<char>& grains, std::vector<char>& pairs,
               std::vector<char>& walls);
// `whole` (a copy of any process's World) made the whole state from every process's
// put_owned() records: the World a serial run holds.
template <int D>
void assemble(World<D>& whole, const std::vector<char>& grains, const std::vector<char>& pairs,
              const std::vector<char>& walls);

}  // namespace sable::mpi_records
