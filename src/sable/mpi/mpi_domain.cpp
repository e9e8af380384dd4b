#include "sable/mpi/mpi_domain.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "sable/core/error.hpp"
#include "sable/mpi/records.hpp"

namespace sable {

namespace {

// Sends out[r] to process r and returns what every process sent to this one, in rank order;
// from[r]: the bytes that came from r.
std::vector<char> all_to_all(MPI_Comm comm, const std::vector<std::vector<char>>& out,
                             std::vector<int>* from = nullptr, std::uint64_t* bytes = nullptr,
                             std::uint64_t* messages = nullptr) {
  for (const auto& o : out) {
    if (bytes) *bytes += o.size();
    if (messages) *messages += o.empty() ? 0 : 1;
  }
  const int size = static_cast<int>(out.size());
  std::vector<int> send(size), recv(size), sdisp(size + 1, 0), rdisp(size + 1, 0);
  for (int r = 0; r < size; ++r) send[r] = static_cast<int>(out[r].size());
  MPI_Alltoall(send.data(), 1, MPI_INT, recv.data(), 1, MPI_INT, comm);
  for (int r = 0; r < size; ++r) {
    sdisp[r + 1] = sdisp[r] + send[r];
    rdisp[r + 1] = rdisp[r] + recv[r];
  }
  std::vector<char> flat(static_cast<std::size_t>(sdisp[size])),
      in(static_cast<std::size_t>(rdisp[size]));
  for (int r = 0; r < size; ++r) std::copy(out[r].begin(), out[r].end(), flat.begin() + sdisp[r]);
  MPI_Alltoallv(flat.data(), send.data(), sdisp.data(), MPI_BYTE, in.data(), recv.data(),
                rdisp.data(), MPI_BYTE, comm);
  if (from) *from = recv;
  return in;
}

}  // namespace

template <int D>
MpiDomain<D>::MpiDomain(MPI_Comm comm) : comm_(comm) {
  MPI_Comm_rank(comm_, &rank_);
  MPI_Comm_size(comm_, &size_);
  send_ids_.resize(static_cast<std::size_t>(size_));
  recv_ids_.resize(static_cast<std::size_t>(size_));
  send_slots_.resize(static_cast<std::size_t>(size_));
  recv_slots_.resize(static_cast<std::size_t>(size_));
}

template <int D>
void MpiDomain<D>::max(double* values, int n) const {
  InMpi timed(*this);
  MPI_Allreduce(MPI_IN_PLACE, values, n, MPI_DOUBLE, MPI_MAX, comm_);
}

template <int D>
void MpiDomain<D>::sum(ExactSum* sums, int n) const {
  InMpi timed(*this);
  constexpr int kPacked = ExactSum::kPacked;
  std::vector<std::int64_t> flat(static_cast<std::size_t>(n) * kPacked);
  for (int k = 0; k < n; ++k) {
    const auto packed = sums[k].packed();
    std::copy(packed.begin(), packed.end(), flat.begin() + k * kPacked);
  }
  MPI_Allreduce(MPI_IN_PLACE, flat.data(), static_cast<int>(flat.size()), MPI_INT64_T, MPI_SUM,
                comm_);
  for (int k = 0; k < n; ++k) {
    std::array<std::int64_t, kPacked> packed;
    std::copy_n(flat.begin() + k * kPacked, kPacked, packed.begin());
    sums[k] = ExactSum::from_packed(packed);
  }
}

// Each owned grain's weight for the cuts: this process's work since the last cut (its time
// outside MPI calls, in ns) shared among its grains in proportion to 1 + their list entries
// (a grain with more partners costs more). The cuts then move work, not grains, from the
// busier processes, as LAMMPS' `fix balance rcb` with time weights does. Empty (count the
// grains) when the work was not measured or time weights are off.
template <int D>
std::vector<std::int64_t> MpiDomain<D>::work_weights(const World<D>& w) {
  const double busy =
      std::chrono::duration<double>(Clock::now() - last_cut_).count() - mpi_seconds_;
  if (!time_weights_ || !(busy > 0.0)) return {};
  const auto& p = w.particles;
  const auto& nl = w.neighbors;
  std::vector<std::int64_t> entries(p.size(), 1);
  for (std::size_t e = 0; e < nl.pairs.size(); ++e) {
    ++entries[nl.pairs.i[e]];
    ++entries[nl.pairs.j[e]];
  }
  for (std::size_t e = 0; e < nl.wall_pairs.size(); ++e) ++entries[nl.wall_pairs.i[e]];
  double total = 0.0;
  for (std::size_t k = 0; k < p.size(); ++k)
    if (!(p.flags[k] & kGhost)) total += static_cast<double>(entries[k]);
  std::vector<std::int64_t> weights;
  weights.reserve(p.size());
  // The time of one interval is noisy (a shared machine's other work, the outputs): the
  // cost per entry is smoothed over the intervals, or the cuts swing from one to the next.
  const double measured = total > 0.0 ? busy * 1e9 / total : 0.0;
  cost_ = cost_ > 0.0 ? 0.5 * (cost_ + measured) : measured;
  for (std::size_t k = 0; k < p.size(); ++k)
    if (!(p.flags[k] & kGhost))
      weights.push_back(
          std::max<std::int64_t>(1, std::llround(cost_ * static_cast<double>(entries[k]))));
  return weights;
}

// The cuts from this process's owned grains (every grain counted once over the processes).
template <int D>
void MpiDomain<D>::cut(const World<D>& w) {
  const auto& p = w.particles;
  std::vector<typename Space<D>::Vec> points;
  points.reserve(p.size());
  for (std::size_t k = 0; k < p.size(); ++k)
    if (!(p.flags[k] & kGhost)) points.push_back(p.x[k]);
  const std::vector<std::int64_t> weights = work_weights(w);
  // Every process must weigh alike (some may not have measured): counts unless all have.
  int weighed = weights.empty() && !points.empty() ? 0 : 1;
  MPI_Allreduce(MPI_IN_PLACE, &weighed, 1, MPI_INT, MPI_MIN, comm_);
  rcb_.cut(
      w.neighbors.domain_lo, w.neighbors.domain_hi, size_, points,
      [this](std::vector<std::int64_t>& counts) {
        MPI_Allreduce(MPI_IN_PLACE, counts.data(), static_cast<int>(counts.size()), MPI_INT64_T,
                      MPI_SUM, comm_);
      },
      bias_, weighed ? weights : std::vector<std::int64_t>{});
  last_cut_ = Clock::now();
  mpi_seconds_ = 0.0;
}

// Migration: the owned grains whose new box is another's go there with their contacts'
// histories; then every process keeps what it owns and takes the ghosts it is sent.
template <int D>
void MpiDomain<D>::redistribute(World<D>& w) {
  cut(w);
  auto& p = w.particles;
  const std::size_t n = p.size();
  std::vector<int> dest(n, -1);  // each owned grain's new owner (-1: a ghost)
  for (std::size_t k = 0; k < n; ++k)
    if (!(p.flags[k] & kGhost)) dest[k] = rcb_.owner(p.x[k]);
  auto leaving = [&](std::uint32_t k) { return dest[k] >= 0 && dest[k] != rank_; };
  std::vector<std::vector<char>> grains(static_cast<std::size_t>(size_)), pairs = grains,
                                                                          walls = grains;
  for (std::uint32_t k = 0; k < n; ++k)
    if (leaving(k))
      mpi_records::put_grain(grains[static_cast<std::size_t>(dest[k])], p, w.liquid.film, k);
  const auto& pl = w.neighbors.pairs;
  for (std::size_t e = 0; e < pl.size(); ++e) {
    const std::uint32_t i = pl.i[e], j = pl.j[e];
    if (!mpi_records::carries_history(pl, e)) continue;
    const int ri = leaving(i) ? dest[i] : -1, rj = leaving(j) ? dest[j] : -1;
    if (ri >= 0) mpi_records::put_pair(pairs[static_cast<std::size_t>(ri)], w, e);
    if (rj >= 0 && rj != ri) mpi_records::put_pair(pairs[static_cast<std::size_t>(rj)], w, e);
  }
  const auto& wl = w.neighbors.wall_pairs;
  for (std::size_t e = 0; e < wl.size(); ++e)
    if (leaving(wl.i[e]))
      mpi_records::put_wall_pair(walls[static_cast<std::size_t>(dest[wl.i[e]])], w, e);
  ++traffic_.builds;
  std::uint64_t* bytes = &traffic_.build_bytes;
  std::uint64_t* messages = &traffic_.build_messages;
  std::vector<char> arrivals = all_to_all(comm_, grains, nullptr, bytes, messages);
  std::vector<char> arrived_pairs = all_to_all(comm_, pairs, nullptr, bytes, messages);
  std::vector<char> arrived_walls = all_to_all(comm_, walls, nullptr, bytes, messages);

  // What stays: the grains this process still owns, their lists' entries (those of pairs
  // with an owned member), then the arrivals and their entries.
  mpi_records::LocalState<D> local =
      mpi_records::extract(w, [&](std::uint32_t k) { return dest[k] == rank_; });
  mpi_records::read_grains(arrivals, local, false);
  local.x_ref.clear();  // a build follows: its positions become the reference
  mpi_records::read_pairs(arrived_pairs, local.pairs);
  mpi_records::read_wall_pairs(arrived_walls, local.wall_pairs);

  // Ghosts: each owned grain to every other process whose box is within reach of it.
  double rmax = 0.0;
  for (double r : local.particles.radius) rmax = std::max(rmax, r);
  this->max(&rmax, 1);
  const double reach2 = ghost_reach2(rmax, w.neighbors.skin);
  std::vector<std::vector<char>> ghosts(static_cast<std::size_t>(size_));
  for (auto& s : send_ids_) s.clear();
  for (std::uint32_t k = 0; k < local.particles.size(); ++k)
    for_each_box_near(local.particles.x[k], reach2, rank_, [&](int r) {
      mpi_records::put_grain(ghosts[static_cast<std::size_t>(r)], local.particles, local.film, k);
      send_ids_[static_cast<std::size_t>(r)].push_back(local.particles.id[k].index);
    });
  std::vector<int> from;
  std::vector<char> ghost_bytes = all_to_all(comm_, ghosts, &from, bytes, messages);
  const std::size_t owned = local.particles.size();
  mpi_records::read_grains(ghost_bytes, local, true);
  // Which process each ghost came from, in the order they came (rank order).
  for (auto& r : recv_ids_) r.clear();
  {
    std::size_t k = owned;
    const std::size_t record = mpi_records::grain_record_bytes<D>();
    for (int r = 0; r < size_; ++r)
      for (int b = 0; b < from[static_cast<std::size_t>(r)]; b += static_cast<int>(record))
        recv_ids_[static_cast<std::size_t>(r)].push_back(local.particles.id[k++].index);
  }
  std::uint64_t count = owned;
  MPI_Allreduce(MPI_IN_PLACE, &count, 1, MPI_UINT64_T, MPI_SUM, comm_);
  total_ = count;
  mpi_records::install(w, std::move(local));
}

// The list build took the pairs among ghosts too: no process needs them (each has its own
// owner elsewhere), and their histories would be wrong (a ghost is not always a ghost here).
template <int D>
void MpiDomain<D>::after_build(World<D>& w) {
  mpi_records::drop_ghost_entries(w);
  const auto& p = w.particles;
  for (int r = 0; r < size_; ++r) {
    auto to_slots = [&](const std::vector<std::uint32_t>& ids, std::vector<std::uint32_t>& slots) {
      slots.clear();
      for (std::uint32_t index : ids) slots.push_back(p.ids.slot(p.ids.id_at_index(index)));
      std::sort(slots.begin(), slots.end());
    };
    to_slots(send_ids_[static_cast<std::size_t>(r)], send_slots_[static_cast<std::size_t>(r)]);
    to_slots(recv_ids_[static_cast<std::size_t>(r)], recv_slots_[static_cast<std::size_t>(r)]);
  }
  neighbours_.clear();
  owner_of_slot_.assign(p.size(), rank_);
  for (int r = 0; r < size_; ++r) {
    const auto q = static_cast<std::size_t>(r);
    if (!send_slots_[q].empty() || !recv_slots_[q].empty()) neighbours_.push_back(r);
    for (std::uint32_t k : recv_slots_[q]) owner_of_slot_[k] = r;
  }
}

// Each share goes to the owner of its bridge's partner (a ghost here), which holds the same
// bridge; every neighbour gets a message, empty or not, so that each knows what to wait for.
template <int D>
void MpiDomain<D>::exchange_bridge_shares(const World<D>& w, std::vector<BridgeShare>& shares) {
  const auto& ids = w.particles.ids;
  shares_out_.resize(static_cast<std::size_t>(size_));
  for (auto& out : shares_out_) out.clear();
  for (const BridgeShare& s : shares) {
    const std::uint32_t slot = ids.slot(ids.id_at_index(s.partner));
    if (slot >= owner_of_slot_.size() || owner_of_slot_[slot] == rank_)
      throw IoError("mpi: a bridge's liquid shared with a grain that is not a ghost here");
    shares_out_[static_cast<std::size_t>(owner_of_slot_[slot])].push_back(s);
  }
  InMpi timed(*this);
  requests_.clear();
  for (int r : neighbours_) {
    const auto& out = shares_out_[static_cast<std::size_t>(r)];
    requests_.emplace_back();
    MPI_Isend(out.data(), static_cast<int>(out.size() * sizeof(BridgeShare)), MPI_BYTE, r,
              kBridgeTag, comm_, &requests_.back());
  }
  shares.clear();
  for (int r : neighbours_) {
    MPI_Status status;
    MPI_Probe(r, kBridgeTag, comm_, &status);
    int bytes = 0;
    MPI_Get_count(&status, MPI_BYTE, &bytes);
    const std::size_t at = shares.size();
    shares.resize(at + static_cast<std::size_t>(bytes) / sizeof(BridgeShare));
    MPI_Recv(shares.data() + at, bytes, MPI_BYTE, r, kBridgeTag, comm_, MPI_STATUS_IGNORE);
  }
  MPI_Waitall(static_cast<int>(requests_.size()), requests_.data(), MPI_STATUSES_IGNORE);
}

// After each drift: the owners' positions, velocities, spins and orientations, in slot order
// on both sides (the global order restricted to the same grains). Only the processes whose
// boxes share ghosts exchange messages (a few neighbours, not every process), their sizes
// known from the slots; the buffers are kept from step to step.
template <int D>
void MpiDomain<D>::refresh_ghosts(World<D>& w) {
  auto& p = w.particles;
  constexpr std::size_t record = mpi_records::motion_record_bytes<D>();
  const auto ranks = static_cast<std::size_t>(size_);
  motion_out_.resize(ranks);
  std::size_t incoming = 0;
  for (const auto& slots : recv_slots_) incoming += slots.size();
  motion_in_.resize(incoming * record);
  requests_.clear();
  ++traffic_.steps;
  InMpi timed(*this);
  char* at = motion_in_.data();
  for (std::size_t r = 0; r < ranks; ++r) {
    const std::size_t bytes = recv_slots_[r].size() * record;
    if (bytes == 0) continue;
    requests_.emplace_back();
    MPI_Irecv(at, static_cast<int>(bytes), MPI_BYTE, static_cast<int>(r), kMotionTag, comm_,
              &requests_.back());
    at += bytes;
  }
  for (std::size_t r = 0; r < ranks; ++r) {
    auto& out = motion_out_[r];
    out.clear();
    for (std::uint32_t k : send_slots_[r]) mpi_records::put_motion(out, p, k);
    if (out.empty()) continue;
    traffic_.step_bytes += out.size();
    ++traffic_.step_messages;
    requests_.emplace_back();
    MPI_Isend(out.data(), static_cast<int>(out.size()), MPI_BYTE, static_cast<int>(r), kMotionTag,
              comm_, &requests_.back());
  }
  MPI_Waitall(static_cast<int>(requests_.size()), requests_.data(), MPI_STATUSES_IGNORE);
  const char* in = motion_in_.data();
  for (std::size_t r = 0; r < ranks; ++r)
    for (std::uint32_t k : recv_slots_[r]) in = mpi_records::get_motion(in, p, k);
}

// Every process built the whole world: keep this one's share, as a redistribution would.
template <int D>
void MpiDomain<D>::scatter(World<D>& w) {
  const auto& p = w.particles;
  total_ = p.size();
  // Every process holds every grain: the cut needs no sum over processes.
  rcb_.cut(
      w.neighbors.domain_lo, w.neighbors.domain_hi, size_, p.x, [](std::vector<std::int64_t>&) {},
      bias_);
  last_cut_ = Clock::now();
  mpi_seconds_ = 0.0;
  double rmax = 0.0;
  for (double r : p.radius) rmax = std::max(rmax, r);
  const double reach2 = ghost_reach2(rmax, w.neighbors.skin);
  for (auto& s : send_ids_) s.clear();
  for (auto& s : recv_ids_) s.clear();
  std::vector<std::uint8_t> keep(p.size(), 0);  // 1 owned, 2 ghost
  for (std::size_t k = 0; k < p.size(); ++k) {
    const int owner = rcb_.owner(p.x[k]);
    for_each_box_near(p.x[k], reach2, owner, [&](int r) {
      if (owner == rank_) send_ids_[static_cast<std::size_t>(r)].push_back(p.id[k].index);
      if (r == rank_) {
        recv_ids_[static_cast<std::size_t>(owner)].push_back(p.id[k].index);
        keep[k] = 2;
      }
    });
    if (owner == rank_) keep[k] = 1;
  }
  mpi_records::LocalState<D> local =
      mpi_records::extract(w, [&](std::uint32_t k) { return keep[k] != 0; });
  for (std::size_t k = 0, m = 0; k < p.size(); ++k) {
    if (!keep[k]) continue;
    if (keep[k] == 2) local.particles.flags[m] |= kGhost;
    ++m;
  }
  mpi_records::install(w, std::move(local));
  after_build(w);
}

template <int D>
void MpiDomain<D>::gather(const World<D>& w, World<D>& whole, int root) const {
  InMpi timed(*this);  // process 0's assembly included: output work, not stepping work
  std::vector<char> grains, pairs, walls;
  mpi_records::put_owned(w, grains, pairs, walls);
  const bool everywhere = root == kEveryProcess;
  const bool here = everywhere || rank_ == root;
  auto collect = [&](const std::vector<char>& mine) {
    int bytes = static_cast<int>(mine.size());
    std::vector<int> counts(static_cast<std::size_t>(size_)),
        disp(static_cast<std::size_t>(size_) + 1, 0);
    if (everywhere)
      MPI_Allgather(&bytes, 1, MPI_INT, counts.data(), 1, MPI_INT, comm_);
    else
      MPI_Gather(&bytes, 1, MPI_INT, counts.data(), 1, MPI_INT, root, comm_);
    for (int r = 0; r < size_; ++r) disp[r + 1] = disp[r] + counts[r];
    std::vector<char> all(here ? static_cast<std::size_t>(disp[size_]) : 0);
    if (everywhere)
      MPI_Allgatherv(mine.data(), bytes, MPI_BYTE, all.data(), counts.data(), disp.data(), MPI_BYTE,
                     comm_);
    else
      MPI_Gatherv(mine.data(), bytes, MPI_BYTE, all.data(), counts.data(), disp.data(), MPI_BYTE,
                  root, comm_);
    return all;
  };
  std::vector<char> all_grains = collect(grains), all_pairs = collect(pairs),
                    all_walls = collect(walls);
  if (!here) return;
  whole = w;
  mpi_records::assemble(whole, all_grains, all_pairs, all_walls);
}

template class MpiDomain<2>;
template class MpiDomain<3>;

}  // namespace sable
