// A lever that wraps the multigrid (or another lever): the deflations
// (-solver_particle_deflation, -solver_ritz_deflation) take it as their
// inner M and add a coarse correction.  This class is the PETSc side of
// such a lever, written once: the PC type's operations (set-up, apply,
// destroy, view), the set-up that keeps the inner preconditioner between
// builds, and the coarse solver of a deflation.
#pragma once

#include "lem/base/petsc_handle.hpp"
#include "lem/system/solver_lever.hpp"

#include <petscksp.h>

#include <functional>
#include <string>
#include <utility>

namespace lem {

/// The solver of a deflation's coarse problem W^T K W: small, so factored
/// whole on every rank (redundant LU), under the prefix -deflation_coarse_
/// so that the main solver's -ksp_* options (a monitor, a converged reason)
/// do not reach it.
void create_coarse_solver(MPI_Comm comm, KspHandle& coarse);

class WrappedLever : public SolverLever {
 public:
  WrappedLever(const WrappedLever&) = delete;
  WrappedLever& operator=(const WrappedLever&) = delete;
  ~WrappedLever() override;
  /// Keeps `inner` (a reference of its own), then calls wrapped().
  void wrap(const LeverSite& site, PC inner) final;

  /// PETSc's create function of a lever type (PCRegister): the PC gets a
  /// new Lever, whose static `apply(PC, Vec r, Vec z)` is the PC's apply.
  template <class Lever>
  static PetscErrorCode create(PC pc) {
    return define(pc, new Lever, Lever::apply, Lever::kName);
  }
  /// The registry entry of a lever of type Lever::kType, chosen by `option`
  /// (read by `read`; see SolverLeverEntry).
  template <class Lever>
  static SolverLeverEntry entry(std::string option, std::function<double(OptionGroup&)> read,
                                std::string excludes = "") {
    return {Lever::kType, create<Lever>, std::move(option), std::move(read), std::move(excludes)};
  }

 protected:
  WrappedLever() = default;
  /// The lever's own set-up, once the inner preconditioner is kept.
  virtual void wrapped(const LeverSite& site) = 0;
  /// After each build of the inner preconditioner (the PC's set-up), for a
  /// lever that copies what the build made.  May throw.
  virtual void inner_built() {}
  /// The lever whose PC `pc` is, in an `apply`.
  template <class Lever>
  static PetscErrorCode context(PC pc, Lever** lever) {
    *lever = static_cast<Lever*>(of(pc));
    return 0;
  }

  PC inner_ = nullptr;

 private:
  static PetscErrorCode define(PC pc, WrappedLever* lever, PetscErrorCode (*apply)(PC, Vec, Vec),
                               const char* name);
  static WrappedLever* of(PC pc);
  static PetscErrorCode set_up(PC pc);
  static PetscErrorCode destroy(PC pc);
  static PetscErrorCode view(PC pc, PetscViewer viewer);

  const char* name_ = "";
};

}  // namespace lem
