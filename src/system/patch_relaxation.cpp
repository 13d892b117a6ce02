// Patch solves of the elastic system (ElasticSystem::relax_patch): the
// local relaxation of the fracture protocol relaxes a few nodes with the
// rest held.
#include "lem/system/elastic_system.hpp"

#include "lem/base/error.hpp"
#include "lem/system/tension.hpp"

#include <limits>
#include <vector>

namespace lem {

SolveReport ElasticSystem::relax_patch(const std::vector<int>& owned_nodes, double rtol) {
  const MPI_Comm comm = lattice_.comm;
  SolveReport report;
  const double t0 = MPI_Wtime();
  // Out-of-balance forces of the current state.
  assemble_rhs(current_displacement_);
  Vec r = nullptr;
  LEM_PETSC(VecDuplicate(b_, &r));
  LEM_PETSC(MatMult(K_, u_, r));
  LEM_PETSC(VecAYPX(r, -1.0, b_));
  std::vector<PetscInt> rows;
  for (int n : owned_nodes)
    for (int a = 0; a < 3; ++a)
      if (!is_fixed(lattice_.dof_flags[n], a))
        rows.push_back(3 * static_cast<PetscInt>(lattice_.global_index[n]) + a);
  IS is = nullptr;
  LEM_PETSC(ISCreateGeneral(comm, static_cast<PetscInt>(rows.size()), rows.data(),
                            PETSC_COPY_VALUES, &is));
  Mat patch = nullptr;
  LEM_PETSC(MatCreateSubMatrix(K_, is, is, MAT_INITIAL_MATRIX, &patch));
  Vec rhs = nullptr, du = nullptr;
  LEM_PETSC(VecGetSubVector(r, is, &rhs));
  LEM_PETSC(VecDuplicate(rhs, &du));
  KSP ksp = create_patch_solver(comm, rtol);
  LEM_PETSC(KSPSetOperators(ksp, patch, patch));
  LEM_PETSC(KSPSolve(ksp, rhs, du));
  PetscInt its = 0;
  LEM_PETSC(KSPGetIterationNumber(ksp, &its));
  LEM_PETSC(KSPGetConvergedReason(ksp, &report.reason));
  report.iterations = static_cast<int>(its);
  LEM_PETSC(VecRestoreSubVector(r, is, &rhs));
  if (report.reason > 0) {
    Vec u_patch = nullptr;
    LEM_PETSC(VecGetSubVector(u_, is, &u_patch));
    LEM_PETSC(VecAXPY(u_patch, 1.0, du));
    LEM_PETSC(VecRestoreSubVector(u_, is, &u_patch));
    update_ghosts();
    equilibrium_ = false;
    field_rtol_ = std::numeric_limits<double>::infinity();
    ties_settled_ = false;
    u_check_.reset();  // a patch field has no certificate: it cannot be rescaled
  }
  LEM_PETSC(KSPDestroy(&ksp));
  LEM_PETSC(VecDestroy(&du));
  LEM_PETSC(MatDestroy(&patch));
  LEM_PETSC(ISDestroy(&is));
  LEM_PETSC(VecDestroy(&r));
  report.solve_seconds = MPI_Wtime() - t0;
  return report;
}

}  // namespace lem
