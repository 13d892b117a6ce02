#include "lem/system/pieces.hpp"

#include "lem/base/collective.hpp"
#include "lem/base/error.hpp"

#include <algorithm>
#include <limits>
#include <map>
#include <numeric>

namespace lem {
namespace {

class UnionFind {
 public:
  explicit UnionFind(int n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }
  int find(int x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  void unite(int a, int b) {
    a = find(a), b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<int> parent_;
};

constexpr double kPinnedLabel = std::numeric_limits<double>::max();

bool pinned(const DistributedLattice& l, int n) { return l.dof_flags[n] & kPinned; }

}  // namespace

PieceFinder::PieceFinder(const DistributedLattice& lattice) : lattice_(lattice) {
  std::vector<PetscInt> ghosts(lattice.global_index.begin() + lattice.owned,
                               lattice.global_index.end());
  LEM_PETSC(VecCreateGhost(lattice.comm, lattice.owned, PETSC_DECIDE,
                           static_cast<PetscInt>(ghosts.size()), ghosts.data(), &labels_));
}

PieceFinder::~PieceFinder() { VecDestroy(&labels_); }

std::vector<char> PieceFinder::underconnected() const {
  const DistributedLattice& l = lattice_;
  const int n_local = l.local_nodes();
  std::vector<char> out(n_local, 0);
  for (int n = 0; n < n_local; ++n) out[n] = pinned(l, n);
  std::vector<int> bonds(l.owned);
  for (;;) {
    std::fill(bonds.begin(), bonds.end(), 0);
    for (int b = 0; b < l.local_bonds(); ++b) {
      const auto [p, q] = l.bond_ends[b];
      if (l.bond_stiffness[b] <= 0 || out[p] || out[q]) continue;
      if (p < l.owned) ++bonds[p];
      if (q < l.owned) ++bonds[q];
    }
    int pruned = 0;
    for (int n = 0; n < l.owned; ++n) {
      if (out[n]) continue;
      const std::uint8_t f = l.dof_flags[n];
      const int free = !(f & kFixX) + !(f & kFixY) + !(f & kFixZ);
      if (bonds[n] < free) out[n] = 1, pruned = 1;
    }
    int any = 0;
    MPI_Allreduce(&pruned, &any, 1, MPI_INT, MPI_MAX, l.comm);
    if (!any) return out;
    // Ghost copies learn their owner's verdict.
    Vec local;
    LEM_PETSC(VecGhostGetLocalForm(labels_, &local));
    PetscScalar* v = nullptr;
    LEM_PETSC(VecGetArray(local, &v));
    for (int n = 0; n < l.owned; ++n) v[n] = out[n];
    LEM_PETSC(VecRestoreArray(local, &v));
    LEM_PETSC(VecGhostRestoreLocalForm(labels_, &local));
    LEM_PETSC(VecGhostUpdateBegin(labels_, INSERT_VALUES, SCATTER_FORWARD));
    LEM_PETSC(VecGhostUpdateEnd(labels_, INSERT_VALUES, SCATTER_FORWARD));
    LEM_PETSC(VecGhostGetLocalForm(labels_, &local));
    LEM_PETSC(VecGetArray(local, &v));
    for (int n = l.owned; n < n_local; ++n) out[n] = v[n] != 0;
    LEM_PETSC(VecRestoreArray(local, &v));
    LEM_PETSC(VecGhostRestoreLocalForm(labels_, &local));
  }
}

std::vector<std::int64_t> PieceFinder::labels(const std::vector<char>& excluded) const {
  const DistributedLattice& l = lattice_;
  const int n_local = l.local_nodes();
  UnionFind uf(n_local);
  for (int b = 0; b < l.local_bonds(); ++b) {
    const auto [p, q] = l.bond_ends[b];
    if (l.bond_stiffness[b] > 0 && !excluded[p] && !excluded[q]) uf.unite(p, q);
  }
  std::vector<int> root(n_local);
  for (int n = 0; n < n_local; ++n) root[n] = uf.find(n);

  std::vector<double> label(n_local);
  for (int n = 0; n < n_local; ++n)
    label[n] = excluded[n] ? kPinnedLabel : static_cast<double>(l.global_index[n]);
  // Rounds: smallest label within each local set, then across ranks.
  for (;;) {
    std::vector<double> best(n_local, kPinnedLabel);
    for (int n = 0; n < n_local; ++n) best[root[n]] = std::min(best[root[n]], label[n]);
    Vec local;
    LEM_PETSC(VecGhostGetLocalForm(labels_, &local));
    PetscScalar* v = nullptr;
    LEM_PETSC(VecGetArray(local, &v));
    for (int n = 0; n < n_local; ++n) v[n] = best[root[n]];
    LEM_PETSC(VecRestoreArray(local, &v));
    LEM_PETSC(VecGhostRestoreLocalForm(labels_, &local));
    LEM_PETSC(VecGhostUpdateBegin(labels_, MIN_VALUES, SCATTER_REVERSE));
    LEM_PETSC(VecGhostUpdateEnd(labels_, MIN_VALUES, SCATTER_REVERSE));
    LEM_PETSC(VecGhostUpdateBegin(labels_, INSERT_VALUES, SCATTER_FORWARD));
    LEM_PETSC(VecGhostUpdateEnd(labels_, INSERT_VALUES, SCATTER_FORWARD));
    int changed = 0;
    LEM_PETSC(VecGhostGetLocalForm(labels_, &local));
    const PetscScalar* w = nullptr;
    LEM_PETSC(VecGetArrayRead(local, &w));
    for (int n = 0; n < n_local; ++n) {
      if (w[n] != best[root[n]]) changed = 1;
      label[n] = w[n];
    }
    LEM_PETSC(VecRestoreArrayRead(local, &w));
    LEM_PETSC(VecGhostRestoreLocalForm(labels_, &local));
    int any = 0;
    MPI_Allreduce(&changed, &any, 1, MPI_INT, MPI_MAX, l.comm);
    if (!any) break;
  }
  std::vector<std::int64_t> out(n_local, -1);
  for (int n = 0; n < n_local; ++n)
    if (!excluded[n]) out[n] = static_cast<std::int64_t>(label[n]);
  return out;
}

PieceReport PieceFinder::find() const {
  const DistributedLattice& l = lattice_;
  const int n_local = l.local_nodes();
  // Under-connected nodes first: they count as pinned below.
  const std::vector<char> out = underconnected();
  auto excluded = [&](int n) { return out[n] != 0; };
  const std::vector<std::int64_t> label = labels(out);

  // Which faces each piece reaches, merged over the ranks (few pieces).
  enum : int { kBottom = 1, kTop = 2 };
  std::map<std::int64_t, int> reach;
  std::map<std::int64_t, std::int64_t> size;
  for (int n = 0; n < l.owned; ++n) {
    if (excluded(n)) continue;
    const std::int64_t piece = label[n];
    const std::uint8_t f = l.dof_flags[n];
    int bits = 0;
    if (f & kLoadedTop)
      bits |= kTop;
    else if (f & kFixZ)
      bits |= kBottom;
    reach[piece] |= bits;
    size[piece] += 1;
  }
  std::vector<std::int64_t> mine;
  for (const auto& [piece, bits] : reach) mine.insert(mine.end(), {piece, bits, size[piece]});
  const std::vector<std::int64_t> all = allgather(l.comm, mine);
  reach.clear();
  size.clear();
  for (std::size_t i = 0; i < all.size(); i += 3) {
    reach[all[i]] |= static_cast<int>(all[i + 1]);
    size[all[i]] += all[i + 2];
  }

  PieceReport report;
  report.pieces = static_cast<std::int64_t>(reach.size());
  for (const auto& [piece, bits] : reach) {
    if (bits == (kBottom | kTop)) {
      report.faces_joined = true;
    } else {
      report.loose_pieces += 1;
      report.loose_node_count += size[piece];
    }
  }
  for (int n = 0; n < n_local; ++n) {
    if (pinned(l, n)) continue;
    if (out[n]) {  // under-connected: carries no load
      report.loose_nodes.push_back(n);
      continue;
    }
    const auto it = reach.find(label[n]);
    // A ghost's piece is always known: the ghost's owner reported it.
    if (it == reach.end() || it->second != (kBottom | kTop)) report.loose_nodes.push_back(n);
  }
  return report;
}

}  // namespace lem
