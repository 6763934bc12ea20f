#include "recon/structures/lattice_table.h"

namespace recon {

void LatticeTable::grow() {
  table_.assign(table_.size() * 2, absent);
  ++bits_;
  for (std::uint32_t slot = 0; slot < keys_.size(); ++slot) {
    std::size_t h = hash(keys_[slot]);
    while (table_[h] != absent) h = (h + 1) & (table_.size() - 1);
    table_[h] = slot;
  }
}

}  // namespace recon
