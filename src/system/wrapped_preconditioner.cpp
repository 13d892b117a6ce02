#include "wrapped_preconditioner.hpp"

#include "solver_defaults.hpp"

#include "lem/base/error.hpp"

namespace lem {

void create_coarse_solver(MPI_Comm comm, KspHandle& coarse) {
  LEM_PETSC(KSPCreate(comm, coarse.replace()));
  LEM_PETSC(KSPSetType(coarse, KSPPREONLY));
  LEM_PETSC(KSPSetOptionsPrefix(coarse, "deflation_coarse_"));
  PC pc = nullptr;
  LEM_PETSC(KSPGetPC(coarse, &pc));
  LEM_PETSC(PCSetType(pc, PCREDUNDANT));
  LEM_PETSC(KSPSetFromOptions(coarse));
}

WrappedPreconditioner::WrappedPreconditioner(KSP ksp, const char* name,
                                             PetscErrorCode (*apply)(PC, Vec, Vec)) {
  LEM_PETSC(KSPGetPC(ksp, &inner_));
  Mat A = nullptr, P = nullptr;  // the operators live in the PC: carried over
  LEM_PETSC(KSPGetOperators(ksp, &A, &P));
  LEM_PETSC(PetscObjectReference(reinterpret_cast<PetscObject>(A)));
  LEM_PETSC(PetscObjectReference(reinterpret_cast<PetscObject>(P)));
  LEM_PETSC(PetscObjectReference(reinterpret_cast<PetscObject>(inner_)));
  PC shell = nullptr;
  LEM_PETSC(PCCreate(PetscObjectComm(reinterpret_cast<PetscObject>(ksp)), &shell));
  LEM_PETSC(PCSetType(shell, PCSHELL));
  LEM_PETSC(PCShellSetName(shell, name));
  LEM_PETSC(PCShellSetContext(shell, this));
  LEM_PETSC(PCShellSetSetUp(shell, set_up));
  LEM_PETSC(PCShellSetApply(shell, apply));
  LEM_PETSC(KSPSetPC(ksp, shell));  // the KSP takes its own reference
  LEM_PETSC(PCDestroy(&shell));
  LEM_PETSC(KSPSetOperators(ksp, A, P));
  LEM_PETSC(MatDestroy(&A));
  LEM_PETSC(MatDestroy(&P));
}

WrappedPreconditioner::~WrappedPreconditioner() { PCDestroy(&inner_); }

PetscErrorCode WrappedPreconditioner::set_up(PC shell) {
  PetscFunctionBeginUser;
  WrappedPreconditioner* w = nullptr;
  PetscCall(context(shell, &w));
  Mat A = nullptr, P = nullptr;
  PetscCall(PCGetOperators(shell, &A, &P));
  PetscCall(PCSetReusePreconditioner(w->inner_, PETSC_FALSE));
  PetscCall(PCSetOperators(w->inner_, A, P));
  PetscCall(PCSetUp(w->inner_));
  PetscCall(apply_multigrid_level_defaults(w->inner_));
  // PCApply sets a PC up again whenever its matrix changed; K changes in
  // place after every batch of ruptures, and the multigrid is rebuilt only
  // when the outer KSP decides (reused between load steps).
  PetscCall(PCSetReusePreconditioner(w->inner_, PETSC_TRUE));
  PetscFunctionReturn(0);
}

}  // namespace lem
