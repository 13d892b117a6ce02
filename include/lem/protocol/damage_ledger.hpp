// The damage ledger: every change of the stiffness matrix as numbered
// batches of events (bonds broken, nodes pinned), and the batch after which
// each preconditioner build happened.  The ledger applies a batch to the
// system, records it, and replays a recorded history on a fresh system: the
// replay gives the same K (on any partition) and, on the same rank count,
// the same preconditioner, since PETSc's multigrid set-up continues a random
// stream from one build to the next.
#pragma once

#include "lem/system/distributed_lattice.hpp"
#include "lem/system/elastic_system.hpp"

#include <cstdint>
#include <unordered_map>
#include <vector>

namespace lem {

/// The history of matrix changes, identical on every rank.
struct DamageHistory {
  std::vector<std::int64_t> bond_events, bond_batches;  // broken bond ids, in order
  std::vector<std::int64_t> node_events, node_batches;  // pinned node ids, in order
  std::vector<std::int64_t> build_batches;  // every preconditioner build, after which batch
};

/// How much of the history existed at some point (a checkpoint's state).
struct DamageMark {
  std::size_t bonds = 0, nodes = 0, builds = 0;
};

class DamageLedger {
 public:
  DamageLedger(DistributedLattice& lattice, ElasticSystem& system);

  /// Start a new batch; the events recorded until the next one belong to it.
  std::int64_t open_batch();
  std::int64_t batches() const { return batches_; }

  /// Set k = 0 on these bonds (global ids, the same list on every rank) and
  /// record them in the current batch.
  void break_bonds(const std::vector<std::int64_t>& ids);
  /// Pin these nodes (global ids, the same list on every rank): their bonds
  /// are detached (k = 0, not counted as broken) and their rows constrained.
  /// Returns the number of bonds detached (global).  Collective.
  std::int64_t pin_nodes(const std::vector<std::int64_t>& ids);
  /// A preconditioner was built after the current batch.
  void record_build() { history_.build_batches.push_back(batches_); }

  /// Replay a recorded history of `batches` batches on the intact system,
  /// with every build at its place; the ledger then holds that history.
  /// Collective.
  void replay(DamageHistory history, std::int64_t batches);

  const DamageHistory& history() const { return history_; }
  DamageMark mark() const;
  /// The history as it was at `mark`.
  DamageHistory prefix(const DamageMark& mark) const;

 private:
  void apply(const std::vector<std::int64_t>& bonds, const std::vector<std::int64_t>& nodes);
  std::int64_t active_reported_bonds() const;

  DistributedLattice& lattice_;
  ElasticSystem& system_;
  std::unordered_map<std::int64_t, std::vector<int>> local_bonds_;  // id -> local copies
  std::unordered_map<std::int64_t, int> local_nodes_;
  DamageHistory history_;
  std::int64_t batches_ = 0;
};

}  // namespace lem
