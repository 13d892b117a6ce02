#include "soft_node_deflation.hpp"

#include "bond_operator.hpp"
#include "wrapped_preconditioner.hpp"

#include "lem/base/error.hpp"
#include "lem/system/tension.hpp"

#include <mpi.h>

#include <utility>

namespace lem {

SoftNodeDeflation::SoftNodeDeflation(const DistributedLattice& lattice, double ground, Mat K,
                                     KSP ksp, double threshold)
    : WrappedPreconditioner(ksp, "soft-node deflation", shell_apply),
      lattice_(lattice),
      ground_(ground),
      threshold_(threshold),
      K_(K) {
  create_coarse_solver(lattice_.comm, coarse_);
  LEM_PETSC(MatCreateVecs(K_, work_.replace(), nullptr));
}

// W from the soft directions, numbered rank by rank; K W and W^T K W formed
// by sparse products.
void SoftNodeDeflation::build() {
  const DistributedLattice& l = lattice_;
  const std::vector<SoftDirection> soft = find_soft_directions(l, ground_, threshold_);
  std::int64_t mine = static_cast<std::int64_t>(soft.size()), first = 0, total = 0;
  MPI_Exscan(&mine, &first, 1, MPI_INT64_T, MPI_SUM, l.comm);
  MPI_Allreduce(&mine, &total, 1, MPI_INT64_T, MPI_SUM, l.comm);
  int rank = 0;
  MPI_Comm_rank(l.comm, &rank);
  if (rank == 0) first = 0;
  columns_ = total;
  stale_ = false;
  W_.reset();
  Wt_.reset();
  KWt_.reset();
  coarse_matrix_.reset();
  LEM_PETSC(KSPReset(coarse_));
  if (total == 0) return;

  LEM_PETSC(MatCreateAIJ(l.comm, 3 * l.owned, static_cast<PetscInt>(mine), PETSC_DETERMINE,
                         static_cast<PetscInt>(total), 3, nullptr, 0, nullptr, W_.replace()));
  for (std::size_t j = 0; j < soft.size(); ++j) {
    const PetscInt column = static_cast<PetscInt>(first) + static_cast<PetscInt>(j);
    for (int a = 0; a < 3; ++a) {
      if (soft[j].vector[a] == 0.0) continue;
      const PetscInt row = 3 * static_cast<PetscInt>(l.global_index[soft[j].node]) + a;
      LEM_PETSC(MatSetValue(W_, row, column, soft[j].vector[a], INSERT_VALUES));
    }
  }
  LEM_PETSC(MatAssemblyBegin(W_, MAT_FINAL_ASSEMBLY));
  LEM_PETSC(MatAssemblyEnd(W_, MAT_FINAL_ASSEMBLY));
  // Products with the stored transposes: MatMultTranspose of a parallel AIJ
  // matrix is several times slower.
  LEM_PETSC(MatTranspose(W_, MAT_INITIAL_MATRIX, Wt_.replace()));
  form_kw_transpose(soft, static_cast<PetscInt>(first));
  LEM_PETSC(MatMatMult(KWt_, W_, MAT_INITIAL_MATRIX, PETSC_DEFAULT, coarse_matrix_.replace()));
  LEM_PETSC(KSPSetOperators(coarse_, coarse_matrix_, coarse_matrix_));
  LEM_PETSC(KSPSetUp(coarse_));
  LEM_PETSC(MatCreateVecs(W_, coarse_solution_.replace(), nullptr));
  LEM_PETSC(VecDuplicate(coarse_solution_, coarse_rhs_.replace()));
  LEM_PETSC(VecDuplicate(coarse_solution_, coarse_other_.replace()));
}

// (K W)^T row by row from the bonds of each soft node (all local: a rank
// holds every bond of its owned nodes): K w for a direction v on node n is
// sum_b k_b n_b (n_b . v) on n and -k_b n_b (n_b . v) on the bond's other
// end, on free dofs only, plus the ground spring on n.  Cheaper than a
// product with K, which would read all of it after every batch of ruptures.
void SoftNodeDeflation::form_kw_transpose(const std::vector<SoftDirection>& soft, PetscInt first) {
  const DistributedLattice& l = lattice_;
  // find_soft_directions lists a node's directions together: node n owns
  // the columns [first_of[n], first_of[n + 1]) of `soft`.
  std::vector<int> first_of(l.owned + 1, 0);
  for (const SoftDirection& d : soft) ++first_of[d.node + 1];
  for (int n = 0; n < l.owned; ++n) first_of[n + 1] += first_of[n];
  std::vector<PetscInt> per_row(soft.size(), 3);
  for (int b = 0; b < l.local_bonds(); ++b)
    for (const int node : l.bond_ends[b])
      if (node < l.owned)
        for (int j = first_of[node]; j < first_of[node + 1]; ++j) per_row[j] += 3;
  LEM_PETSC(MatCreateAIJ(l.comm, static_cast<PetscInt>(soft.size()), 3 * l.owned, PETSC_DETERMINE,
                         PETSC_DETERMINE, 0, per_row.data(), 0, per_row.data(), KWt_.replace()));
  auto add = [&](int j, int node, int a, double value) {
    if (is_fixed(l.dof_flags[node], a) || value == 0.0) return;
    const PetscInt row = first + j, column = 3 * static_cast<PetscInt>(l.global_index[node]) + a;
    LEM_PETSC(MatSetValue(KWt_, row, column, value, ADD_VALUES));
  };
  for (std::size_t j = 0; j < soft.size(); ++j)
    for (int a = 0; a < 3; ++a)
      add(static_cast<int>(j), soft[j].node, a, ground_ * soft[j].vector[a]);
  for (int b = 0; b < l.local_bonds(); ++b) {
    const double k = l.bond_stiffness[b];
    if (!(k > 0)) continue;
    double n[3];
    bond_direction(l, b, n);
    for (int e = 0; e < 2; ++e) {
      const int me = l.bond_ends[b][e], other = l.bond_ends[b][1 - e];
      if (me >= l.owned) continue;
      for (int j = first_of[me]; j < first_of[me + 1]; ++j) {
        const std::array<double, 3>& v = soft[j].vector;
        const double stretch = k * (n[0] * v[0] + n[1] * v[1] + n[2] * v[2]);
        for (int a = 0; a < 3; ++a) {
          add(j, me, a, stretch * n[a]);
          add(j, other, a, -stretch * n[a]);
        }
      }
    }
  }
  LEM_PETSC(MatAssemblyBegin(KWt_, MAT_FINAL_ASSEMBLY));
  LEM_PETSC(MatAssemblyEnd(KWt_, MAT_FINAL_ASSEMBLY));
}

void SoftNodeDeflation::coarse_correction(Vec t, Vec out) {
  LEM_PETSC(KSPSolve(coarse_, t, coarse_solution_));
  LEM_PETSC(MatMultAdd(W_, coarse_solution_, out, out));
}

void SoftNodeDeflation::prepare(Vec b, Vec u) {
  if (stale_) build();
  if (columns_ == 0) return;
  LEM_PETSC(MatMult(K_, u, work_));  // work = b - K u
  LEM_PETSC(VecAYPX(work_, -1.0, b));
  LEM_PETSC(MatMult(Wt_, work_, coarse_rhs_));
  coarse_correction(coarse_rhs_, u);
}

// z = y + W E^-1 (W^T r - (K W)^T y) with y = M^-1 r (K is symmetric).
PetscErrorCode SoftNodeDeflation::shell_apply(PC pc, Vec r, Vec z) {
  PetscFunctionBeginUser;
  SoftNodeDeflation* d = nullptr;
  PetscCall(context(pc, &d));
  PetscCall(PCApply(d->inner_, r, z));
  if (d->columns_ > 0 && !d->stale_) {
    PetscCall(MatMult(d->Wt_, r, d->coarse_rhs_));
    PetscCall(MatMult(d->KWt_, z, d->coarse_other_));
    PetscCall(VecAXPY(d->coarse_rhs_, -1.0, d->coarse_other_));
    try {
      d->coarse_correction(d->coarse_rhs_, z);
    } catch (const PetscFailure& e) {
      SETERRQ(PetscObjectComm(reinterpret_cast<PetscObject>(pc)), PETSC_ERR_LIB, "%s", e.what());
    }
  }
  PetscFunctionReturn(0);
}

}  // namespace lem
