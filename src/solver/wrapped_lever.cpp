#include "lem/solver/wrapped_lever.hpp"

#include "petsc318_private.hpp"

#include "lem/base/error.hpp"

#include <exception>

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

PetscErrorCode WrappedLever::define(PC pc, WrappedLever* lever,
                                    PetscErrorCode (*apply)(PC, Vec, Vec), const char* name) {
  PetscFunctionBeginUser;
  lever->name_ = name;
  PcOperations ops;
  ops.setup = set_up;
  ops.apply = apply;
  ops.destroy = destroy;
  ops.view = view;
  try {
    define_pc_type(pc, lever, ops);
    attach_lever(pc, lever);
  } catch (...) {
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_LIB, "could not make the lever's PC");
  }
  PetscFunctionReturn(0);
}

WrappedLever* WrappedLever::of(PC pc) {
  return static_cast<WrappedLever*>(static_cast<SolverLever*>(pc_type_data(pc)));
}

void WrappedLever::wrap(const LeverSite& site, PC inner) {
  LEM_PETSC(PetscObjectReference(reinterpret_cast<PetscObject>(inner)));
  inner_ = inner;
  wrapped(site);
}

WrappedLever::~WrappedLever() { PCDestroy(&inner_); }

PetscErrorCode WrappedLever::destroy(PC pc) {
  PetscFunctionBeginUser;
  delete of(pc);
  clear_pc_type_data(pc);
  PetscFunctionReturn(0);
}

PetscErrorCode WrappedLever::view(PC pc, PetscViewer viewer) {
  PetscFunctionBeginUser;
  WrappedLever* w = of(pc);
  PetscBool ascii = PETSC_FALSE;
  PetscCall(
      PetscObjectTypeCompare(reinterpret_cast<PetscObject>(viewer), PETSCVIEWERASCII, &ascii));
  if (ascii) PetscCall(PetscViewerASCIIPrintf(viewer, "  %s around:\n", w->name_));
  if (ascii && w->inner_) {
    PetscCall(PetscViewerASCIIPushTab(viewer));
    PetscCall(PCView(w->inner_, viewer));
    PetscCall(PetscViewerASCIIPopTab(viewer));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode WrappedLever::set_up(PC pc) {
  PetscFunctionBeginUser;
  WrappedLever* w = of(pc);
  PetscCheck(w->inner_, PetscObjectComm(reinterpret_cast<PetscObject>(pc)),
             PETSC_ERR_ARG_WRONGSTATE,
             "a lever wraps the preconditioner of the elastic system: choose it with its -solver_* "
             "option, not with -pc_type");
  Mat A = nullptr, P = nullptr;
  PetscCall(PCGetOperators(pc, &A, &P));
  PetscCall(PCSetReusePreconditioner(w->inner_, PETSC_FALSE));
  PetscCall(PCSetOperators(w->inner_, A, P));
  PetscCall(PCSetUp(w->inner_));
  PetscCall(apply_multigrid_level_defaults(w->inner_));
  // PCApply sets a PC up again whenever its matrix changed; K changes in
  // place after every batch of ruptures, and the multigrid is rebuilt only
  // when the outer KSP decides (reused between load steps).
  PetscCall(PCSetReusePreconditioner(w->inner_, PETSC_TRUE));
  try {
    w->inner_built();
  } catch (const std::exception& e) {
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_LIB, "%s", e.what());
  }
  PetscFunctionReturn(0);
}

}  // namespace lem
