#include "bond_operator.hpp"

#include "lem/base/error.hpp"
#include "lem/system/tension.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace lem {
namespace {

PetscErrorCode shell_mult(Mat A, Vec x, Vec y) {
  PetscFunctionBeginUser;
  BondOperator* op = nullptr;
  PetscCall(MatShellGetContext(A, &op));
  try {
    op->multiply(x, y);
  } catch (const PetscFailure& e) {
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_LIB, "%s", e.what());
  }
  PetscFunctionReturn(0);
}

PetscErrorCode shell_diagonal(Mat A, Vec d) {
  PetscFunctionBeginUser;
  BondOperator* op = nullptr;
  PetscCall(MatShellGetContext(A, &op));
  try {
    op->diagonal(d);
  } catch (const PetscFailure& e) {
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_LIB, "%s", e.what());
  }
  PetscFunctionReturn(0);
}

}  // namespace

BondOperator::BondOperator(const DistributedLattice& lattice, double ground, double scale)
    : lattice_(lattice), ground_(ground), scale_(scale) {
  const int bonds = lattice_.local_bonds();
  // Bonds in the order of their lower local end: the nodes are in Morton
  // order, so consecutive bonds touch nearby entries of x and y.
  std::vector<std::int32_t> order(bonds);
  std::iota(order.begin(), order.end(), 0);
  auto low = [&](int b) { return std::min(lattice_.bond_ends[b][0], lattice_.bond_ends[b][1]); };
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return low(a) < low(b); });
  i_.resize(bonds);
  j_.resize(bonds);
  k_.resize(bonds);
  nx_.resize(bonds);
  ny_.resize(bonds);
  nz_.resize(bonds);
  slot_.resize(bonds);
  for (int s = 0; s < bonds; ++s) {
    const int b = order[s];
    double n[3];
    bond_direction(lattice_, b, n);
    i_[s] = lattice_.bond_ends[b][0];
    j_[s] = lattice_.bond_ends[b][1];
    k_[s] = lattice_.bond_stiffness[b];
    nx_[s] = n[0];
    ny_[s] = n[1];
    nz_[s] = n[2];
    slot_[b] = s;
  }
  acc_.resize(3 * static_cast<std::size_t>(lattice_.local_nodes()));
  constraints_changed();

  std::vector<PetscInt> ghosts(lattice_.global_index.begin() + lattice_.owned,
                               lattice_.global_index.end());
  LEM_PETSC(VecCreateGhostBlock(lattice_.comm, 3, 3 * lattice_.owned, PETSC_DECIDE,
                                static_cast<PetscInt>(ghosts.size()), ghosts.data(),
                                x_ghosted_.replace()));
  const PetscInt m = 3 * lattice_.owned;
  LEM_PETSC(MatCreateShell(lattice_.comm, m, m, PETSC_DETERMINE, PETSC_DETERMINE, this,
                           shell_.replace()));
  LEM_PETSC(MatSetBlockSize(shell_, 3));
  LEM_PETSC(MatShellSetOperation(shell_, MATOP_MULT, reinterpret_cast<void (*)(void)>(shell_mult)));
  LEM_PETSC(MatShellSetOperation(shell_, MATOP_GET_DIAGONAL,
                                 reinterpret_cast<void (*)(void)>(shell_diagonal)));
  LEM_PETSC(MatSetOption(shell_, MAT_SYMMETRIC, PETSC_TRUE));
  LEM_PETSC(MatSetOption(shell_, MAT_SYMMETRY_ETERNAL, PETSC_TRUE));
}

void BondOperator::read_stiffness() {
  for (std::size_t b = 0; b < slot_.size(); ++b) k_[slot_[b]] = lattice_.bond_stiffness[b];
}

void BondOperator::constraints_changed() {
  free_.resize(3 * static_cast<std::size_t>(lattice_.local_nodes()));
  for (int n = 0; n < lattice_.local_nodes(); ++n)
    for (int a = 0; a < 3; ++a) free_[3 * n + a] = is_fixed(lattice_.dof_flags[n], a) ? 0.0 : 1.0;
}

void BondOperator::multiply(Vec x, Vec y) const {
  const int owned3 = 3 * lattice_.owned;
  // Fixed dofs enter no bond (their rows and columns of K hold only the
  // scale): zero them in the copy whose ghosts the bonds read.
  {
    const PetscScalar* xa = nullptr;
    PetscScalar* w = nullptr;
    LEM_PETSC(VecGetArrayRead(x, &xa));
    LEM_PETSC(VecGetArray(x_ghosted_, &w));
    for (int r = 0; r < owned3; ++r) w[r] = free_[r] * xa[r];
    LEM_PETSC(VecRestoreArray(x_ghosted_, &w));
    LEM_PETSC(VecRestoreArrayRead(x, &xa));
  }
  LEM_PETSC(VecGhostUpdateBegin(x_ghosted_, INSERT_VALUES, SCATTER_FORWARD));
  LEM_PETSC(VecGhostUpdateEnd(x_ghosted_, INSERT_VALUES, SCATTER_FORWARD));
  Vec local;
  LEM_PETSC(VecGhostGetLocalForm(x_ghosted_, &local));
  const PetscScalar* u = nullptr;
  LEM_PETSC(VecGetArrayRead(local, &u));
  std::fill(acc_.begin(), acc_.end(), 0.0);
  double* __restrict acc = acc_.data();
  const std::int32_t* __restrict bi = i_.data();
  const std::int32_t* __restrict bj = j_.data();
  const double* __restrict k = k_.data();
  const double* __restrict nx = nx_.data();
  const double* __restrict ny = ny_.data();
  const double* __restrict nz = nz_.data();
  const std::size_t bonds = i_.size();
  for (std::size_t b = 0; b < bonds; ++b) {
    const double* ui = u + 3 * static_cast<std::size_t>(bi[b]);
    const double* uj = u + 3 * static_cast<std::size_t>(bj[b]);
    const double f =
        k[b] * (nx[b] * (uj[0] - ui[0]) + ny[b] * (uj[1] - ui[1]) + nz[b] * (uj[2] - ui[2]));
    double* yi = acc + 3 * static_cast<std::size_t>(bi[b]);
    double* yj = acc + 3 * static_cast<std::size_t>(bj[b]);
    yi[0] -= f * nx[b];
    yi[1] -= f * ny[b];
    yi[2] -= f * nz[b];
    yj[0] += f * nx[b];
    yj[1] += f * ny[b];
    yj[2] += f * nz[b];
  }
  LEM_PETSC(VecRestoreArrayRead(local, &u));
  LEM_PETSC(VecGhostRestoreLocalForm(x_ghosted_, &local));
  // Owned rows only (a ghost's row is its owner's); ground or scale on the diagonal.
  const PetscScalar* xa = nullptr;
  PetscScalar* ya = nullptr;
  LEM_PETSC(VecGetArrayRead(x, &xa));
  LEM_PETSC(VecGetArray(y, &ya));
  for (int r = 0; r < owned3; ++r)
    ya[r] = free_[r] * (acc[r] + ground_ * xa[r]) + (1.0 - free_[r]) * scale_ * xa[r];
  LEM_PETSC(VecRestoreArray(y, &ya));
  LEM_PETSC(VecRestoreArrayRead(x, &xa));
}

void BondOperator::diagonal(Vec d) const {
  std::fill(acc_.begin(), acc_.end(), 0.0);
  for (std::size_t b = 0; b < i_.size(); ++b) {
    const double n[3] = {nx_[b], ny_[b], nz_[b]};
    for (int a = 0; a < 3; ++a) {
      acc_[3 * static_cast<std::size_t>(i_[b]) + a] += k_[b] * n[a] * n[a];
      acc_[3 * static_cast<std::size_t>(j_[b]) + a] += k_[b] * n[a] * n[a];
    }
  }
  PetscScalar* da = nullptr;
  LEM_PETSC(VecGetArray(d, &da));
  for (int r = 0; r < 3 * lattice_.owned; ++r) da[r] = free_[r] ? acc_[r] + ground_ : scale_;
  LEM_PETSC(VecRestoreArray(d, &da));
}

double BondOperator::bytes_per_multiply() const {
  const double bonds = static_cast<double>(i_.size());
  const double local = 3.0 * lattice_.local_nodes(), owned = 3.0 * lattice_.owned;
  // Bond arrays (ghost exchange not counted); the masked copy (free_ and x
  // read, the copy written), the accumulator zeroed then read and written by
  // the bonds, the last pass (free_, accumulator, x read, y written).
  return bonds * (2 * sizeof(std::int32_t) + 4 * sizeof(double)) +
         sizeof(double) * (3 * owned + local + 2 * local + 4 * owned);
}

}  // namespace lem
