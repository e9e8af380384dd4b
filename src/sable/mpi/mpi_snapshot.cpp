// A decomposed run's share of a snapshot (world/snapshot_part.hpp): where each of this
// process's rows goes in the file that every process writes together.
//
// The file's grain rows are in the global order (order_key, then id index), which interleaves
// the processes' grains; a pair's rows follow its first member's, a wall entry's its grain's.
// Each process knows its own grains' order among themselves, not among everyone's: their
// keys go to the process that ranks a range of keys (ranges cut at keys sampled from every
// process, as a sample sort cuts them), which numbers the range's grains and their entries
// from the counts of the ranges before it and sends the numbers back. Only keys and counts
// travel (24 bytes a grain); no process holds more than its share.
#include <hdf5.h>
#include <unistd.h>

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <tuple>

#include "sable/core/error.hpp"
#include "sable/mpi/mpi_domain.hpp"

namespace sable {

namespace {

// A grain's place in the global order, and what follows it in the file.
struct KeyRecord {
  std::uint64_t key;
  std::uint32_t index, pairs, walls, unused;
};
bool before(const KeyRecord& a, const KeyRecord& b) {
  return std::tie(a.key, a.index) < std::tie(b.key, b.index);
}
// The rows the ranking process found for it: the grain's, its first pair's, its first wall
// entry's.
struct Placed {
  std::uint64_t grain, pair, wall;
};

// Sends out[k] to process dest[k] (dest nondecreasing) and returns what came, by rank, with
// the counts that came from each (for the reply).
template <class T>
std::vector<T> exchange(MPI_Comm comm, int size, const std::vector<T>& out,
                        const std::vector<int>& send, std::vector<int>& recv) {
  std::vector<int> sdisp(size + 1, 0), rdisp(size + 1, 0), sbytes(size), rbytes(size);
  recv.assign(size, 0);
  MPI_Alltoall(send.data(), 1, MPI_INT, recv.data(), 1, MPI_INT, comm);
  for (int r = 0; r < size; ++r) {
    sbytes[r] = send[r] * static_cast<int>(sizeof(T));
    rbytes[r] = recv[r] * static_cast<int>(sizeof(T));
    sdisp[r + 1] = sdisp[r] + sbytes[r];
    rdisp[r + 1] = rdisp[r] + rbytes[r];
  }
  std::vector<T> in(static_cast<std::size_t>(rdisp[size]) / sizeof(T));
  MPI_Alltoallv(out.data(), sbytes.data(), sdisp.data(), MPI_BYTE, in.data(), rbytes.data(),
                rdisp.data(), MPI_BYTE, comm);
  return in;
}

// Splitters: size - 1 keys cutting the global order into ranges of about equal counts,
// from size evenly spaced keys of each process's (sorted) ones.
std::vector<KeyRecord> splitters(MPI_Comm comm, int size, const std::vector<KeyRecord>& mine) {
  std::vector<KeyRecord> sample;
  const std::size_t n = mine.size(),
                    take = std::min<std::size_t>(n, static_cast<std::size_t>(size));
  for (std::size_t k = 0; k < take; ++k) sample.push_back(mine[k * n / take]);
  int bytes = static_cast<int>(sample.size() * sizeof(KeyRecord));
  std::vector<int> counts(size), disp(size + 1, 0);
  MPI_Allgather(&bytes, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
  for (int r = 0; r < size; ++r) disp[r + 1] = disp[r] + counts[r];
  std::vector<KeyRecord> all(static_cast<std::size_t>(disp[size]) / sizeof(KeyRecord));
  MPI_Allgatherv(sample.data(), bytes, MPI_BYTE, all.data(), counts.data(), disp.data(), MPI_BYTE,
                 comm);
  std::sort(all.begin(), all.end(), before);
  std::vector<KeyRecord> cuts;
  for (int r = 1; r < size && !all.empty(); ++r)
    cuts.push_back(all[static_cast<std::size_t>(r) * all.size() / static_cast<std::size_t>(size)]);
  return cuts;
}

// The process that ranks `rec`: the number of cuts at or before it.
int ranker(const std::vector<KeyRecord>& cuts, const KeyRecord& rec) {
  return static_cast<int>(std::upper_bound(cuts.begin(), cuts.end(), rec, before) - cuts.begin());
}

// Numbers the grains that came to this process (its range of the global order) and their
// entries' first rows, from the totals of the ranges before it.
std::vector<Placed> place(MPI_Comm comm, const std::vector<KeyRecord>& in) {
  std::vector<std::uint32_t> order(in.size());
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(),
            [&](std::uint32_t a, std::uint32_t b) { return before(in[a], in[b]); });
  std::uint64_t here[3] = {in.size(), 0, 0}, start[3] = {0, 0, 0};
  for (const KeyRecord& r : in) {
    here[1] += r.pairs;
    here[2] += r.walls;
  }
  MPI_Exscan(here, start, 3, MPI_UINT64_T, MPI_SUM, comm);
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  if (rank == 0) std::fill(start, start + 3, 0);  // MPI_Exscan leaves process 0's undefined
  std::vector<Placed> placed(in.size());
  for (std::uint32_t k : order) {
    placed[k] = {start[0]++, start[1], start[2]};
    start[1] += in[k].pairs;
    start[2] += in[k].walls;
  }
  return placed;
}

}  // namespace

template <int D>
std::vector<std::uint64_t> MpiDomain<D>::global_slots(const World<D>& w,
                                                      const std::vector<std::uint32_t>& pairs,
                                                      const std::vector<std::uint32_t>& walls,
                                                      std::vector<std::uint64_t>& pair_row,
                                                      std::vector<std::uint64_t>& wall_row) const {
  const auto& p = w.particles;
  std::vector<KeyRecord> mine;
  std::vector<std::uint32_t> owned;
  for (std::uint32_t s = 0; s < p.size(); ++s) {
    if (p.flags[s] & kGhost) continue;
    owned.push_back(s);
    mine.push_back({p.order_key[s], p.id[s].index, pairs[s], walls[s], 0});
  }
  if (!std::is_sorted(mine.begin(), mine.end(), before))
    throw std::logic_error("mpi: a process's grains are not in the global order");
  const std::vector<KeyRecord> cuts = splitters(comm_, size_, mine);
  std::vector<int> send(size_, 0), recv;
  for (const KeyRecord& r : mine) ++send[ranker(cuts, r)];
  const std::vector<KeyRecord> in = exchange(comm_, size_, mine, send, recv);
  std::vector<int> back;
  const std::vector<Placed> placed = exchange(comm_, size_, place(comm_, in), recv, back);
  // The replies come back in the order the keys left: this process's order.
  std::vector<std::uint64_t> slot(p.size(), ~std::uint64_t{0});
  pair_row.assign(p.size(), 0);
  wall_row.assign(p.size(), 0);
  for (std::size_t k = 0; k < owned.size(); ++k) {
    slot[owned[k]] = placed[k].grain;
    pair_row[owned[k]] = placed[k].pair;
    wall_row[owned[k]] = placed[k].wall;
  }
  ghost_slots(slot);
  return slot;
}

// Each ghost's global slot from its owner, along the ghost refresh's routes.
template <int D>
void MpiDomain<D>::ghost_slots(std::vector<std::uint64_t>& slot) const {
  std::vector<std::vector<std::uint64_t>> out(static_cast<std::size_t>(size_)),
      in(static_cast<std::size_t>(size_));
  std::vector<MPI_Request> requests;
  for (std::size_t r = 0; r < out.size(); ++r) {
    in[r].resize(recv_slots_[r].size());
    if (!in[r].empty()) {
      requests.emplace_back();
      MPI_Irecv(in[r].data(), static_cast<int>(in[r].size()), MPI_UINT64_T, static_cast<int>(r),
                kSlotTag, comm_, &requests.back());
    }
    for (std::uint32_t k : send_slots_[r]) out[r].push_back(slot[k]);
    if (!out[r].empty()) {
      requests.emplace_back();
      MPI_Isend(out[r].data(), static_cast<int>(out[r].size()), MPI_UINT64_T, static_cast<int>(r),
                kSlotTag, comm_, &requests.back());
    }
  }
  MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
  for (std::size_t r = 0; r < in.size(); ++r)
    for (std::size_t k = 0; k < in[r].size(); ++k) slot[recv_slots_[r][k]] = in[r][k];
}

template <int D>
bool MpiDomain<D>::snapshot_part(const World<D>& w, const std::string& path,
                                 SnapshotPart<D>& part) const {
  InMpi timed(*this);
  const auto& p = w.particles;
  const auto& nl = w.neighbors;
  auto owned = [&](std::uint32_t s) { return !(p.flags[s] & kGhost); };
  // The entries this process writes, as a gathered World lists them: sorted by their grains'
  // global order, which the slots here follow.
  std::vector<std::uint32_t> pe, we, pairs(p.size(), 0), walls(p.size(), 0);
  for (std::uint32_t e = 0; e < nl.pairs.size(); ++e)
    if (owned(nl.pairs.i[e])) pe.push_back(e);
  for (std::uint32_t e = 0; e < nl.wall_pairs.size(); ++e)
    if (owned(nl.wall_pairs.i[e])) we.push_back(e);
  std::stable_sort(pe.begin(), pe.end(), [&](std::uint32_t a, std::uint32_t b) {
    return std::tie(nl.pairs.i[a], nl.pairs.j[a]) < std::tie(nl.pairs.i[b], nl.pairs.j[b]);
  });
  const auto& wl = nl.wall_pairs;
  std::stable_sort(we.begin(), we.end(), [&](std::uint32_t a, std::uint32_t b) {
    return std::tie(wl.i[a], wl.wall[a], wl.element[a]) <
           std::tie(wl.i[b], wl.wall[b], wl.element[b]);
  });
  for (std::uint32_t e : pe) ++pairs[nl.pairs.i[e]];
  for (std::uint32_t e : we) ++walls[wl.i[e]];
  std::vector<std::uint64_t> pair_row, wall_row;
  const std::vector<std::uint64_t> slot = global_slots(w, pairs, walls, pair_row, wall_row);
  fill_part(w, slot, pe, we, pair_row, wall_row, part);
  open_lists(path, part);
  return true;
}

// The share itself: this process's grains and entries, renumbered into global slots.
template <int D>
void MpiDomain<D>::fill_part(const World<D>& w, const std::vector<std::uint64_t>& slot,
                             const std::vector<std::uint32_t>& pe,
                             const std::vector<std::uint32_t>& we,
                             std::vector<std::uint64_t>& pair_row,
                             std::vector<std::uint64_t>& wall_row, SnapshotPart<D>& part) const {
  const auto& p = w.particles;
  const auto& nl = w.neighbors;
  part.world = w;
  World<D>& pw = part.world;
  std::vector<std::uint32_t> keep;
  for (std::uint32_t s = 0; s < p.size(); ++s)
    if (!(p.flags[s] & kGhost)) keep.push_back(s);
  pw.particles.for_each_array([&](auto& a) {
    auto from = a;
    a.clear();
    for (std::uint32_t s : keep) a.push_back(from[s]);
  });
  pw.liquid.film.clear();
  pw.neighbors.x_ref.clear();
  std::uint64_t max_index = 0;
  // A process may hold no grain, hence no films: the files' films are every process's choice.
  int films = w.liquid.has_films() ? 1 : 0;
  MPI_Allreduce(MPI_IN_PLACE, &films, 1, MPI_INT, MPI_MAX, comm_);
  part.films = films != 0;
  for (std::uint32_t s : keep) {
    // As a gathered World holds them (mpi/records.cpp, install): films where this world has
    // any (wet, or a capillary law's zeros before the wetting), none otherwise.
    if (films) pw.liquid.film.push_back(s < w.liquid.film.size() ? w.liquid.film[s] : 0.0);
    pw.neighbors.x_ref.push_back(s < nl.x_ref.size() ? nl.x_ref[s] : p.x[s]);
    part.grain_rows.push_back(slot[s]);
    part.registry_rows.push_back(p.id[s].index);
    part.registry_slots.push_back(static_cast<std::uint32_t>(slot[s]));
    part.registry_generations.push_back(p.id[s].generation);
    max_index = std::max<std::uint64_t>(max_index, p.id[s].index + std::uint64_t{1});
  }
  auto& pl = pw.neighbors.pairs;
  pl.clear();
  for (std::uint32_t e : pe) {
    const std::uint32_t i = nl.pairs.i[e], j = nl.pairs.j[e];
    if (slot[j] == ~std::uint64_t{0}) throw std::logic_error("mpi: a pair's ghost has no slot");
    pl.i.push_back(static_cast<std::uint32_t>(slot[i]));
    pl.j.push_back(static_cast<std::uint32_t>(slot[j]));
    pl.shear.push_back(nl.pairs.shear[e]);
    pl.force.push_back(nl.pairs.force[e]);
    if (nl.rolling) pl.roll.push_back(nl.pairs.roll[e]);
    if (nl.bridges && nl.pairs.bridge.size() == nl.pairs.size())
      pl.bridge.push_back(nl.pairs.bridge[e]);
    part.pair_rows.push_back(pair_row[i]++);
  }
  auto& wl = pw.neighbors.wall_pairs;
  wl.clear();
  for (std::uint32_t e : we) {
    const std::uint32_t i = nl.wall_pairs.i[e];
    wl.i.push_back(static_cast<std::uint32_t>(slot[i]));
    wl.wall.push_back(nl.wall_pairs.wall[e]);
    wl.element.push_back(nl.wall_pairs.element[e]);
    wl.feature.push_back(nl.wall_pairs.feature[e]);
    wl.shear.push_back(nl.wall_pairs.shear[e]);
    wl.force.push_back(nl.wall_pairs.force[e]);
    if (nl.rolling) wl.roll.push_back(nl.wall_pairs.roll[e]);
    part.wall_pair_rows.push_back(wall_row[i]++);
  }
  std::uint64_t sums[3] = {keep.size(), pe.size(), we.size()}, totals[3];
  MPI_Allreduce(sums, totals, 3, MPI_UINT64_T, MPI_SUM, comm_);
  MPI_Allreduce(&max_index, &part.registry, 1, MPI_UINT64_T, MPI_MAX, comm_);
  part.grains = totals[0];
  part.pairs = totals[1];
  part.wall_pairs = totals[2];
  part.root = rank_ == 0;
}

// Parallel HDF5 on this communicator, collective transfers; the temporary's name is process
// 0's (`path.tmp-<pid>`, as every atomic write of Sable names its temporary).
template <int D>
void MpiDomain<D>::open_lists(const std::string& path, SnapshotPart<D>& part) const {
  const hid_t fapl = H5Pcreate(H5P_FILE_ACCESS), dxpl = H5Pcreate(H5P_DATASET_XFER);
  part.lists = std::shared_ptr<const void>(nullptr, [fapl, dxpl](const void*) {
    H5Pclose(fapl);
    H5Pclose(dxpl);
  });
  if (fapl < 0 || dxpl < 0 || H5Pset_fapl_mpio(fapl, comm_, MPI_INFO_NULL) < 0 ||
      H5Pset_dxpl_mpio(dxpl, H5FD_MPIO_COLLECTIVE) < 0)
    throw IoError("parallel HDF5: cannot set up MPI-IO for writing a snapshot");
  part.file_access = fapl;
  part.transfer = dxpl;
  long pid = static_cast<long>(::getpid());
  MPI_Bcast(&pid, 1, MPI_LONG, 0, comm_);
  part.temp_path = path + ".tmp-" + std::to_string(pid);
}

template <int D>
void MpiDomain<D>::barrier() const {
  InMpi timed(*this);
  MPI_Barrier(comm_);
}

#define SABLE_MPI_SNAPSHOT(D)                                                                      \
  template bool MpiDomain<D>::snapshot_part(const World<D>&, const std::string&, SnapshotPart<D>&) \
      const;                                                                                       \
  template void MpiDomain<D>::barrier() const;
SABLE_MPI_SNAPSHOT(2)
SABLE_MPI_SNAPSHOT(3)
#undef SABLE_MPI_SNAPSHOT

}  // namespace sable
