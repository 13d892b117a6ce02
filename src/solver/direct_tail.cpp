#include "direct_tail.hpp"

#include "lem/base/collective.hpp"
#include "lem/base/driver.hpp"
#include "lem/base/error.hpp"
#include "lem/base/log.hpp"
#include "lem/system/tension.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <stdexcept>

namespace lem {

namespace {
// Solves each decision looks back on.
constexpr int kWindow = 8;
// Columns of Z solved for at once: MUMPS gathers a block's right-hand sides
// on one rank (8 bytes a dof and column).
constexpr int kBlock = 32;
// A pivot of C below this fraction of its 1/k is lost to rounding: the
// broken bond left a part held by the ground springs alone, which the
// factor of the damaged K then carries better.
constexpr double kSmallestPivot = 1e-10;
// The options read with -solver_direct_tail (the PC is created by PETSc's
// registry, which passes nothing).
int g_most_columns = 1000;
double g_memory_share = 0.8;

struct Record {
  std::int64_t id;
  double delta;
  int twice;
};
}  // namespace

SolverLeverEntry DirectTail::entry() {
  return WrappedLever::entry<DirectTail>("-solver_direct_tail", [](OptionGroup& g) -> double {
    g_most_columns = static_cast<int>(g.integer(
        "-solver_direct_columns",
        "-solver_direct_tail: broken bonds carried by low-rank updates of one factorization "
        "before K is factored again (each keeps a column of 8 bytes a dof on its ranks)",
        1000, 1, 100000));
    g_memory_share = g.real(
        "-solver_direct_memory",
        "-solver_direct_tail: the largest share of a machine's available memory the route may "
        "take (MUMPS's estimate for the factor, plus the columns); beyond it the run keeps "
        "the multigrid",
        0.8, 0, 1, /*open_lo=*/true);
    return static_cast<double>(g.integer(
        "-solver_direct_tail",
        "Take a direct route when the last solves needed at least this many CG iterations on "
        "average: a sparse Cholesky factorization of K (MUMPS) with exact low-rank updates for "
        "the bonds that break after it, kept while its measured cost a solve stays below the "
        "multigrid's (docs/model/fracture-solver.md); 0: the multigrid only",
        0, 0, 1000000));
  });
}

void DirectTail::wrapped(const LeverSite& site) {
  lattice_ = &site.lattice;
  K_ = site.K;
  trigger_ = static_cast<int>(site.setting);
  most_columns_ = g_most_columns;
  memory_share_ = g_memory_share;
  dofs_ = 3 * lattice_->owned;
  // Refused now, not at the first factorization hours into a run.
  MatType type = nullptr;
  LEM_PETSC(MatGetType(K_, &type));
  PetscBool solver = PETSC_FALSE, for_type = PETSC_FALSE;
  LEM_PETSC(
      MatSolverTypeGet(MATSOLVERMUMPS, type, MAT_FACTOR_CHOLESKY, &solver, &for_type, nullptr));
  if (!(solver && for_type))
    throw InputError(std::string("option -solver_direct_tail needs PETSc built with MUMPS (a "
                                 "Cholesky factorization of ") +
                     type + " matrices); this PETSc has none");
  for (int b = 0; b < lattice_->local_bonds(); ++b) local_bond_[lattice_->bond_id[b]] = b;
}

bool DirectTail::want_route() const {
  if (trigger_ <= 0 || static_cast<int>(recent_.size()) < kWindow) return false;
  double applications = 0, seconds = 0;
  for (const auto& [a, s] : recent_) {
    applications += a;
    seconds += s;
  }
  // An application more than the iterations: the convergence test's on b.
  if (applications / kWindow - 1 < trigger_) return false;
  return route_cost_ == 0 || seconds / kWindow > route_cost_;
}

bool DirectTail::want_multigrid() const {
  return route_solves_ >= kWindow && route_seconds_ / route_solves_ > multigrid_cost_;
}

void DirectTail::prepare(Vec b, Vec u) {
  if (!direct_ && want_route()) {
    multigrid_cost_ = 0;
    for (const auto& r : recent_) multigrid_cost_ += r.second / kWindow;
    route_seconds_ = 0;
    route_solves_ = 0;
    direct_ = true;
    factor_or_leave();
  } else if (direct_ && want_multigrid()) {
    route_cost_ = route_seconds_ / route_solves_;
    release();
    recent_.clear();
    ++switches_back_;
  }
  if (direct_ && !solution_) LEM_PETSC(VecDuplicate(b, solution_.replace()));
  int solved = 0;
  if (direct_ && !stale_factor_ && changed_) solved = update(b);
  if (direct_ && (stale_factor_ || solved < 0)) factor_or_leave();
  changed_ = false;
  applications_ = 0;
  solve_start_ = MPI_Wtime();
  rhs_ = nullptr;
  if (direct_) {
    // Start CG from the route's solution; CG checks it on its true
    // residual (start_is_solution), so a solve costs one pass over the
    // factor.  Under a KSP that tests the preconditioned norm, apply()
    // answers the test's application to b with this same vector.
    if (solved > 0) {
      ++route_applications_;
      correct(solution_);
    } else {
      route_apply(b, solution_);
    }
    LEM_PETSC(VecCopy(solution_, u));
    rhs_ = b;
  }
}

void DirectTail::after_solve() {
  rhs_ = nullptr;
  const double seconds = max_over_ranks(lattice_->comm, MPI_Wtime() - solve_start_);
  if (direct_) {
    route_seconds_ += seconds;
    ++route_solves_;
    solve_seconds_ += seconds;
    ++total_solves_;
  } else {
    recent_.emplace_back(applications_, seconds);
    if (static_cast<int>(recent_.size()) > kWindow) recent_.pop_front();
  }
}

void DirectTail::factor() {
  const double t0 = MPI_Wtime();
  MatFactorInfo info;
  LEM_PETSC(MatFactorInfoInitialize(&info));
  if (!K0_) {
    LEM_PETSC(MatDuplicate(K_, MAT_COPY_VALUES, K0_.replace()));
    // A prefix of its own, which no option uses: the main solver's -pc_* and
    // -mat_* options do not reach the factor.
    LEM_PETSC(MatSetOptionsPrefixFactor(K0_, "solver_direct_"));
    LEM_PETSC(MatGetFactor(K0_, MATSOLVERMUMPS, MAT_FACTOR_CHOLESKY, factor_.replace()));
    LEM_PETSC(MatCholeskyFactorSymbolic(factor_, K0_, nullptr, &info));
    check_memory();
  } else {
    // The pattern of K never changes (broken bonds keep their zeros), so
    // the analysis of the first factorization is kept.
    LEM_PETSC(MatCopy(K_, K0_, SAME_NONZERO_PATTERN));
  }
  LEM_PETSC(MatCholeskyFactorNumeric(factor_, K0_, &info));
  MatFactorError failed = MAT_FACTOR_NOERROR;
  LEM_PETSC(MatFactorGetError(factor_, &failed));
  if (failed != MAT_FACTOR_NOERROR)
    throw NumericalError(std::string("-solver_direct_tail: the Cholesky factorization of K "
                                     "failed (") +
                         (failed == MAT_FACTOR_OUTMEMORY ? "out of memory" : "a zero pivot") + ")");
  assumed_ = lattice_->bond_stiffness;
  in_column_.assign(lattice_->bond_stiffness.size(), 0);
  g_.clear();
  delta_.clear();
  Z_.clear();
  Z_.shrink_to_fit();
  L_.clear();
  stale_factor_ = false;
  changed_ = false;
  const double seconds = max_over_ranks(lattice_->comm, MPI_Wtime() - t0);
  factor_seconds_ += seconds;
  route_seconds_ += seconds;
  ++factorizations_;
}

// Before the first numerical factorization: MUMPS's analysis estimates
// what the factor will take on each rank, and the columns take 8 bytes a
// dof each; together they must fit the share of each machine's available
// memory the option allows, or the route is left for good.
void DirectTail::check_memory() {
  PetscInt factor_mb = 0;  // INFO(15): the in-core factorization's estimate
  LEM_PETSC(MatMumpsGetInfo(factor_, 15, &factor_mb));
  const double columns = 8.0 * dofs_ * most_columns_;
  const MachineMemory m = tightest_machine(lattice_->comm, 1e6 * factor_mb + columns);
  estimated_mb_ = max_over_ranks(lattice_->comm, 1e-6 * (1e6 * factor_mb + columns));
  if (!m.fits(memory_share_)) {
    char text[320];
    std::snprintf(text, sizeof text,
                  "the factor of K and its %d columns would take about %.3g GB on a machine "
                  "(MUMPS's estimate, %d ranks), above %.2g of the %.3g GB it has available "
                  "(-solver_direct_memory)",
                  most_columns_, m.need / 1e9, m.ranks, memory_share_, m.available / 1e9);
    throw std::runtime_error(text);
  }
}

// A factorization that fails (MUMPS out of memory, say) ends the route for
// the rest of the run: the multigrid carries on, with a warning.
void DirectTail::factor_or_leave() {
  try {
    factor();
  } catch (const std::exception& e) {
    release();
    trigger_ = 0;
    say_warning("-solver_direct_tail: %s; the run goes on with the multigrid alone\n", e.what());
  }
}

void DirectTail::release() {
  direct_ = false;
  factor_.reset();
  K0_.reset();
  solution_.reset();
  g_.clear();
  delta_.clear();
  std::vector<double>().swap(Z_);
  L_.clear();
}

int DirectTail::update(Vec rhs) {
  const DistributedLattice& l = *lattice_;
  std::vector<Record> mine;
  for (int b = 0; b < l.local_bonds(); ++b)
    if (l.bond_stiffness[b] != assumed_[b] && l.bond_reported[b])
      mine.push_back({l.bond_id[b], assumed_[b] - l.bond_stiffness[b], in_column_[b]});
  std::vector<Record> all = allgather(l.comm, mine);
  std::sort(all.begin(), all.end(), [](const Record& a, const Record& b) { return a.id < b.id; });
  if (all.empty()) return 0;
  // A bond changed twice, a stiffer bond, or more columns than allowed:
  // a factorization of K as it is now.
  if (columns() + static_cast<int>(all.size()) > most_columns_) return -1;
  for (const Record& r : all)
    if (r.twice || !(r.delta > 0)) return -1;
  std::vector<std::pair<std::int64_t, double>> bonds;
  for (const Record& r : all) bonds.emplace_back(r.id, r.delta);
  for (int b = 0; b < l.local_bonds(); ++b)
    if (l.bond_stiffness[b] != assumed_[b]) {
      assumed_[b] = l.bond_stiffness[b];
      in_column_[b] = 1;
    }
  return add_columns(bonds, rhs) ? 1 : -1;
}

bool DirectTail::add_columns(const std::vector<std::pair<std::int64_t, double>>& bonds, Vec rhs) {
  const double t0 = MPI_Wtime();
  const DistributedLattice& l = *lattice_;
  bool ok = true;
  for (std::size_t first = 0; first < bonds.size() && ok; first += kBlock) {
    const int p = static_cast<int>(std::min<std::size_t>(kBlock, bonds.size() - first));
    const int m0 = columns();
    // The owned entries of each new g: +n at the first end, -n at the
    // second, none on fixed dofs (as the bond's block of K).
    for (int j = 0; j < p; ++j) {
      std::vector<std::pair<int, double>> entries;
      const auto found = local_bond_.find(bonds[first + j].first);
      if (found != local_bond_.end()) {
        const int b = found->second;
        double n[3];
        bond_direction(l, b, n);
        for (int e = 0; e < 2; ++e) {
          const int node = l.bond_ends[b][e];
          if (node >= l.owned) continue;
          for (int a = 0; a < 3; ++a)
            if (!is_fixed(l.dof_flags[node], a))
              entries.emplace_back(3 * node + a, e ? -n[a] : n[a]);
        }
      }
      g_.push_back(std::move(entries));
      delta_.push_back(bonds[first + j].second);
    }
    // The first block also carries the right-hand side, in its last column.
    const bool with_rhs = rhs && first == 0;
    const int width = p + (with_rhs ? 1 : 0);
    MatHandle B, X;
    LEM_PETSC(
        MatCreateDense(l.comm, dofs_, PETSC_DECIDE, PETSC_DETERMINE, width, nullptr, B.replace()));
    PetscScalar* b = nullptr;
    LEM_PETSC(MatDenseGetArrayWrite(B, &b));
    std::fill(b, b + static_cast<std::size_t>(dofs_) * width, 0.0);
    for (int j = 0; j < p; ++j)
      for (const auto& [dof, value] : g_[m0 + j])
        b[static_cast<std::size_t>(j) * dofs_ + dof] = value;
    if (with_rhs) {
      const PetscScalar* f = nullptr;
      LEM_PETSC(VecGetArrayRead(rhs, &f));
      std::copy_n(f, dofs_, b + static_cast<std::size_t>(p) * dofs_);
      LEM_PETSC(VecRestoreArrayRead(rhs, &f));
    }
    LEM_PETSC(MatDenseRestoreArrayWrite(B, &b));
    LEM_PETSC(MatDuplicate(B, MAT_DO_NOT_COPY_VALUES, X.replace()));
    LEM_PETSC(MatMatSolve(factor_, B, X));
    const PetscScalar* x = nullptr;
    PetscInt lda = 0;
    LEM_PETSC(MatDenseGetLDA(X, &lda));
    LEM_PETSC(MatDenseGetArrayRead(X, &x));
    if (with_rhs) {
      PetscScalar* y = nullptr;
      LEM_PETSC(VecGetArray(solution_, &y));
      std::copy_n(x + static_cast<std::size_t>(p) * lda, dofs_, y);
      LEM_PETSC(VecRestoreArray(solution_, &y));
    }
    Z_.reserve(Z_.size() + static_cast<std::size_t>(dofs_) * p);
    for (int j = 0; j < p; ++j)
      Z_.insert(Z_.end(), x + static_cast<std::size_t>(j) * lda,
                x + static_cast<std::size_t>(j) * lda + dofs_);
    // G = U^T Z_new over every column: the new rows of C = S^-1 - U^T Z.
    const int m = m0 + p;
    std::vector<double> G(static_cast<std::size_t>(m) * p);
    for (int j = 0; j < p; ++j)
      project(x + static_cast<std::size_t>(j) * lda, G.data() + static_cast<std::size_t>(j) * m);
    MPI_Allreduce(MPI_IN_PLACE, G.data(), m * p, MPI_DOUBLE, MPI_SUM, l.comm);
    LEM_PETSC(MatDenseRestoreArrayRead(X, &x));
    for (int j = 0; j < p && ok; ++j) {
      const int r = m0 + j;
      auto at = [&](int row, int col) { return G[static_cast<std::size_t>(col) * m + row]; };
      std::vector<double> c(r + 1);
      for (int k = 0; k < m0; ++k) c[k] = -at(k, j);
      for (int k = 0; k < j; ++k) c[m0 + k] = -0.5 * (at(m0 + k, j) + at(r, k));
      c[r] = 1.0 / delta_[r] - at(r, j);
      // The Cholesky factor of C gains row r.
      std::vector<double> row(r + 1);
      double diag = c[r];
      for (int k = 0; k < r; ++k) {
        double s = c[k];
        for (int q = 0; q < k; ++q) s -= row[q] * L_[k][q];
        row[k] = s / L_[k][k];
        diag -= row[k] * row[k];
      }
      if (!(diag > kSmallestPivot / delta_[r])) {
        ok = false;
        break;
      }
      row[r] = std::sqrt(diag);
      L_.push_back(std::move(row));
    }
  }
  const double seconds = max_over_ranks(l.comm, MPI_Wtime() - t0);
  column_seconds_ += seconds;
  route_seconds_ += seconds;
  total_columns_ += static_cast<int>(bonds.size());
  return ok;
}

void DirectTail::project(const PetscScalar* x, double* t) const {
  for (int j = 0; j < columns(); ++j) {
    double s = 0;
    for (const auto& [dof, value] : g_[j]) s += value * x[dof];
    t[j] = s;
  }
}

void DirectTail::solve_capacitance(std::vector<double>& t) const {
  const int n = static_cast<int>(t.size());
  for (int a = 0; a < n; ++a) {  // L y = t
    double s = t[a];
    for (int c = 0; c < a; ++c) s -= L_[a][c] * t[c];
    t[a] = s / L_[a][a];
  }
  for (int a = n - 1; a >= 0; --a) {  // L^T x = y
    double s = t[a];
    for (int c = a + 1; c < n; ++c) s -= L_[c][a] * t[c];
    t[a] = s / L_[a][a];
  }
}

// z = F^-1 r + Z C^-1 (U^T F^-1 r).
void DirectTail::route_apply(Vec r, Vec z) {
  ++route_applications_;
  LEM_PETSC(MatSolve(factor_, r, z));
  correct(z);
}

void DirectTail::correct(Vec z) {
  const int m = columns();
  if (m == 0) return;
  std::vector<double> t(m);
  PetscScalar* y = nullptr;
  LEM_PETSC(VecGetArray(z, &y));
  project(y, t.data());
  MPI_Allreduce(MPI_IN_PLACE, t.data(), m, MPI_DOUBLE, MPI_SUM, lattice_->comm);
  solve_capacitance(t);
  for (int j = 0; j < m; ++j) {
    const double* column = Z_.data() + static_cast<std::size_t>(j) * dofs_;
    const double s = t[j];
    for (int i = 0; i < dofs_; ++i) y[i] += s * column[i];
  }
  LEM_PETSC(VecRestoreArray(z, &y));
}

PetscErrorCode DirectTail::apply(PC pc, Vec r, Vec z) {
  PetscFunctionBeginUser;
  DirectTail* d = nullptr;
  PetscCall(context(pc, &d));
  ++d->applications_;
  if (!d->direct_) {
    PetscCall(PCApply(d->inner_, r, z));
  } else if (r == d->rhs_) {
    PetscCall(VecCopy(d->solution_, z));  // made in prepare
  } else {
    try {
      d->route_apply(r, z);
    } catch (const PetscFailure& e) {
      SETERRQ(PetscObjectComm(reinterpret_cast<PetscObject>(pc)), PETSC_ERR_LIB, "%s", e.what());
    }
  }
  PetscFunctionReturn(0);
}

std::string DirectTail::work_line() const {
  char line[400];
  std::snprintf(line, sizeof line,
                "direct tail: %d solves on the route (%d applications, %.3g s), %d factorizations "
                "(%.3g s), %d broken bonds as columns (%.3g s), back to the multigrid %d times; "
                "factor and columns estimated at %.0f MB a rank",
                total_solves_, route_applications_, solve_seconds_, factorizations_,
                factor_seconds_, total_columns_, column_seconds_, switches_back_, estimated_mb_);
  return line;
}

}  // namespace lem
