#pragma once
// What an algorithm did, counted: the figures the alternatives lab (lab.h)
// prints beside each run's time. A counter that does not apply to a run
// stays 0. Counting is done only by the instrumented versions the lab calls
// (a CountingQueue, a counted search): the default paths count nothing.

#include <cstdint>

namespace recon {

struct OperationCounts {
  // priority queue (Prim)
  std::uint64_t pushes = 0;
  std::uint64_t pops = 0;
  std::uint64_t decrease_keys = 0;
  std::uint64_t comparisons = 0;  ///< key comparisons inside the queue
  // union-find (Kruskal, Borůvka)
  std::uint64_t finds = 0;
  std::uint64_t unions = 0;
  // neighbour searches, the complete graph
  std::uint64_t distance_evaluations = 0;  ///< squared distances between two points computed
  // Borůvka
  std::uint64_t rounds = 0;

  OperationCounts& operator+=(const OperationCounts& o) {
    pushes += o.pushes;
    pops += o.pops;
    decrease_keys += o.decrease_keys;
    comparisons += o.comparisons;
    finds += o.finds;
    unions += o.unions;
    distance_evaluations += o.distance_evaluations;
    rounds += o.rounds;
    return *this;
  }
  friend bool operator==(const OperationCounts&, const OperationCounts&) = default;
};

}  // namespace recon
