// Deflation of slow Ritz vectors of the preconditioned operator, gathered
// from the solves themselves (-solver_ritz_deflation).
//
// The spectrum probe (-solver_spectrum_solves) of a damaged sample shows the
// slow modes of the multigrid-preconditioned K (docs/notes/slow-modes.md): a
// handful of Ritz values 10-1000 times below the bulk, carried by large
// parts of the sample moving nearly rigidly against each other and, after
// the peak, by small clusters of a few nodes held by soft bonds.  They change
// little from one solve to the next, so they are learnt as the run goes
// (in the spirit of eigCG, Stathopoulos & Orginos, SISC 32, 2010): during
// every CG solve the shell records the preconditioned residuals z_k and the
// step lengths (read from the iterate, which CG updates in place), which
// give the Lanczos vectors and tridiagonal of that solve; after it, its Ritz
// vectors with values below 0.1 join the columns of W (the oldest leave
// beyond `count`).  With Q = W (W^T K W)^-1 W^T and M the multigrid the
// preconditioner is (I - Q K) M^-1 + Q and every solve starts from
// u + Q (b - K u) (the A-DEF2 form, as the per-particle deflation).  K W is
// kept, so an iteration costs a few vector operations but no extra product
// with K; K W and W^T K W are formed again (count products) when K changes.
// W is what the run has learnt: a checkpoint keeps it (columns, restore), so
// that a resumed run solves as the uninterrupted one.
#pragma once

#include "lem/base/petsc_handle.hpp"
#include "lem/solver/wrapped_lever.hpp"

#include <petscksp.h>

#include <string>
#include <utility>
#include <vector>

namespace lem {

class RitzDeflation final : public WrappedLever {
 public:
  static constexpr const char* kType = "lem_ritz_deflation";
  static constexpr const char* kName = "Ritz-vector deflation";
  /// The registry entry: -solver_ritz_deflation N chooses it.
  static SolverLeverEntry entry();

  RitzDeflation() = default;
  /// K changed (values or constraints): K W and W^T K W are formed again
  /// before the next solve.
  void operator_changed() override { coarse_stale_ = true; }
  /// Before KSPSolve on (b, u), after the preconditioner is set up: bring
  /// the coarse operator up to date, move u by Q (b - K u) and start
  /// recording the solve (u must be the KSP's solution vector).
  void prepare(Vec b, Vec u) override;
  /// After KSPSolve: the Ritz vectors of the recorded solve join W.
  void after_solve() override { learn(); }
  std::vector<VecHandle> learnt_space() const override { return columns(); }
  void restore_learnt_space(std::vector<VecHandle> columns) override {
    restore(std::move(columns));
  }
  std::string learning_option() const override { return "-solver_ritz_deflation"; }
  void learn();
  /// Columns of W.
  int size() const { return static_cast<int>(W_.size()); }
  /// The columns of W, oldest first, shared with W: a column never changes
  /// once learnt (new ones join, old ones leave), so a holder sees the
  /// space of this moment.
  std::vector<VecHandle> columns() const;
  /// Start from these columns (a resumed run; the newest `count` of them):
  /// K W and W^T K W are formed before the next solve, as after any change
  /// of K.
  void restore(std::vector<VecHandle> columns);

 private:
  friend class WrappedLever;
  void wrapped(const LeverSite& site) override;
  static PetscErrorCode apply(PC pc, Vec r, Vec z);
  void record(Vec r, Vec z);
  void form_coarse();
  void coarse_solve(std::vector<PetscScalar>& t) const;  // t = E^-1 t

  Mat K_ = nullptr;
  int count_ = 0;
  std::vector<VecHandle> W_, KW_;
  std::vector<Vec> w_, kw_;     // the same, for PETSc's multi-vector calls
  std::vector<double> factor_;  // lower Cholesky factor of E = W^T K W
  VecHandle work_;
  mutable std::vector<PetscScalar> t_, s_;
  bool coarse_stale_ = true;

  // The recording of one solve.
  bool recording_ = false;
  Vec x_ = nullptr;  // CG's iterate (the solution vector)
  Vec rhs_ = nullptr;
  VecHandle x_last_, p_;
  std::vector<VecHandle> lanczos_;  // z_k / sqrt(rho_k)
  std::vector<double> alpha_, beta_;
  double rho_last_ = 0;
};

}  // namespace lem
