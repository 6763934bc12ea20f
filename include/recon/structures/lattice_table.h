#pragma once
// The lattice hash table: the lattice corners a marching-cubes walk meets,
// numbered in the order they were first inserted.
//
// Textbook version: std::unordered_map<key, number>. This one does the same
// with an open-addressing table (linear probing) of 32-bit numbers over an
// array of the keys, which is smaller and faster, and hashes so that corners
// near each other in the lattice lie near each other in the table.
//
// Contract: keys are any 64-bit integers (normally Lattice<3>::key of a
// corner). insert(key) gives the key's slot, a new one (size() before the
// call) if the key was not there; find(key) gives the slot or `absent`;
// key(slot) gives the key back.
//
// Order: slots are numbered 0, 1, 2, ... in the order keys were first
// inserted, and never change (growing rehashes the table, not the slots), so
// callers keep what they know of a key in arrays indexed by slot.
//
// Memory: 8 bytes per key, plus 8 to 16 bytes per key for the table (at
// most half full; it doubles when it would be fuller, rehashing every key).
//
// Threads: find() and key() are safe from many threads at once while
// nothing is inserted; insert() is not.
//
// Hash: the corners of each 4 x 4 x 4 block of Lattice<3> stay together: the
// block is hashed, the place inside it is not. A cube's corners and its
// neighbours' then share a few cache lines of the table rather than one
// each (lookups are much of the walk's time once the table outgrows the
// caches; see docs/benchmarks.md).

#include "recon/structures/detail/block_array.h"
#include "recon/structures/lattice.h"

#include <cstdint>
#include <utility>
#include <vector>

namespace recon {

class LatticeTable {
 public:
  static constexpr std::uint32_t absent = UINT32_MAX;  ///< no such slot (also marks an empty table cell)

  [[nodiscard]] std::size_t size() const { return keys_.size(); }
  /// The table's cells (a power of two, at least twice size()).
  [[nodiscard]] std::size_t capacity() const { return table_.size(); }

  /// The slot of `key`, or `absent`.
  /// Cost: O(1) expected probes (the table is at most half full).
  /// Throws: nothing.
  /// Pre: none.
  [[nodiscard]] std::uint32_t find(std::uint64_t key) const {
    for (std::size_t h = hash(key);; h = (h + 1) & (table_.size() - 1)) {
      const std::uint32_t slot = table_[h];
      if (slot == absent || keys_[slot] == key) return slot;
    }
  }
  /// The key of a slot.
  /// Cost: O(1).
  /// Throws: nothing.
  /// Pre: slot < size().
  [[nodiscard]] std::uint64_t key(std::uint32_t slot) const { return keys_[slot]; }

  /// The slot of `key`, and whether it was added (as slot size() - 1).
  /// Cost: O(1) expected probes, amortised over the doublings that rehash every key.
  /// Throws: nothing.
  /// Pre: fewer than 2^32 - 1 keys so far (slots are 32-bit, and the largest value marks an empty cell).
  std::pair<std::uint32_t, bool> insert(std::uint64_t key) {
    if (2 * (keys_.size() + 1) > table_.size()) grow();
    std::size_t h = hash(key);
    for (; table_[h] != absent; h = (h + 1) & (table_.size() - 1))
      if (keys_[table_[h]] == key) return {table_[h], false};
    const auto slot = static_cast<std::uint32_t>(keys_.size());
    table_[h] = slot;
    keys_.push_back(key);
    return {slot, true};
  }

  /// Where `key` goes first in a table of 2^bits cells (bits >= 6).
  [[nodiscard]] static std::size_t hash(std::uint64_t key, int bits) {
    constexpr int b = Lattice<3>::key_bits;
    constexpr std::uint64_t low = 3u | (std::uint64_t{3} << b) | (std::uint64_t{3} << (2 * b));
    const std::uint64_t inside = (key & 3u) | ((key >> b) & 3u) << 2 | ((key >> (2 * b)) & 3u) << 4;
    const std::uint64_t block = ((key & ~low) * 0x9E3779B97F4A7C15ull) >> (64 - (bits - 6));
    return static_cast<std::size_t>((block << 6) | inside);
  }

 private:
  [[nodiscard]] std::size_t hash(std::uint64_t key) const { return hash(key, bits_); }
  void grow();  // doubles the table and puts every slot back

  std::vector<std::uint32_t> table_ = std::vector<std::uint32_t>(1024, absent);
  detail::BlockArray<std::uint64_t> keys_;
  int bits_ = 10;
};

}  // namespace recon
