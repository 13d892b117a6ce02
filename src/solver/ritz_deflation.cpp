#include "ritz_deflation.hpp"

#include "lem/base/error.hpp"
#include "lem/base/log.hpp"
#include "lem/system/elastic_system.hpp"
#include "lem/system/lanczos.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>

namespace lem {

namespace {
// Lanczos vectors kept per solve (the first ones: a truncated Lanczos run
// still gives Ritz pairs), and the Ritz values that count as slow.
constexpr int kMaxRecorded = 100;
constexpr double kSlow = 0.1;
}  // namespace

SolverLeverEntry RitzDeflation::entry() {
  return WrappedLever::entry<RitzDeflation>(
      "-solver_ritz_deflation",
      [](OptionGroup& g) -> double {
        return static_cast<double>(g.integer(
            "-solver_ritz_deflation",
            "Deflate up to this many slow Ritz vectors of the "
            "multigrid-preconditioned K around the preconditioner (A-DEF2), learnt from the "
            "Lanczos vectors of the solves themselves (docs/model/fracture.md); 0: none",
            0, 0, kMostRitzColumns));
      },
      "one deflation space");
}

void RitzDeflation::wrapped(const LeverSite& site) {
  K_ = site.K;
  count_ = static_cast<int>(site.setting);
  LEM_PETSC(MatCreateVecs(K_, work_.replace(), nullptr));
  LEM_PETSC(VecDuplicate(work_, x_last_.replace()));
  LEM_PETSC(VecDuplicate(work_, p_.replace()));
}

// CG calls the preconditioner once per iteration, on r_k, after it moved the
// iterate to x_k = x_{k-1} + alpha_{k-1} p_{k-1}: alpha_{k-1} is read from
// the change of x along p_{k-1}, which follows from the z_k seen here
// (p_0 = z_0, p_k = z_k + beta_k p_{k-1}, beta_k = rho_k / rho_{k-1}).
void RitzDeflation::record(Vec r, Vec z) {
  PetscScalar rho = 0;
  LEM_PETSC(VecDot(r, z, &rho));
  const bool first = alpha_.empty() && lanczos_.empty();
  if (!first) {
    PetscScalar step = 0, pp = 0;
    LEM_PETSC(VecAYPX(x_last_, -1.0, x_));  // x_k - x_{k-1}
    LEM_PETSC(VecDot(x_last_, p_, &step));
    LEM_PETSC(VecDot(p_, p_, &pp));
    if (!(rho > 0) || !(pp > 0) || !(step > 0)) {
      recording_ = false;  // breakdown or a restart: keep what was recorded
      return;
    }
    alpha_.push_back(step / pp);
    beta_.push_back(rho / rho_last_);
    LEM_PETSC(VecAYPX(p_, beta_.back(), z));
  } else {
    if (!(rho > 0)) {
      recording_ = false;
      return;
    }
    LEM_PETSC(VecCopy(z, p_));
  }
  LEM_PETSC(VecCopy(x_, x_last_));
  rho_last_ = rho;
  if (static_cast<int>(lanczos_.size()) < kMaxRecorded) {
    lanczos_.emplace_back();
    LEM_PETSC(VecDuplicate(z, lanczos_.back().replace()));
    LEM_PETSC(VecCopy(z, lanczos_.back()));
    LEM_PETSC(VecScale(lanczos_.back(), 1.0 / std::sqrt(rho)));
  } else {
    recording_ = false;
  }
}

void RitzDeflation::learn() {
  recording_ = false;
  const int m = static_cast<int>(std::min(alpha_.size(), lanczos_.size()));

  if (m >= 2) {
    std::vector<double> alpha(alpha_.begin(), alpha_.begin() + m);
    std::vector<double> beta(beta_.begin(), beta_.begin() + (m - 1));
    std::vector<double> theta, y;
    lanczos_eigenpairs(alpha, beta, theta, y);
    std::vector<Vec> v(m);
    for (int k = 0; k < m; ++k) v[k] = lanczos_[k];
    std::vector<PetscScalar> column(m);
    for (int j = 0; j < m && theta[j] < kSlow && j < count_; ++j) {
      VecHandle w;
      LEM_PETSC(VecDuplicate(work_, w.replace()));
      LEM_PETSC(VecZeroEntries(w));
      for (int k = 0; k < m; ++k) column[k] = y[static_cast<std::size_t>(k) * m + j];
      LEM_PETSC(VecMAXPY(w, m, column.data(), v.data()));
      W_.push_back(std::move(w));
      KW_.emplace_back();
      LEM_PETSC(VecDuplicate(work_, KW_.back().replace()));
      coarse_stale_ = true;
    }
    // The oldest leave beyond count.
    if (size() > count_) {
      const std::size_t drop = static_cast<std::size_t>(size() - count_);
      W_.erase(W_.begin(), W_.begin() + static_cast<std::ptrdiff_t>(drop));
      KW_.erase(KW_.begin(), KW_.begin() + static_cast<std::ptrdiff_t>(drop));
    }
    w_.assign(W_.begin(), W_.end());
    kw_.assign(KW_.begin(), KW_.end());
  }
  lanczos_.clear();
  alpha_.clear();
  beta_.clear();
}

std::vector<VecHandle> RitzDeflation::columns() const {
  std::vector<VecHandle> shared;
  for (const VecHandle& w : W_) {
    LEM_PETSC(PetscObjectReference(reinterpret_cast<PetscObject>(w.get())));
    shared.emplace_back(w.get());
  }
  return shared;
}

void RitzDeflation::restore(std::vector<VecHandle> columns) {
  const std::size_t kept = std::min(columns.size(), static_cast<std::size_t>(count_));
  W_.assign(std::make_move_iterator(columns.end() - static_cast<std::ptrdiff_t>(kept)),
            std::make_move_iterator(columns.end()));
  KW_.clear();
  for (std::size_t j = 0; j < kept; ++j) {
    KW_.emplace_back();
    LEM_PETSC(VecDuplicate(work_, KW_.back().replace()));
  }
  w_.assign(W_.begin(), W_.end());
  kw_.assign(KW_.begin(), KW_.end());
  coarse_stale_ = true;
}

void RitzDeflation::form_coarse() {
  const int k = size();
  for (int j = 0; j < k; ++j) LEM_PETSC(MatMult(K_, w_[j], kw_[j]));
  // E = W^T K W, symmetrised, and its Cholesky factor.  A column that adds
  // nothing (a Ritz vector repeated by the lost orthogonality of Lanczos)
  // would make E singular: such columns are dropped.
  std::vector<double> E(static_cast<std::size_t>(k) * k);
  std::vector<PetscScalar> row(k);
  for (int i = 0; i < k; ++i) {
    LEM_PETSC(VecMDot(w_[i], k, kw_.data(), row.data()));
    for (int j = 0; j < k; ++j) E[static_cast<std::size_t>(i) * k + j] = row[j];
  }
  std::vector<int> keep;
  factor_.assign(static_cast<std::size_t>(k) * k, 0.0);
  for (int i = 0; i < k; ++i) {
    // Try to add column i to the factor of the kept ones.
    const int n = static_cast<int>(keep.size());
    std::vector<double> l(n + 1, 0.0);
    double diag = E[static_cast<std::size_t>(i) * k + i];
    for (int a = 0; a < n; ++a) {
      const int ia = keep[a];
      double s =
          0.5 * (E[static_cast<std::size_t>(i) * k + ia] + E[static_cast<std::size_t>(ia) * k + i]);
      for (int c = 0; c < a; ++c) s -= l[c] * factor_[static_cast<std::size_t>(a) * k + c];
      l[a] = s / factor_[static_cast<std::size_t>(a) * k + a];
      diag -= l[a] * l[a];
    }
    if (!(diag > 1e-8 * E[static_cast<std::size_t>(i) * k + i])) continue;
    for (int a = 0; a < n; ++a) factor_[static_cast<std::size_t>(n) * k + a] = l[a];
    factor_[static_cast<std::size_t>(n) * k + n] = std::sqrt(diag);
    keep.push_back(i);
  }
  if (static_cast<int>(keep.size()) < k) {
    std::vector<VecHandle> W, KW;
    for (int i : keep) {
      W.push_back(std::move(W_[i]));
      KW.push_back(std::move(KW_[i]));
    }
    W_ = std::move(W);
    KW_ = std::move(KW);
    w_.assign(W_.begin(), W_.end());
    kw_.assign(KW_.begin(), KW_.end());
    // The factor rows were written in the kept order with stride k: repack.
    const int n = size();
    std::vector<double> f(static_cast<std::size_t>(n) * n);
    for (int a = 0; a < n; ++a)
      for (int c = 0; c <= a; ++c)
        f[static_cast<std::size_t>(a) * n + c] = factor_[static_cast<std::size_t>(a) * k + c];
    factor_ = std::move(f);
  }
  t_.resize(size());
  s_.resize(size());
  coarse_stale_ = false;
}

void RitzDeflation::coarse_solve(std::vector<PetscScalar>& t) const {
  const int n = size();
  for (int a = 0; a < n; ++a) {  // L y = t
    double s = t[a];
    for (int c = 0; c < a; ++c) s -= factor_[static_cast<std::size_t>(a) * n + c] * t[c];
    t[a] = s / factor_[static_cast<std::size_t>(a) * n + a];
  }
  for (int a = n - 1; a >= 0; --a) {  // L^T c = y
    double s = t[a];
    for (int c = a + 1; c < n; ++c) s -= factor_[static_cast<std::size_t>(c) * n + a] * t[c];
    t[a] = s / factor_[static_cast<std::size_t>(a) * n + a];
  }
}

void RitzDeflation::prepare(Vec b, Vec u) {
  if (coarse_stale_) form_coarse();
  if (!W_.empty()) {
    LEM_PETSC(MatMult(K_, u, work_));  // work = b - K u
    LEM_PETSC(VecAYPX(work_, -1.0, b));
    LEM_PETSC(VecMDot(work_, size(), w_.data(), t_.data()));
    coarse_solve(t_);
    LEM_PETSC(VecMAXPY(u, size(), t_.data(), w_.data()));
  }
  x_ = u;
  rhs_ = b;
  lanczos_.clear();
  alpha_.clear();
  beta_.clear();
  recording_ = true;
}

// z = y + W E^-1 (W^T r - (K W)^T y) with y = M^-1 r: the A-DEF2
// preconditioner without a product with K (K is symmetric).
PetscErrorCode RitzDeflation::apply(PC pc, Vec r, Vec z) {
  PetscFunctionBeginUser;
  RitzDeflation* d = nullptr;
  PetscCall(context(pc, &d));
  PetscCall(PCApply(d->inner_, r, z));
  const int k = d->size();
  if (k > 0 && !d->coarse_stale_) {
    PetscCall(VecMDot(r, k, d->w_.data(), d->t_.data()));
    PetscCall(VecMDot(z, k, d->kw_.data(), d->s_.data()));
    for (int j = 0; j < k; ++j) d->t_[j] -= d->s_[j];
    d->coarse_solve(d->t_);
    PetscCall(VecMAXPY(z, k, d->t_.data(), d->w_.data()));
  }
  // (The default convergence test applies the preconditioner to b once, to
  // scale its tolerance: not a CG step.)
  if (d->recording_ && r != d->rhs_) {
    try {
      d->record(r, z);
    } catch (const PetscFailure& e) {
      SETERRQ(PetscObjectComm(reinterpret_cast<PetscObject>(pc)), PETSC_ERR_LIB, "%s", e.what());
    }
  }
  PetscFunctionReturn(0);
}

}  // namespace lem
