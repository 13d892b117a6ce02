// Deflation of the soft directions of single nodes
// (-solver_soft_node_deflation).
//
// The spectrum probe of the paper-size sample after damage
// (docs/notes/slow-modes.md) finds the slowest mode of the
// multigrid-preconditioned K on one node held by three nearly coplanar
// bonds: the node moves normal to their plane at almost no cost, a direction
// the point-Jacobi smoother does not see (the node's diagonal holds its stiff
// bonds) and aggregation does not isolate.  Each such direction
// (lem/system/soft_nodes.hpp) is a column of a sparse W on its node; with
// Q = W (W^T K W)^-1 W^T and M the multigrid, the preconditioner is (I - Q K) M^-1 + Q and every solve starts
// from u + Q (b - K u) (the A-DEF2 form, as the per-particle deflation).  K W
// is kept as a sparse matrix formed from the soft nodes' bonds, so an
// iteration costs two small sparse products and a coarse solve, no product
// with K.  The space is found again whenever K changes (every batch of
// ruptures), at the cost of one pass over the local bonds.
#pragma once

#include "wrapped_preconditioner.hpp"

#include "lem/base/petsc_handle.hpp"
#include "lem/system/soft_nodes.hpp"

#include <petscksp.h>

#include <cstdint>
#include <vector>

namespace lem {

class SoftNodeDeflation : public WrappedPreconditioner {
 public:
  /// Wraps the KSP's current preconditioner (kept as the inner M) in a shell
  /// that applies the deflated one.  `K` is the assembled matrix.
  SoftNodeDeflation(const DistributedLattice& lattice, double ground, Mat K, KSP ksp,
                    double threshold);

  /// K changed (values or constraints): the space is found again before the
  /// next solve.
  void operator_changed() { stale_ = true; }
  /// Before KSPSolve on (b, u), after the preconditioner is set up: bring
  /// the space up to date and move u by Q (b - K u).
  void prepare(Vec b, Vec u);

 private:
  static PetscErrorCode shell_apply(PC pc, Vec r, Vec z);
  void build();
  void form_kw_transpose(const std::vector<SoftDirection>& soft, PetscInt first);
  void coarse_correction(Vec t, Vec out);  // out += W E^-1 t

  const DistributedLattice& lattice_;
  double ground_, threshold_;
  Mat K_;
  MatHandle W_, Wt_, KWt_, coarse_matrix_;
  KspHandle coarse_;
  VecHandle coarse_rhs_, coarse_other_, coarse_solution_, work_;
  bool stale_ = true;
  std::int64_t columns_ = 0;  // of the current space, all ranks
};

}  // namespace lem
