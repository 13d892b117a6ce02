#include "lem/system/single_cycle.hpp"

#include "bond_operator.hpp"
#include "solver_defaults.hpp"

#include "lem/base/error.hpp"
#include "lem/system/tension.hpp"

#include <petsc/private/petscimpl.h>  // PetscObjectStateGet (public from PETSc 3.19)

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <string>

namespace lem {
namespace {

enum class Mode { set, residual, add };  // y = A x, y = b - A x, y += A x

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

using Kernel = void (*)(int, const std::int32_t*, const std::int32_t*, const float*, const double*,
                        const double*, double*, double);

Kernel kernel_for(int br, int bc) {
  if (br == 6 && bc == 6) return block_rows<6, 6>;
  if (br == 3 && bc == 3) return block_rows<3, 3>;
  if (br == 3 && bc == 6) return block_rows<3, 6>;
  if (br == 6 && bc == 3) return block_rows<6, 3>;
  return block_rows<1, 1>;
}

bool supported_blocks(int br, int bc) { return (br == 6 || br == 3) && (bc == 6 || bc == 3); }

// A parallel AIJ matrix with float values in blocks: the owned columns
// (x's own entries) and the ghost columns (gathered by a scatter), each as
// block rows.
struct FloatBlockMatrix {
  int br = 1, bc = 1, row_blocks = 0;
  std::vector<std::int32_t> dptr, dcol, optr, ocol;
  std::vector<float> dval, oval;
  VecScatterHandle scatter;
  VecHandle ghosts;
  Kernel kernel = nullptr;
  double nonzeros = 0;  // global, as stored by PETSc
  double local_columns = 0;

  void build(Mat A, int want_br, int want_bc) {
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
          const std::size_t at = static_cast<std::size_t>(
              std::lower_bound(list.begin(), list.end(), cb) - list.begin());
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
  void apply(Vec x, Vec y, Vec b, Mode mode) const {
    LEM_PETSC(VecScatterBegin(scatter, x, ghosts, INSERT_VALUES, SCATTER_FORWARD));
    const PetscScalar *xa = nullptr, *ba = nullptr;
    PetscScalar* ya = nullptr;
    LEM_PETSC(VecGetArrayRead(x, &xa));
    LEM_PETSC(VecGetArray(y, &ya));
    if (mode == Mode::residual) LEM_PETSC(VecGetArrayRead(b, &ba));
    const double sign = mode == Mode::residual ? -1.0 : 1.0;
    const double* base = mode == Mode::set ? nullptr : mode == Mode::residual ? ba : ya;
    kernel(row_blocks, dptr.data(), dcol.data(), dval.data(), xa, base, ya, sign);
    if (mode == Mode::residual) LEM_PETSC(VecRestoreArrayRead(b, &ba));
    LEM_PETSC(VecRestoreArrayRead(x, &xa));
    LEM_PETSC(VecScatterEnd(scatter, x, ghosts, INSERT_VALUES, SCATTER_FORWARD));
    const PetscScalar* ga = nullptr;
    LEM_PETSC(VecGetArrayRead(ghosts, &ga));
    kernel(row_blocks, optr.data(), ocol.data(), oval.data(), ga, ya, ya, sign);
    LEM_PETSC(VecRestoreArrayRead(ghosts, &ga));
    LEM_PETSC(VecRestoreArray(y, &ya));
  }

  double memory_bytes() const {
    const std::size_t words =
        dptr.size() + dcol.size() + optr.size() + ocol.size() + dval.size() + oval.size();
    return 4.0 * static_cast<double>(words);
  }
  // One product: the blocks and their indices, x (and its ghosts) read, y
  // written (and read for a residual or an addition).
  double bytes_per_product(bool reads_y) const {
    PetscInt ng = 0;
    LEM_PETSC(VecGetLocalSize(ghosts, &ng));
    const double rows = static_cast<double>(row_blocks) * br;
    return memory_bytes() +
           8.0 * (local_columns + static_cast<double>(ng) + rows * (reads_y ? 2 : 1));
  }
};

double max_over(MPI_Comm comm, double v) {
  double m = 0;
  MPI_Allreduce(&v, &m, 1, MPI_DOUBLE, MPI_MAX, comm);
  return m;
}
double sum_over(MPI_Comm comm, double v) {
  double s = 0;
  MPI_Allreduce(&v, &s, 1, MPI_DOUBLE, MPI_SUM, comm);
  return s;
}

}  // namespace

// The fine level bond by bond in float: per bond two local node indices and
// m = sqrt(k) n (k n n^T = m m^T), the product accumulated in double.
struct SingleCycle::FloatBonds {
  const DistributedLattice& lattice;
  double ground, scale;
  std::vector<std::int32_t> order;  // bonds sorted by their lower local end
  std::vector<std::int32_t> i, j;
  std::vector<float> nx, ny, nz;   // unit directions
  std::vector<float> mx, my, mz;   // sqrt(k) n, the arrays a product reads
  std::vector<std::uint8_t> free;  // per local dof
  VecHandle x_ghosted;
  mutable std::vector<double> acc;

  FloatBonds(const DistributedLattice& l, double g, double s) : lattice(l), ground(g), scale(s) {
    const int bonds = lattice.local_bonds();
    order.resize(bonds);
    std::iota(order.begin(), order.end(), 0);
    auto low = [&](int b) { return std::min(lattice.bond_ends[b][0], lattice.bond_ends[b][1]); };
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return low(a) < low(b); });
    std::vector<PetscInt> gh(lattice.global_index.begin() + lattice.owned,
                             lattice.global_index.end());
    LEM_PETSC(VecCreateGhostBlock(lattice.comm, 3, 3 * lattice.owned, PETSC_DECIDE,
                                  static_cast<PetscInt>(gh.size()), gh.data(),
                                  x_ghosted.replace()));
    acc.resize(3 * static_cast<std::size_t>(lattice.local_nodes()));
  }

  // The directions and end nodes (at every build of the cycle).
  void read() {
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
  void refresh() {
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

  void apply(Vec x, Vec y, Vec b, Mode mode) const {
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
    if (mode == Mode::residual) LEM_PETSC(VecGetArrayRead(b, &ba));
    for (int r = 0; r < owned3; ++r) {
      const double kx = free[r] ? a[r] + ground * xa[r] : scale * xa[r];
      ya[r] = mode == Mode::residual ? ba[r] - kx : mode == Mode::add ? ya[r] + kx : kx;
    }
    if (mode == Mode::residual) LEM_PETSC(VecRestoreArrayRead(b, &ba));
    LEM_PETSC(VecRestoreArray(y, &ya));
    LEM_PETSC(VecRestoreArrayRead(x, &xa));
  }

  double memory_bytes() const {
    return 32.0 * static_cast<double>(i.size()) + 4.0 * static_cast<double>(order.size()) +
           static_cast<double>(free.size()) + 8.0 * static_cast<double>(acc.size());
  }
  // Bond arrays; the masked copy (x read, mask, copy written), the
  // accumulator zeroed, read and written by the bonds, x's ghosted copy read
  // by them, the last pass (accumulator, x, b, mask read, y written).
  double bytes_per_product() const {
    const double local = static_cast<double>(acc.size()), owned = 3.0 * lattice.owned;
    return 20.0 * static_cast<double>(i.size()) + 17.0 * owned + 8.0 * 4.0 * local + 33.0 * owned;
  }
};

struct SingleCycle::Level {
  FloatBlockMatrix A, P, R;  // A: levels between the finest and the coarsest
  VecHandle own_b, own_x, r;
  Vec b = nullptr, x = nullptr;         // own_b/own_x, or the shell's vectors (finest)
  std::vector<float> dinv;              // Jacobi of the smoother
  double step = 0;                      // Chebyshev step of one sweep: x += step D^-1 (b - A x)
  KSP coarse = nullptr;                 // the coarsest level: GAMG's own solver (double)
  KSP smoother = nullptr;               // the others: GAMG's smoother, probed
  PetscObjectState operator_state = 0;  // of the smoother's matrix when probed
  long long rows = 0;
  double nonzeros = 0;
  double visits = 0, products = 0, transfers = 0, seconds = 0, bytes = 0;
  double product_bytes = 0, restrict_bytes = 0, interpolate_bytes = 0, vector_bytes = 0;
};

SingleCycle::SingleCycle(const DistributedLattice& lattice, double ground, double scale, KSP ksp)
    : lattice_(lattice), ground_(ground), scale_(scale) {
  LEM_PETSC(KSPGetPC(ksp, &inner_));
  PetscBool mg = PETSC_FALSE;
  LEM_PETSC(
      PetscObjectTypeCompareAny(reinterpret_cast<PetscObject>(inner_), &mg, PCGAMG, PCMG, ""));
  if (!mg) {
    PCType type = nullptr;
    LEM_PETSC(PCGetType(inner_, &type));
    throw InputError(std::string("-solver_cycle_precision single needs the multigrid "
                                 "preconditioner (-pc_type gamg or mg), not -pc_type ") +
                     (type ? type : "(none)"));
  }
  check_smoother_options();
  LEM_PETSC(PetscObjectReference(reinterpret_cast<PetscObject>(inner_)));
  Mat A = nullptr, P = nullptr;
  LEM_PETSC(KSPGetOperators(ksp, &A, &P));
  LEM_PETSC(PetscObjectReference(reinterpret_cast<PetscObject>(A)));
  LEM_PETSC(PetscObjectReference(reinterpret_cast<PetscObject>(P)));
  PC shell = nullptr;
  LEM_PETSC(PCCreate(lattice_.comm, &shell));
  LEM_PETSC(PCSetType(shell, PCSHELL));
  LEM_PETSC(PCShellSetName(shell, "multigrid cycle in single precision"));
  LEM_PETSC(PCShellSetContext(shell, this));
  LEM_PETSC(PCShellSetSetUp(shell, shell_setup));
  LEM_PETSC(PCShellSetApply(shell, shell_apply));
  LEM_PETSC(KSPSetPC(ksp, shell));  // the KSP takes its own reference
  LEM_PETSC(PCDestroy(&shell));
  LEM_PETSC(KSPSetOperators(ksp, A, P));
  MatDestroy(&A);
  MatDestroy(&P);
  fine_ = std::make_unique<FloatBonds>(lattice_, ground_, scale_);
}

// The smoothers the float cycle copies, checked before any work (the build
// checks the smoother objects again).
void SingleCycle::check_smoother_options() {
  const struct {
    const char *name, *wanted;
  } kept[] = {{"-mg_levels_ksp_type", "chebyshev"},
              {"-mg_levels_pc_type", "jacobi"},
              {"-mg_levels_ksp_max_it", "1"}};
  for (const auto& k : kept) {
    char value[64] = "";
    PetscBool set = PETSC_FALSE;
    LEM_PETSC(PetscOptionsGetString(nullptr, nullptr, k.name, value, sizeof value, &set));
    if (set && std::strcmp(value, k.wanted) != 0)
      throw InputError(std::string("-solver_cycle_precision single supports the smoother of "
                                   "the default solver only (-mg_levels_ksp_type chebyshev "
                                   "-mg_levels_pc_type jacobi -mg_levels_ksp_max_it 1), not ") +
                       k.name + " " + value);
  }
}

SingleCycle::~SingleCycle() { PCDestroy(&inner_); }

SingleCycle* SingleCycle::of(KSP ksp) {
  PC pc = nullptr;
  LEM_PETSC(KSPGetPC(ksp, &pc));
  PetscBool shell = PETSC_FALSE;
  LEM_PETSC(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(pc), PCSHELL, &shell));
  if (!shell) return nullptr;
  const char* name = nullptr;
  LEM_PETSC(PCShellGetName(pc, &name));
  if (!name || std::strcmp(name, "multigrid cycle in single precision") != 0) return nullptr;
  SingleCycle* s = nullptr;
  LEM_PETSC(PCShellGetContext(pc, &s));
  return s;
}

PetscErrorCode SingleCycle::shell_setup(PC pc) {
  PetscFunctionBeginUser;
  SingleCycle* s = nullptr;
  PetscCall(PCShellGetContext(pc, &s));
  Mat A = nullptr, P = nullptr;
  PetscCall(PCGetOperators(pc, &A, &P));
  PetscCall(PCSetReusePreconditioner(s->inner_, PETSC_FALSE));
  PetscCall(PCSetOperators(s->inner_, A, P));
  PetscCall(PCSetUp(s->inner_));
  PetscCall(apply_multigrid_level_defaults(s->inner_));
  // The shell decides when the multigrid is built again; PCApply would
  // otherwise rebuild it whenever K changed.
  PetscCall(PCSetReusePreconditioner(s->inner_, PETSC_TRUE));
  try {
    s->build();
  } catch (const std::exception& e) {
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_LIB, "%s", e.what());
  }
  PetscFunctionReturn(0);
}

PetscErrorCode SingleCycle::shell_apply(PC pc, Vec b, Vec x) {
  PetscFunctionBeginUser;
  SingleCycle* s = nullptr;
  PetscCall(PCShellGetContext(pc, &s));
  if (!s->single_ || s->levels_.empty()) {
    PetscCall(PCApply(s->inner_, b, x));
    PetscFunctionReturn(0);
  }
  try {
    const double t = MPI_Wtime();
    Level& fine = *s->levels_.back();
    // K changes in place with every rupture and pinned node, and the double
    // cycle's fine level follows it: read the fine level again and probe its
    // smoother again (checked here, not in a pre-solve hook, which a shell
    // around this one, as the deflation's, would not pass on).
    Mat K = nullptr;
    PetscObjectState state = 0;
    PetscCall(KSPGetOperators(fine.smoother, nullptr, &K));
    PetscCall(PetscObjectStateGet(reinterpret_cast<PetscObject>(K), &state));
    if (state != fine.operator_state) {
      s->fine_->refresh();
      s->probe_smoother(fine);
    }
    fine.b = b;
    fine.x = x;
    s->cycle(static_cast<int>(s->levels_.size()) - 1, true);
    fine.b = fine.x = nullptr;
    s->applications_ += 1;
    s->apply_seconds_ += MPI_Wtime() - t;
  } catch (const std::exception& e) {
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_LIB, "%s", e.what());
  }
  PetscFunctionReturn(0);
}

void SingleCycle::build() {
  PetscInt count = 0;
  LEM_PETSC(PCMGGetLevels(inner_, &count));
  const int n = static_cast<int>(count);
  {
    char type[8] = "";
    PetscBool set = PETSC_FALSE;
    LEM_PETSC(
        PetscOptionsGetString(nullptr, nullptr, "-pc_mg_cycle_type", type, sizeof type, &set));
    cycles_ = set && (type[0] == 'v' || type[0] == 'V') ? 1 : 2;
  }
  levels_.clear();
  // A single level (fewer rows than -pc_gamg_coarse_eq_limit) is GAMG's
  // direct solve alone: nothing to copy, the shell applies it.
  if (n < 2) return;
  fine_->read();
  for (int l = 0; l < n; ++l) {
    auto level = std::make_unique<Level>();
    KSP smoother = nullptr;
    LEM_PETSC(PCMGGetSmoother(inner_, l, &smoother));
    Mat Amat = nullptr, Pmat = nullptr;
    LEM_PETSC(KSPGetOperators(smoother, &Amat, &Pmat));
    PetscInt rows = 0;
    LEM_PETSC(MatGetSize(Pmat, &rows, nullptr));
    level->rows = rows;
    MatInfo info;
    LEM_PETSC(MatGetInfo(Pmat, MAT_GLOBAL_SUM, &info));
    level->nonzeros = info.nz_used;
    const bool finest = l == n - 1;
    if (!finest) {
      LEM_PETSC(MatCreateVecs(Pmat, level->own_x.replace(), level->own_b.replace()));
      level->x = level->own_x;
      level->b = level->own_b;
    }
    if (l == 0) {
      level->coarse = smoother;
      levels_.push_back(std::move(level));
      continue;
    }
    // The smoother: Chebyshev with Jacobi, one sweep.
    PetscBool cheb = PETSC_FALSE, jacobi = PETSC_FALSE;
    PC jpc = nullptr;
    PetscInt max_it = 0;
    LEM_PETSC(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(smoother), KSPCHEBYSHEV, &cheb));
    LEM_PETSC(KSPGetPC(smoother, &jpc));
    LEM_PETSC(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(jpc), PCJACOBI, &jacobi));
    LEM_PETSC(KSPGetTolerances(smoother, nullptr, nullptr, nullptr, &max_it));
    if (!cheb || !jacobi || max_it != 1)
      throw InputError("-solver_cycle_precision single supports the smoother of the default "
                       "solver only: Chebyshev with Jacobi, one sweep per level "
                       "(-mg_levels_ksp_type chebyshev -mg_levels_pc_type jacobi "
                       "-mg_levels_ksp_max_it 1); level " +
                       std::to_string(l) + " has another");
    LEM_PETSC(MatCreateVecs(Pmat, nullptr, level->r.replace()));
    level->smoother = smoother;
    probe_smoother(*level);
    PetscInt bs = 1;
    LEM_PETSC(MatGetBlockSize(Pmat, &bs));
    if (!finest) level->A.build(Pmat, static_cast<int>(bs), static_cast<int>(bs));
    Mat interpolation = nullptr;
    LEM_PETSC(PCMGGetInterpolation(inner_, l, &interpolation));
    PetscInt rbs = 1, cbs = 1;
    LEM_PETSC(MatGetBlockSizes(interpolation, &rbs, &cbs));
    level->P.build(interpolation, static_cast<int>(rbs), static_cast<int>(cbs));
    MatHandle transposed;
    LEM_PETSC(MatTranspose(interpolation, MAT_INITIAL_MATRIX, transposed.replace()));
    level->R.build(transposed, static_cast<int>(cbs), static_cast<int>(rbs));
    // Byte models of one product, one transfer each way, and the vector
    // passes of a visit (sweeps, residual: about 12 passes of the level's rows).
    PetscInt local = 0;
    LEM_PETSC(VecGetLocalSize(level->r, &local));
    level->product_bytes = finest ? fine_->bytes_per_product() : level->A.bytes_per_product(true);
    level->restrict_bytes = level->R.bytes_per_product(false);
    level->interpolate_bytes = level->P.bytes_per_product(true);
    level->vector_bytes = 12.0 * 8.0 * static_cast<double>(local);
    levels_.push_back(std::move(level));
  }
}

// Jacobi's inverse diagonal and the step of one Chebyshev sweep, probed: from
// a zero guess the sweep gives x = step D^-1 b.  The sweep sets the smoother
// up first, as the double cycle does whenever its operator changed (a new
// diagonal, a new eigenvalue estimate).
void SingleCycle::probe_smoother(Level& level) {
  VecHandle ones, d, probe;
  LEM_PETSC(VecDuplicate(level.r, ones.replace()));
  LEM_PETSC(VecDuplicate(level.r, d.replace()));
  LEM_PETSC(VecDuplicate(level.r, probe.replace()));
  LEM_PETSC(VecSet(ones, 1.0));
  LEM_PETSC(VecSet(probe, 0.0));
  LEM_PETSC(KSPSolve(level.smoother, ones, probe));
  PC jacobi = nullptr;
  LEM_PETSC(KSPGetPC(level.smoother, &jacobi));
  LEM_PETSC(PCApply(jacobi, ones, d));
  PetscScalar xd = 0, dd = 0;
  LEM_PETSC(VecDot(probe, d, &xd));
  LEM_PETSC(VecDot(d, d, &dd));
  level.step = dd > 0 ? xd / dd : 0.0;
  PetscInt m = 0;
  LEM_PETSC(VecGetLocalSize(d, &m));
  const PetscScalar* da = nullptr;
  LEM_PETSC(VecGetArrayRead(d, &da));
  level.dinv.assign(da, da + m);
  LEM_PETSC(VecRestoreArrayRead(d, &da));
  Mat Pmat = nullptr;
  LEM_PETSC(KSPGetOperators(level.smoother, nullptr, &Pmat));
  LEM_PETSC(PetscObjectStateGet(reinterpret_cast<PetscObject>(Pmat), &level.operator_state));
}

void SingleCycle::residual(int l, Vec b, Vec x, Vec r) {
  Level& level = *levels_[l];
  if (l == static_cast<int>(levels_.size()) - 1)
    fine_->apply(x, r, b, Mode::residual);
  else
    level.A.apply(x, r, b, Mode::residual);
  level.products += 1;
  level.bytes += level.product_bytes;
}

void SingleCycle::cycle(int l, bool zero_guess) {
  Level& level = *levels_[l];
  level.visits += 1;
  double t = MPI_Wtime();
  if (l == 0) {
    LEM_PETSC(KSPSolve(level.coarse, level.b, level.x));
    level.seconds += MPI_Wtime() - t;
    return;
  }
  // One Jacobi-preconditioned Chebyshev sweep: x += step D^-1 (b - A x).
  const auto sweep = [&](bool zero) {
    PetscScalar* xa = nullptr;
    const PetscScalar* ra = nullptr;
    if (!zero) residual(l, level.b, level.x, level.r);
    LEM_PETSC(VecGetArray(level.x, &xa));
    LEM_PETSC(VecGetArrayRead(zero ? level.b : level.r.get(), &ra));
    const std::size_t m = level.dinv.size();
    const double step = level.step;
    if (zero)
      for (std::size_t k = 0; k < m; ++k) xa[k] = step * level.dinv[k] * ra[k];
    else
      for (std::size_t k = 0; k < m; ++k) xa[k] += step * level.dinv[k] * ra[k];
    LEM_PETSC(VecRestoreArrayRead(zero ? level.b : level.r.get(), &ra));
    LEM_PETSC(VecRestoreArray(level.x, &xa));
  };
  sweep(zero_guess);
  residual(l, level.b, level.x, level.r);
  Level& lower = *levels_[l - 1];
  level.R.apply(level.r, lower.b, nullptr, Mode::set);
  level.seconds += MPI_Wtime() - t;
  const int cycles = l == 1 ? 1 : cycles_;
  for (int c = 0; c < cycles; ++c) cycle(l - 1, c == 0);
  t = MPI_Wtime();
  level.P.apply(lower.x, level.x, nullptr, Mode::add);
  sweep(false);
  level.transfers += 2;
  level.bytes += level.restrict_bytes + level.interpolate_bytes + level.vector_bytes;
  level.seconds += MPI_Wtime() - t;
}

std::vector<SingleCycle::LevelStats> SingleCycle::level_stats() const {
  std::vector<LevelStats> out;
  const MPI_Comm comm = lattice_.comm;
  for (auto it = levels_.rbegin(); it != levels_.rend(); ++it) {
    const Level& l = **it;
    LevelStats s;
    s.rows = l.rows;
    s.nonzeros = static_cast<long long>(l.nonzeros);
    s.visits = l.visits;
    s.products = l.products;
    s.transfers = l.transfers;
    s.seconds = max_over(comm, l.seconds);
    s.bytes = sum_over(comm, l.bytes);
    out.push_back(s);
  }
  return out;
}

void SingleCycle::reset_stats() {
  applications_ = apply_seconds_ = 0;
  for (auto& l : levels_) l->visits = l->products = l->transfers = l->seconds = l->bytes = 0;
}

double SingleCycle::memory_bytes() const {
  double bytes = fine_ ? fine_->memory_bytes() : 0.0;
  for (const auto& l : levels_)
    bytes += l->A.memory_bytes() + l->P.memory_bytes() + l->R.memory_bytes() +
             4.0 * static_cast<double>(l->dinv.size());
  return bytes;
}

}  // namespace lem
