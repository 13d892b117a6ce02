// The float operators of the single-precision multigrid cycle
// (single_cycle.cpp): PETSc's level matrices copied to float blocks, and the
// fine level applied bond by bond.
#include "float_operators.hpp"

#include "lem/base/error.hpp"
#include "lem/system/distributed_lattice.hpp"
#include "lem/system/tension.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace lem {
namespace {

// Rows of float blocks (BR x BC, row-major), one column-block index each;
// x and y are double.  y = base + sign * A x, base null (zero) or an array.
template <int BR, int BC>
void block_rows(int row_blocks, const std::int32_t* __restrict ptr,
                const std::int32_t* __restrict col, const float* __restrict val,
                const double* __restrict x, const double* base, double* y, double sign) {
  for (int rb = 0; rb < row_blocks; ++rb) {
    double s[BR] = {};
    for (std::int32_t k = ptr[rb]; k < ptr[rb + 1]; ++k) {
      const float* v = val + static_cast<std::size_t>(k) * BR * BC;
      const double* xc = x + static_cast<std::size_t>(col[k]) * BC;
      for (int a = 0; a < BR; ++a)
        for (int c = 0; c < BC; ++c) s[a] += static_cast<double>(v[a * BC + c]) * xc[c];
    }
    double* yr = y + static_cast<std::size_t>(rb) * BR;
    const double* br = base ? base + static_cast<std::size_t>(rb) * BR : nullptr;
    for (int a = 0; a < BR; ++a) yr[a] = (br ? br[a] : 0.0) + sign * s[a];
  }
}

FloatBlockMatrix::Kernel kernel_for(int br, int bc) {
  if (br == 6 && bc == 6) return block_rows<6, 6>;
  if (br == 3 && bc == 3) return block_rows<3, 3>;
  if (br == 3 && bc == 6) return block_rows<3, 6>;
  if (br == 6 && bc == 3) return block_rows<6, 3>;
  return block_rows<1, 1>;
}

bool supported_blocks(int br, int bc) { return (br == 6 || br == 3) && (bc == 6 || bc == 3); }

}  // namespace

void FloatBlockMatrix::build(Mat A, int want_br, int want_bc) {
  PetscInt m = 0, n = 0, M = 0, N = 0, rstart = 0, rend = 0, cstart = 0, cend = 0;
  LEM_PETSC(MatGetLocalSize(A, &m, &n));
  LEM_PETSC(MatGetSize(A, &M, &N));
  LEM_PETSC(MatGetOwnershipRange(A, &rstart, &rend));
  LEM_PETSC(MatGetOwnershipRangeColumn(A, &cstart, &cend));
  br = want_br;
  bc = want_bc;
  if (!supported_blocks(br, bc) || m % br || n % bc || rstart % br || cstart % bc || N % bc)
    br = bc = 1;
  kernel = kernel_for(br, bc);
  MatInfo info;
  LEM_PETSC(MatGetInfo(A, MAT_GLOBAL_SUM, &info));
  nonzeros = info.nz_used;
  row_blocks = static_cast<int>(m / br);
  local_columns = static_cast<double>(n);
  const std::size_t block = static_cast<std::size_t>(br) * bc;
  // Column blocks of each block row: owned ones as local indices, ghost
  // ones as global block numbers (renumbered afterwards).
  std::vector<PetscInt> own_blocks, ghost_blocks;
  std::vector<std::int64_t> ocol_global;
  dptr.assign(1, 0);
  optr.assign(1, 0);
  dcol.clear();
  dval.clear();
  oval.clear();
  std::vector<PetscInt> cols_of_rows;
  for (int rb = 0; rb < row_blocks; ++rb) {
    own_blocks.clear();
    ghost_blocks.clear();
    for (int a = 0; a < br; ++a) {
      const PetscInt row = rstart + rb * br + a;
      PetscInt ncols = 0;
      const PetscInt* cols = nullptr;
      LEM_PETSC(MatGetRow(A, row, &ncols, &cols, nullptr));
      for (PetscInt c = 0; c < ncols; ++c) {
        if (cols[c] >= cstart && cols[c] < cend)
          own_blocks.push_back((cols[c] - cstart) / bc);
        else
          ghost_blocks.push_back(cols[c] / bc);
      }
      LEM_PETSC(MatRestoreRow(A, row, &ncols, &cols, nullptr));
    }
    for (auto* v : {&own_blocks, &ghost_blocks}) {
      std::sort(v->begin(), v->end());
      v->erase(std::unique(v->begin(), v->end()), v->end());
    }
    const std::size_t d0 = dcol.size(), o0 = ocol_global.size();
    for (PetscInt b : own_blocks) dcol.push_back(static_cast<std::int32_t>(b));
    for (PetscInt b : ghost_blocks) ocol_global.push_back(b);
    dval.resize(dcol.size() * block, 0.0f);
    oval.resize(ocol_global.size() * block, 0.0f);
    for (int a = 0; a < br; ++a) {
      const PetscInt row = rstart + rb * br + a;
      PetscInt ncols = 0;
      const PetscInt* cols = nullptr;
      const PetscScalar* vals = nullptr;
      LEM_PETSC(MatGetRow(A, row, &ncols, &cols, &vals));
      for (PetscInt c = 0; c < ncols; ++c) {
        const bool own = cols[c] >= cstart && cols[c] < cend;
        const PetscInt cb = own ? (cols[c] - cstart) / bc : cols[c] / bc;
        const auto& list = own ? own_blocks : ghost_blocks;
        const std::size_t at =
            static_cast<std::size_t>(std::lower_bound(list.begin(), list.end(), cb) - list.begin());
        float* v = (own ? dval.data() + (d0 + at) * block : oval.data() + (o0 + at) * block);
        v[a * bc + cols[c] % bc] = static_cast<float>(vals[c]);
      }
      LEM_PETSC(MatRestoreRow(A, row, &ncols, &cols, &vals));
    }
    dptr.push_back(static_cast<std::int32_t>(dcol.size()));
    optr.push_back(static_cast<std::int32_t>(ocol_global.size()));
  }
  // Ghost blocks numbered in the order of their global numbers.
  std::vector<std::int64_t> unique(ocol_global);
  std::sort(unique.begin(), unique.end());
  unique.erase(std::unique(unique.begin(), unique.end()), unique.end());
  ocol.resize(ocol_global.size());
  for (std::size_t k = 0; k < ocol_global.size(); ++k)
    ocol[k] = static_cast<std::int32_t>(
        std::lower_bound(unique.begin(), unique.end(), ocol_global[k]) - unique.begin());
  std::vector<PetscInt> index(unique.size() * bc);
  for (std::size_t g = 0; g < unique.size(); ++g)
    for (int t = 0; t < bc; ++t) index[g * bc + t] = static_cast<PetscInt>(unique[g] * bc + t);
  VecHandle x;
  LEM_PETSC(MatCreateVecs(A, x.replace(), nullptr));
  IsHandle is;
  LEM_PETSC(ISCreateGeneral(PETSC_COMM_SELF, static_cast<PetscInt>(index.size()), index.data(),
                            PETSC_COPY_VALUES, is.replace()));
  LEM_PETSC(VecCreateSeq(PETSC_COMM_SELF, static_cast<PetscInt>(index.size()), ghosts.replace()));
  LEM_PETSC(VecScatterCreate(x, is, ghosts, nullptr, scatter.replace()));
}

// y = A x, b - A x or y + A x.
void FloatBlockMatrix::apply(Vec x, Vec y, Vec b, ProductMode mode) const {
  LEM_PETSC(VecScatterBegin(scatter, x, ghosts, INSERT_VALUES, SCATTER_FORWARD));
  const PetscScalar *xa = nullptr, *ba = nullptr;
  PetscScalar* ya = nullptr;
  LEM_PETSC(VecGetArrayRead(x, &xa));
  LEM_PETSC(VecGetArray(y, &ya));
  if (mode == ProductMode::residual) LEM_PETSC(VecGetArrayRead(b, &ba));
  const double sign = mode == ProductMode::residual ? -1.0 : 1.0;
  const double* base = mode == ProductMode::set ? nullptr : mode == ProductMode::residual ? ba : ya;
  kernel(row_blocks, dptr.data(), dcol.data(), dval.data(), xa, base, ya, sign);
  if (mode == ProductMode::residual) LEM_PETSC(VecRestoreArrayRead(b, &ba));
  LEM_PETSC(VecRestoreArrayRead(x, &xa));
  LEM_PETSC(VecScatterEnd(scatter, x, ghosts, INSERT_VALUES, SCATTER_FORWARD));
  const PetscScalar* ga = nullptr;
  LEM_PETSC(VecGetArrayRead(ghosts, &ga));
  kernel(row_blocks, optr.data(), ocol.data(), oval.data(), ga, ya, ya, sign);
  LEM_PETSC(VecRestoreArrayRead(ghosts, &ga));
  LEM_PETSC(VecRestoreArray(y, &ya));
}

double FloatBlockMatrix::memory_bytes() const {
  const std::size_t words =
      dptr.size() + dcol.size() + optr.size() + ocol.size() + dval.size() + oval.size();
  return 4.0 * static_cast<double>(words);
}

// One product: the blocks and their indices, x (and its ghosts) read, y
// written (and read for a residual or an addition).
double FloatBlockMatrix::bytes_per_product(bool reads_y) const {
  PetscInt ng = 0;
  LEM_PETSC(VecGetLocalSize(ghosts, &ng));
  const double rows = static_cast<double>(row_blocks) * br;
  return memory_bytes() +
         8.0 * (local_columns + static_cast<double>(ng) + rows * (reads_y ? 2 : 1));
}
FloatBondOperator::FloatBondOperator(const DistributedLattice& l, double g, double s)
    : lattice(l), ground(g), scale(s) {
  const int bonds = lattice.local_bonds();
  order.resize(bonds);
  std::iota(order.begin(), order.end(), 0);
  auto low = [&](int b) { return std::min(lattice.bond_ends[b][0], lattice.bond_ends[b][1]); };
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return low(a) < low(b); });
  std::vector<PetscInt> gh(lattice.global_index.begin() + lattice.owned,
                           lattice.global_index.end());
  LEM_PETSC(VecCreateGhostBlock(lattice.comm, 3, 3 * lattice.owned, PETSC_DECIDE,
                                static_cast<PetscInt>(gh.size()), gh.data(), x_ghosted.replace()));
  acc.resize(3 * static_cast<std::size_t>(lattice.local_nodes()));
}

// The directions and end nodes (at every build of the cycle).
void FloatBondOperator::read() {
  const std::size_t bonds = order.size();
  i.resize(bonds);
  j.resize(bonds);
  nx.resize(bonds);
  ny.resize(bonds);
  nz.resize(bonds);
  for (std::size_t s = 0; s < bonds; ++s) {
    const int b = order[s];
    double n[3];
    bond_direction(lattice, b, n);
    i[s] = lattice.bond_ends[b][0];
    j[s] = lattice.bond_ends[b][1];
    nx[s] = static_cast<float>(n[0]);
    ny[s] = static_cast<float>(n[1]);
    nz[s] = static_cast<float>(n[2]);
  }
  refresh();
}

// The stiffnesses and constraints of now: before every solve, since the
// double cycle's fine level is the operator of CG, which follows every
// rupture and pinned node even while the multigrid is kept.
void FloatBondOperator::refresh() {
  const std::size_t bonds = order.size();
  mx.resize(bonds);
  my.resize(bonds);
  mz.resize(bonds);
  for (std::size_t s = 0; s < bonds; ++s) {
    const float root =
        static_cast<float>(std::sqrt(std::max(lattice.bond_stiffness[order[s]], 0.0)));
    mx[s] = root * nx[s];
    my[s] = root * ny[s];
    mz[s] = root * nz[s];
  }
  free.resize(3 * static_cast<std::size_t>(lattice.local_nodes()));
  for (int n = 0; n < lattice.local_nodes(); ++n)
    for (int a = 0; a < 3; ++a) free[3 * n + a] = is_fixed(lattice.dof_flags[n], a) ? 0 : 1;
}

void FloatBondOperator::apply(Vec x, Vec y, Vec b, ProductMode mode) const {
  const int owned3 = 3 * lattice.owned;
  {
    const PetscScalar* xa = nullptr;
    PetscScalar* w = nullptr;
    LEM_PETSC(VecGetArrayRead(x, &xa));
    LEM_PETSC(VecGetArray(x_ghosted, &w));
    for (int r = 0; r < owned3; ++r) w[r] = free[r] ? xa[r] : 0.0;
    LEM_PETSC(VecRestoreArray(x_ghosted, &w));
    LEM_PETSC(VecRestoreArrayRead(x, &xa));
  }
  LEM_PETSC(VecGhostUpdateBegin(x_ghosted, INSERT_VALUES, SCATTER_FORWARD));
  LEM_PETSC(VecGhostUpdateEnd(x_ghosted, INSERT_VALUES, SCATTER_FORWARD));
  Vec local;
  LEM_PETSC(VecGhostGetLocalForm(x_ghosted, &local));
  const PetscScalar* u = nullptr;
  LEM_PETSC(VecGetArrayRead(local, &u));
  std::fill(acc.begin(), acc.end(), 0.0);
  double* __restrict a = acc.data();
  const std::int32_t* __restrict bi = i.data();
  const std::int32_t* __restrict bj = j.data();
  const float* __restrict px = mx.data();
  const float* __restrict py = my.data();
  const float* __restrict pz = mz.data();
  const std::size_t bonds = i.size();
  for (std::size_t s = 0; s < bonds; ++s) {
    const double* ui = u + 3 * static_cast<std::size_t>(bi[s]);
    const double* uj = u + 3 * static_cast<std::size_t>(bj[s]);
    const double m0 = px[s], m1 = py[s], m2 = pz[s];
    const double f = m0 * (uj[0] - ui[0]) + m1 * (uj[1] - ui[1]) + m2 * (uj[2] - ui[2]);
    double* yi = a + 3 * static_cast<std::size_t>(bi[s]);
    double* yj = a + 3 * static_cast<std::size_t>(bj[s]);
    yi[0] -= f * m0;
    yi[1] -= f * m1;
    yi[2] -= f * m2;
    yj[0] += f * m0;
    yj[1] += f * m1;
    yj[2] += f * m2;
  }
  LEM_PETSC(VecRestoreArrayRead(local, &u));
  LEM_PETSC(VecGhostRestoreLocalForm(x_ghosted, &local));
  const PetscScalar *xa = nullptr, *ba = nullptr;
  PetscScalar* ya = nullptr;
  LEM_PETSC(VecGetArrayRead(x, &xa));
  LEM_PETSC(VecGetArray(y, &ya));
  if (mode == ProductMode::residual) LEM_PETSC(VecGetArrayRead(b, &ba));
  for (int r = 0; r < owned3; ++r) {
    const double kx = free[r] ? a[r] + ground * xa[r] : scale * xa[r];
    ya[r] = mode == ProductMode::residual ? ba[r] - kx : mode == ProductMode::add ? ya[r] + kx : kx;
  }
  if (mode == ProductMode::residual) LEM_PETSC(VecRestoreArrayRead(b, &ba));
  LEM_PETSC(VecRestoreArray(y, &ya));
  LEM_PETSC(VecRestoreArrayRead(x, &xa));
}

double FloatBondOperator::memory_bytes() const {
  return 32.0 * static_cast<double>(i.size()) + 4.0 * static_cast<double>(order.size()) +
         static_cast<double>(free.size()) + 8.0 * static_cast<double>(acc.size());
}

// Bond arrays; the masked copy (x read, mask, copy written), the
// accumulator zeroed, read and written by the bonds, x's ghosted copy read
// by them, the last pass (accumulator, x, b, mask read, y written).
double FloatBondOperator::bytes_per_product() const {
  const double local = static_cast<double>(acc.size()), owned = 3.0 * lattice.owned;
  return 20.0 * static_cast<double>(i.size()) + 17.0 * owned + 8.0 * 4.0 * local + 33.0 * owned;
}
}  // namespace lem
