#include "lem/protocol/damage_ledger.hpp"

#include "lem/base/collective.hpp"
#include "lem/base/error.hpp"

#include <algorithm>
#include <string>

namespace lem {

DamageLedger::DamageLedger(DistributedLattice& l, ElasticSystem& s) : lattice_(l), system_(s) {
  for (int b = 0; b < l.local_bonds(); ++b) local_bonds_[l.bond_id[b]].push_back(b);
  for (int n = 0; n < l.local_nodes(); ++n) local_nodes_[l.node_id[n]] = n;
}

std::int64_t DamageLedger::open_batch() { return ++batches_; }

void DamageLedger::break_bonds(const std::vector<std::int64_t>& ids) {
  for (std::int64_t id : ids) {
    history_.bond_events.push_back(id);
    history_.bond_batches.push_back(batches_);
  }
  apply(ids, {});
}

std::int64_t DamageLedger::active_reported_bonds() const {
  std::int64_t n = 0;
  for (int b = 0; b < lattice_.local_bonds(); ++b)
    n += lattice_.bond_reported[b] && lattice_.bond_stiffness[b] > 0;
  return n;
}

std::int64_t DamageLedger::pin_nodes(const std::vector<std::int64_t>& ids) {
  for (std::int64_t id : ids) {
    history_.node_events.push_back(id);
    history_.node_batches.push_back(batches_);
  }
  const std::int64_t before = active_reported_bonds();
  apply({}, ids);
  std::int64_t detached = before - active_reported_bonds(), total = 0;
  MPI_Allreduce(&detached, &total, 1, MPI_INT64_T, MPI_SUM, lattice_.comm);
  return total;
}

void DamageLedger::apply(const std::vector<std::int64_t>& bonds,
                         const std::vector<std::int64_t>& nodes) {
  for (std::int64_t id : bonds) {
    const auto it = local_bonds_.find(id);
    if (it == local_bonds_.end()) continue;
    for (int b : it->second) system_.set_bond_stiffness(b, 0.0);
  }
  if (nodes.empty()) return;
  std::vector<char> pin(lattice_.local_nodes(), 0);
  std::vector<int> local;
  for (std::int64_t id : nodes) {
    const auto it = local_nodes_.find(id);
    if (it == local_nodes_.end()) continue;
    pin[it->second] = 1;
    local.push_back(it->second);
  }
  std::sort(local.begin(), local.end());
  // Detach the bonds of the pinned pieces (no load: not counted as broken).
  for (int b = 0; b < lattice_.local_bonds(); ++b) {
    const auto [p, q] = lattice_.bond_ends[b];
    if (lattice_.bond_stiffness[b] > 0 && (pin[p] || pin[q])) system_.set_bond_stiffness(b, 0.0);
  }
  system_.pin_nodes(local);
}

void DamageLedger::replay(DamageHistory h, std::int64_t batches) {
  // A recorded bond id that is no bond of this system would be skipped
  // silently (another fracture): each must be reported by exactly one rank.
  std::vector<int> held(h.bond_events.size(), 0), total(held.size(), 0);
  for (std::size_t k = 0; k < held.size(); ++k) {
    const auto it = local_bonds_.find(h.bond_events[k]);
    if (it != local_bonds_.end())
      for (int b : it->second) held[k] += lattice_.bond_reported[b] ? 1 : 0;
  }
  // MPI counts are int: a history of more than 2^31 events goes in pieces.
  in_pieces(held.size(), kMpiPieceBytes / sizeof(int), [&](std::uint64_t at, int count) {
    MPI_Allreduce(held.data() + at, total.data() + at, count, MPI_INT, MPI_SUM, lattice_.comm);
  });
  const auto foreign = std::find_if(total.begin(), total.end(), [](int n) { return n != 1; });
  if (foreign != total.end()) {
    const auto k = static_cast<std::size_t>(foreign - total.begin());
    throw InputError("the damage history to resume from (the checkpoint) breaks bond " +
                     std::to_string(h.bond_events[k]) + " (its bond event " + std::to_string(k) +
                     "), which is not a bond of this sample's system");
  }
  std::size_t ib = 0, in = 0, ip = 0;
  auto builds_after = [&](std::int64_t batch) {
    for (; ip < h.build_batches.size() && h.build_batches[ip] == batch; ++ip)
      system_.build_preconditioner();
  };
  builds_after(0);
  for (std::int64_t batch = 1; batch <= batches; ++batch) {
    std::vector<std::int64_t> bonds, nodes;
    for (; ib < h.bond_events.size() && h.bond_batches[ib] == batch; ++ib)
      bonds.push_back(h.bond_events[ib]);
    for (; in < h.node_events.size() && h.node_batches[in] == batch; ++in)
      nodes.push_back(h.node_events[in]);
    apply(bonds, nodes);
    system_.finish_updates();
    builds_after(batch);
  }
  history_ = std::move(h);
  batches_ = batches;
}

DamageMark DamageLedger::mark() const {
  return {history_.bond_events.size(), history_.node_events.size(), history_.build_batches.size()};
}

DamageHistory DamageLedger::prefix(const DamageMark& m) const {
  auto head = [](const std::vector<std::int64_t>& v, std::size_t n) {
    return std::vector<std::int64_t>(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(n));
  };
  const DamageHistory& h = history_;
  return {head(h.bond_events, m.bonds), head(h.bond_batches, m.bonds), head(h.node_events, m.nodes),
          head(h.node_batches, m.nodes), head(h.build_batches, m.builds)};
}

}  // namespace lem
