// The elastic system's convergence test (ElasticSystem::ConvergenceTest):
// PETSc's own test, then the decided-solve stop and the near-tie
// tightening of one solve.  Private to src/system/elastic_system.cpp.
#pragma once

#include "lem/system/elastic_system.hpp"

#include <petscksp.h>

#include <exception>
#include <functional>

namespace lem {

// The KSP's own convergence test (as configured by KSPSetFromOptions), then,
// during a solve given an EarlyStop, that test every `interval`
// iterations.  The iterate of CG is the solution vector itself, updated in
// place, so the test sees it after a ghost update.  Exceptions cannot cross
// PETSc's C frames: they are kept and rethrown after KSPSolve.  Installed
// once at construction; the KSP owns it.
struct ElasticSystem::ConvergenceTest {
  using Fn = PetscErrorCode (*)(KSP, PetscInt, PetscReal, KSPConvergedReason*, void*);
  Fn inner = nullptr;
  void* inner_context = nullptr;
  PetscErrorCode (*inner_destroy)(void*) = nullptr;
  ElasticSystem* system = nullptr;
  const EarlyStop* early = nullptr;        // set for one solve
  const Tightening* tightening = nullptr;  // set for one solve
  PetscInt tightened_at = -1;              // the iteration it went on from, -1: not
  PetscReal tight_norm = 0;                // the residual norm it goes on to
  bool settled = false;                    // Tightening::settled ended it
  bool stopped = false;
  std::exception_ptr error;

  static PetscErrorCode test(KSP ksp, PetscInt it, PetscReal rnorm, KSPConvergedReason* reason,
                             void* ctx) {
    PetscFunctionBeginUser;
    auto* c = static_cast<ConvergenceTest*>(ctx);
    PetscCall(c->inner(ksp, it, rnorm, reason, c->inner_context));
    if (c->early && it == 0 && c->early->restart) c->early->restart();  // cannot throw
    if (c->tightening && (*reason > 0 || (c->tightened_at >= 0 && *reason == 0)))
      PetscCall(c->tighten(ksp, it, rnorm, reason));
    // A solve gone on for near-ties ends on their tolerance, an equilibrium
    // like the re-solve it replaces.
    if (!c->early || *reason != KSP_CONVERGED_ITERATING || it == 0 ||
        it % c->early->interval != 0 || c->tightened_at >= 0)
      PetscFunctionReturn(0);
    try {
      c->system->update_ghosts();
      if (c->early->decided()) {
        c->stopped = true;
        *reason = KSP_CONVERGED_ITS;
      }
    } catch (...) {
      c->error = std::current_exception();
      *reason = KSP_DIVERGED_BREAKDOWN;
    }
    PetscFunctionReturn(0);
  }
  // Met -ksp_rtol (the inner test's verdict): go on if the field wants the
  // Tightening's rtol, until the residual norm has fallen by the ratio of
  // the two tolerances (the inner test keeps its target from iteration 0,
  // so it cannot be lowered; the norm here is at most that target, so the
  // field ends at least as tight as a solve to the Tightening's rtol).
  PetscErrorCode tighten(KSP ksp, PetscInt it, PetscReal rnorm, KSPConvergedReason* reason) {
    PetscFunctionBeginUser;
    if (tightened_at < 0) {
      PetscReal rtol = 0;
      PetscCall(KSPGetTolerances(ksp, &rtol, nullptr, nullptr, nullptr));
      if (rtol <= tightening->rtol || !ask(tightening->wanted, reason)) PetscFunctionReturn(0);
      tightened_at = it;
      tight_norm = rnorm * (tightening->rtol / rtol);
    }
    if (rnorm <= tight_norm) {
      *reason = KSP_CONVERGED_RTOL;
      PetscFunctionReturn(0);
    }
    *reason = KSP_CONVERGED_ITERATING;
    if (tightening->settled && (it - tightened_at) % tightening->interval == 0 &&
        ask(tightening->settled, reason)) {
      settled = true;
      *reason = KSP_CONVERGED_RTOL;
    }
    PetscFunctionReturn(0);
  }
  // question(), on the current iterate; an exception is kept for after
  // KSPSolve and ends the solve.
  bool ask(const std::function<bool()>& question, KSPConvergedReason* reason) {
    try {
      system->update_ghosts();
      return question();
    } catch (...) {
      error = std::current_exception();
      *reason = KSP_DIVERGED_BREAKDOWN;
      return false;
    }
  }
  static PetscErrorCode destroy(void* ctx) {
    auto* c = static_cast<ConvergenceTest*>(ctx);
    const PetscErrorCode ierr = c->inner_destroy ? c->inner_destroy(c->inner_context) : 0;
    delete c;
    return ierr;
  }
};

}  // namespace lem
