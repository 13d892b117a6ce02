// A preconditioner put around the KSP's own: the deflations
// (-solver_particle_deflation, -solver_ritz_deflation) take the multigrid as
// their inner M and add a coarse correction in a PETSc shell.
#pragma once

#include "lem/base/petsc_handle.hpp"

#include <petscksp.h>

namespace lem {

/// The solver of a deflation's coarse problem W^T K W: small, so factored
/// whole on every rank (redundant LU), under the prefix -deflation_coarse_
/// so that the main solver's -ksp_* options (a monitor, a converged reason)
/// do not reach it.
void create_coarse_solver(MPI_Comm comm, KspHandle& coarse);

class WrappedPreconditioner {
 public:
  WrappedPreconditioner(const WrappedPreconditioner&) = delete;
  WrappedPreconditioner& operator=(const WrappedPreconditioner&) = delete;

 protected:
  /// Put a shell named `name` that applies `apply` in the place of the KSP's
  /// preconditioner, which becomes inner_ (with a reference of our own).  At
  /// every set-up of the shell, inner_ gets the shell's operators and is
  /// built, then kept (reused) until the next set-up.
  WrappedPreconditioner(KSP ksp, const char* name, PetscErrorCode (*apply)(PC, Vec, Vec));
  ~WrappedPreconditioner();
  /// The object whose shell `pc` is, in an `apply`.
  template <class Wrapper>
  static PetscErrorCode context(PC pc, Wrapper** wrapper) {
    void* c = nullptr;
    PetscErrorCode ierr = PCShellGetContext(pc, &c);
    *wrapper = static_cast<Wrapper*>(static_cast<WrappedPreconditioner*>(c));
    return ierr;
  }

  PC inner_ = nullptr;

 private:
  static PetscErrorCode set_up(PC pc);
};

}  // namespace lem
