// K applied bond by bond (-solver_operator bonds): a PETSc MATSHELL whose
// product is y = sum_b k_b n_b n_b^T (x_i - x_j) on free dofs, plus the
// ground spring there and the constrained scale on fixed dofs, exactly the
// values the assembled K holds.  It reads per bond two 32-bit node indices,
// k and the unit direction (40 bytes, structure of arrays, bonds sorted by
// their first end), about a sixth of what an AIJ MatMult reads per bond.
#pragma once

#include "lem/system/distributed_lattice.hpp"
#include "lem/base/petsc_handle.hpp"

#include <petscmat.h>

#include <cstdint>
#include <vector>

namespace lem {

class BondOperator {
 public:
  /// `ground` on free dofs, `scale` on fixed ones, as ElasticSystem assembles.
  BondOperator(const DistributedLattice& lattice, double ground, double scale);
  BondOperator(const BondOperator&) = delete;
  BondOperator& operator=(const BondOperator&) = delete;

  /// The shell matrix (owned by this object).
  Mat matrix() const { return shell_; }
  /// A local bond's stiffness changed (rupture): effective at once.
  void set_stiffness(int local_bond, double k) { k_[slot_[local_bond]] = k; }
  /// Read every stiffness from the lattice again (assemble()).
  void read_stiffness();
  /// The lattice's dof flags changed (pinned nodes): read them again.
  void constraints_changed();

  void multiply(Vec x, Vec y) const;
  void diagonal(Vec d) const;
  /// Bytes one multiply() reads and writes: the bond arrays, x with its
  /// ghosts gathered, the local accumulator written and read back, y written.
  double bytes_per_multiply() const;

 private:
  const DistributedLattice& lattice_;
  double ground_, scale_;
  std::vector<std::int32_t> i_, j_;  // local node indices, sorted by i
  std::vector<double> k_, nx_, ny_, nz_;
  std::vector<std::int32_t> slot_;   // local bond -> position in the arrays
  std::vector<double> free_;         // 1 on free local dofs, 0 on fixed
  VecHandle x_ghosted_;              // x with fixed dofs zeroed, then ghosts
  mutable std::vector<double> acc_;  // 3 per local node
  MatHandle shell_;
};

}  // namespace lem
