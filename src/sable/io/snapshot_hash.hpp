// The state hash of a snapshot, computed from its file a block of rows at a time.
//
// A decomposed run writes its snapshot collectively (each process its own rows), so no
// process holds the whole state whose hash goes into the root attribute 'state_hash'. Process
// 0 streams the per-grain and per-contact datasets back from the written file instead,
// through the same field order as state_hash (world/state_hash.hpp, state_hash_with): the
// bits are those state_hash gives for the whole state in memory.
#pragma once

#include <cstddef>
#include <cstdint>

#include "sable/io/hdf5_file.hpp"
#include "sable/world/world.hpp"

namespace sable {

// What state_hash(whole) returns for the World `whole` that the snapshot in `f` holds, as
// load_snapshot would restore it into a world of `like`'s contact law.
//
// Every per-grain and per-contact array (those state_hash_with hands to its callback) is read
// from `f`, at most `block_rows` rows at a time, never whole; everything else (walls and
// per-wall arrays, skin, domain, liquid totals, clock, random generator, and which optional
// arrays are hashed at all: bridges and films for a wet law, rolling springs, mesh elements)
// comes from `like`. `like`'s own grains and lists are never read: it may hold any share of
// them, or none.
//
// An optional dataset `like`'s law hashes but the file lacks (an older file, or one written
// under another law) hashes as load_snapshot restores it: '/particles/order_key' as the slots'
// order (row k is k), wall-pair elements and features as 0, bridges as kNoBridge, rolling
// springs as zero, films as none. (Such an old file's 'state_hash' attribute may not cover an
// order key: load_snapshot checks it with state_hash(world, false).)
//
// Throws InputError naming the file and dataset for a missing or malformed dataset, and
// std::invalid_argument for block_rows = 0.
template <int D>
std::uint64_t state_hash_of_file(const h5::File& f, const World<D>& like,
                                 std::size_t block_rows = 65536);

}  // namespace sable
