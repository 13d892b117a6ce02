#include "particle_deflation.hpp"

#include "lem/base/error.hpp"
#include "lem/base/log.hpp"
#include "lem/system/tension.hpp"

#include <mpi.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace lem {
namespace {

using Modes = std::array<double, 6>;

// The six rigid-body modes of a particle at one degree of freedom (axis a) of
// a node at offset x from the particle's centroid: translation e_m for m < 3,
// rotation (e_{m-3} x x)_a for m >= 3.
Modes rigid_modes(const double x[3], int a) {
  Modes m{};
  m[a] = 1.0;
  const int b = (a + 1) % 3, c = (a + 2) % 3;
  m[3 + b] = x[c];   // (e_b x x)_a = +x_c for (a, b, c) cyclic
  m[3 + c] = -x[b];  // (e_c x x)_a = -x_b
  return m;
}

// Combinations of a particle's six modes orthonormal over its free degrees
// of freedom, from their Gram matrix G (Gram-Schmidt in the G metric,
// twice); a mode that adds less than 1e-6 of its own norm (a particle cut by
// a face, a handful of nodes in a line) is dropped, so that W^T K W stays
// regular.
std::vector<Modes> orthonormal_modes(const double* G) {
  auto dot = [G](const Modes& u, const Modes& v) {
    double s = 0;
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j) s += u[i] * G[6 * i + j] * v[j];
    return s;
  };
  std::vector<Modes> basis;
  for (int j = 0; j < 6; ++j) {
    if (G[7 * j] <= 0) continue;
    Modes v{};
    v[j] = 1.0;
    for (int pass = 0; pass < 2; ++pass)
      for (const Modes& b : basis) {
        const double c = dot(b, v);
        for (int i = 0; i < 6; ++i) v[i] -= c * b[i];
      }
    const double norm2 = dot(v, v);
    if (norm2 < 1e-6 * G[7 * j]) continue;
    for (double& c : v) c /= std::sqrt(norm2);
    basis.push_back(v);
  }
  return basis;
}

}  // namespace

SolverLeverEntry ParticleDeflation::entry() {
  return WrappedLever::entry<ParticleDeflation>(
      "-solver_particle_deflation",
      [](OptionGroup& g) -> double {
        return g.flag("-solver_particle_deflation",
                      "Deflate the six rigid-body modes of every "
                      "particle around the preconditioner (a coarse space of 6 unknowns per "
                      "particle, solved exactly).  For porous cemented samples, where stiff "
                      "particles joined by a few soft bridges make CG slow "
                      "(docs/benchmarks.md); needs a cemented sample",
                      false)
                   ? 1
                   : 0;
      },
      "one deflation space");
}

void ParticleDeflation::wrapped(const LeverSite& site) {
  lattice_ = &site.lattice;
  K_ = site.K;
  int has = lattice_->node_particle.empty() ? 0 : 1, any = 0;
  MPI_Allreduce(&has, &any, 1, MPI_INT, MPI_MAX, lattice_->comm);
  if (!any)
    throw InputError("-solver_particle_deflation needs the particle of every node: use a "
                     "cemented sample (-sample_file or -sample_*), not a plain lattice");
  // CG keeps its operator (-solver_operator): handing it K here made the
  // first preconditioner's solves multiply by K and later ones by the bond
  // operator, so a resumed run (whose builds all set the operator) parted
  // from the uninterrupted one in the last bits.

  create_coarse_solver(lattice_->comm, coarse_);
  LEM_PETSC(MatCreateVecs(K_, work_.replace(), nullptr));
  LEM_PETSC(VecDuplicate(work_, work2_.replace()));
}

// W from the particles' nodes; columns numbered particle by particle, so the
// space does not depend on the number of ranks.
void ParticleDeflation::build_space() {
  const DistributedLattice& l = *lattice_;
  std::int32_t last = -1;
  for (int n = 0; n < l.owned; ++n) last = std::max(last, l.node_particle[n]);
  std::int32_t particles = 0;
  const std::int32_t mine = last + 1;
  MPI_Allreduce(&mine, &particles, 1, MPI_INT32_T, MPI_MAX, l.comm);

  // Centroid of each particle's nodes.
  std::vector<double> sums(4 * static_cast<std::size_t>(particles), 0.0);
  for (int n = 0; n < l.owned; ++n) {
    const std::int32_t p = l.node_particle[n];
    if (p < 0) continue;
    for (int a = 0; a < 3; ++a) sums[4 * p + a] += l.coords[n][a];
    sums[4 * p + 3] += 1;
  }
  MPI_Allreduce(MPI_IN_PLACE, sums.data(), static_cast<int>(sums.size()), MPI_DOUBLE, MPI_SUM,
                l.comm);
  auto offset = [&](int n, double x[3]) {
    const std::int32_t p = l.node_particle[n];
    for (int a = 0; a < 3; ++a) x[a] = l.coords[n][a] - sums[4 * p + a] / sums[4 * p + 3];
  };

  // visit(node, axis, particle, modes) for every free degree of freedom of
  // an owned node inside a particle.
  auto for_each_free_dof = [&](auto&& visit) {
    for (int n = 0; n < l.owned; ++n) {
      const std::int32_t p = l.node_particle[n];
      if (p < 0) continue;
      double x[3];
      offset(n, x);
      for (int a = 0; a < 3; ++a)
        if (!is_fixed(l.dof_flags[n], a)) visit(n, a, p, rigid_modes(x, a));
    }
  };

  // Gram matrix of each particle's modes over its free degrees of freedom.
  std::vector<double> gram(36 * static_cast<std::size_t>(particles), 0.0);
  for_each_free_dof([&](int, int, std::int32_t p, const Modes& m) {
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j) gram[36 * p + 6 * i + j] += m[i] * m[j];
  });
  MPI_Allreduce(MPI_IN_PLACE, gram.data(), static_cast<int>(gram.size()), MPI_DOUBLE, MPI_SUM,
                l.comm);

  std::vector<std::vector<Modes>> basis(particles);
  for (std::int32_t p = 0; p < particles; ++p)
    basis[p] = orthonormal_modes(&gram[36 * static_cast<std::size_t>(p)]);
  std::vector<PetscInt> first(particles + 1, 0);
  for (std::int32_t p = 0; p < particles; ++p)
    first[p + 1] = first[p] + static_cast<PetscInt>(basis[p].size());
  const PetscInt coarse_size = first[particles];
  if (!announced_) {
    const auto held = std::count_if(basis.begin(), basis.end(),
                                    [](const std::vector<Modes>& b) { return !b.empty(); });
    say("per-particle deflation: %lld coarse unknowns for the %lld particles in the box\n",
        static_cast<long long>(coarse_size), static_cast<long long>(held));
    announced_ = true;
  }

  int rank = 0, size = 1;
  MPI_Comm_rank(l.comm, &rank);
  MPI_Comm_size(l.comm, &size);
  const PetscInt local_columns = coarse_size / size + (rank < coarse_size % size ? 1 : 0);
  LEM_PETSC(MatCreateAIJ(l.comm, 3 * l.owned, local_columns, PETSC_DETERMINE, coarse_size, 6,
                         nullptr, 6, nullptr, W_.replace()));
  for_each_free_dof([&](int n, int a, std::int32_t p, const Modes& m) {
    const PetscInt row = 3 * static_cast<PetscInt>(l.global_index[n]) + a;
    for (std::size_t i = 0; i < basis[p].size(); ++i) {
      double value = 0;
      for (int k = 0; k < 6; ++k) value += m[k] * basis[p][i][k];
      const PetscInt column = first[p] + static_cast<PetscInt>(i);
      LEM_PETSC(MatSetValues(W_, 1, &row, 1, &column, &value, INSERT_VALUES));
    }
  });
  LEM_PETSC(MatAssemblyBegin(W_, MAT_FINAL_ASSEMBLY));
  LEM_PETSC(MatAssemblyEnd(W_, MAT_FINAL_ASSEMBLY));
  // W^T v as a product with the stored transpose: MatMultTranspose of a
  // parallel AIJ matrix is several times slower.
  LEM_PETSC(MatTranspose(W_, MAT_INITIAL_MATRIX, Wt_.replace()));
  LEM_PETSC(MatCreateVecs(W_, coarse_rhs_.replace(), nullptr));
  LEM_PETSC(VecDuplicate(coarse_rhs_, coarse_solution_.replace()));
  // A new space may have another size (pins can take a particle's last free
  // degrees of freedom): the coarse solver starts afresh.
  coarse_matrix_.reset();
  LEM_PETSC(KSPReset(coarse_));
  space_stale_ = false;
  coarse_stale_ = true;
}

void ParticleDeflation::form_coarse() {
  if (space_stale_) build_space();
  if (!coarse_stale_) return;
  if (!coarse_matrix_)
    LEM_PETSC(MatPtAP(K_, W_, MAT_INITIAL_MATRIX, 2.0, coarse_matrix_.replace()));
  else {
    Mat coarse = coarse_matrix_;  // filled in place (replace() would destroy it)
    LEM_PETSC(MatPtAP(K_, W_, MAT_REUSE_MATRIX, 2.0, &coarse));
  }
  LEM_PETSC(KSPSetOperators(coarse_, coarse_matrix_, coarse_matrix_));
  LEM_PETSC(KSPSetUp(coarse_));
  coarse_stale_ = false;
}

void ParticleDeflation::apply_q(Vec v, Vec out) {
  LEM_PETSC(MatMult(Wt_, v, coarse_rhs_));
  LEM_PETSC(KSPSolve(coarse_, coarse_rhs_, coarse_solution_));
  LEM_PETSC(MatMult(W_, coarse_solution_, out));
}

void ParticleDeflation::prepare(Vec b, Vec u) {
  form_coarse();
  LEM_PETSC(MatMult(K_, u, work_));  // work = b - K u
  LEM_PETSC(VecAYPX(work_, -1.0, b));
  apply_q(work_, work2_);
  LEM_PETSC(VecAXPY(u, 1.0, work2_));
}

// z = (I - Q K) M^-1 r + Q r, written as y = M^-1 r, z = y + Q (r - K y):
// one coarse solve per iteration.
PetscErrorCode ParticleDeflation::apply(PC pc, Vec r, Vec z) {
  PetscFunctionBeginUser;
  ParticleDeflation* d = nullptr;
  PetscCall(context(pc, &d));
  try {
    PetscCall(PCApply(d->inner_, r, z));
    PetscCall(MatMult(d->K_, z, d->work_));
    PetscCall(VecAYPX(d->work_, -1.0, r));
    d->apply_q(d->work_, d->work2_);
    PetscCall(VecAXPY(z, 1.0, d->work2_));
  } catch (const PetscFailure& e) {
    SETERRQ(PetscObjectComm(reinterpret_cast<PetscObject>(pc)), PETSC_ERR_LIB, "%s", e.what());
  }
  PetscFunctionReturn(0);
}

}  // namespace lem
