// A coarse space of per-particle rigid-body modes deflated around the
// preconditioner of the elastic system (-solver_particle_deflation).
//
// In a porous cemented sample the stiff particles are held together by a few
// soft bridges: every particle moving as a rigid body is a near-null mode of
// K that aggregation multigrid does not see, and CG needs several times the
// iterations of a well-cemented sample.  Each particle's three translations
// and three rotations (about its node centroid, over its free degrees of
// freedom, orthonormalised per particle, nearly dependent ones dropped) form
// the columns of W; with Q = W (W^T K W)^-1 W^T and M the multigrid, the
// preconditioner is (I - Q K) M^-1 + Q and every solve starts from
// u + Q (b - K u): the "A-DEF2" form of Tang, Nabben, Vuik & Erlangga
// (J. Sci. Comput. 39, 2009), which stays robust when M is kept for several
// operators.  W^T K W is small (6 unknowns per particle) and is formed and
// factored again whenever K changes.
#pragma once

#include "lem/solver/wrapped_lever.hpp"

#include "lem/base/petsc_handle.hpp"
#include "lem/system/distributed_lattice.hpp"

#include <petscksp.h>

namespace lem {

class ParticleDeflation final : public WrappedLever {
 public:
  static constexpr const char* kType = "lem_particle_deflation";
  static constexpr const char* kName = "per-particle rigid-body deflation";
  /// The registry entry: -solver_particle_deflation chooses it.
  static SolverLeverEntry entry();

  ParticleDeflation() = default;
  /// K changed in place (values only): the coarse operator is formed again
  /// before the next solve.
  void operator_changed() override { coarse_stale_ = true; }
  /// Degrees of freedom were constrained (pinned nodes): W is built again.
  void constraints_changed() override { space_stale_ = true; }
  /// Before a solve, after the preconditioner is set up: bring the coarse
  /// operator up to date and move the initial guess u by Q (b - K u).
  void prepare(Vec b, Vec u) override;

 private:
  friend class WrappedLever;
  /// Throws InputError if the lattice has no particles.
  void wrapped(const LeverSite& site) override;
  static PetscErrorCode apply(PC pc, Vec r, Vec z);
  void build_space();
  void form_coarse();
  void apply_q(Vec v, Vec out);  // out = Q v

  const DistributedLattice* lattice_ = nullptr;
  Mat K_ = nullptr;
  MatHandle W_, Wt_, coarse_matrix_;
  KspHandle coarse_;
  VecHandle coarse_rhs_, coarse_solution_, work_, work2_;
  bool space_stale_ = true, coarse_stale_ = true;
  bool announced_ = false;  // the size of the space is said once
};

}  // namespace lem
