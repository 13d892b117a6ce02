#include "lem/solver/single_cycle.hpp"

#include "float_operators.hpp"
#include "petsc318_private.hpp"

#include "lem/base/collective.hpp"
#include "lem/base/error.hpp"
#include "lem/base/options.hpp"

#include <cstdio>
#include <exception>
#include <string>
#include <utility>

namespace lem {

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

namespace {

// The smoother options the float cycle copies, with the one value it takes.
const struct {
  const char *name, *wanted;
} kKeptSmoother[] = {{"-mg_levels_ksp_type", "chebyshev"},
                     {"-mg_levels_pc_type", "jacobi"},
                     {"-mg_levels_ksp_max_it", "1"}};

// An option's value read directly from PETSc's database, "" if not given.
std::string given_value(const char* name) {
  char value[64] = "";
  PetscBool set = PETSC_FALSE;
  LEM_PETSC(PetscOptionsGetString(nullptr, nullptr, name, value, sizeof value, &set));
  return set ? value : "";
}

// The float cycle is the default wherever it can stand in for the multigrid
// (0.76 of the double cycle's wall on the paper-size run, the same ruptures:
// docs/notes/performance-single-cycle.md); options that ask for what it does
// not copy make the default the double cycle instead of an error.  Given
// explicitly, `single` still refuses them by name.
bool float_cycle_fits_options() {
  const std::string pc = given_value("-pc_type");
  if (!pc.empty() && pc != PCGAMG && pc != PCMG) return false;
  for (const auto& k : kKeptSmoother) {
    const std::string value = given_value(k.name);
    if (!value.empty() && value != k.wanted) return false;
  }
  // The damage aggregates change GAMG's own coarsening and must be the
  // multigrid itself, not wrapped (docs/model/fracture-solver.md).
  const std::string split = given_value("-solver_damage_aggregates");
  return split.empty() || split == "0";
}

}  // namespace

SolverLeverEntry SingleCycle::entry() {
  return WrappedLever::entry<SingleCycle>(
      "-solver_cycle_precision single", [](OptionGroup& g) -> double {
        const int single = g.choice<int>(
            "-solver_cycle_precision",
            "Precision of the multigrid cycle that preconditions CG: single (the default: "
            "GAMG's levels, operators and smoothers copied to float at every preconditioner "
            "build and applied by our own code, about half the bytes per cycle; CG, its "
            "operator and its residual stay in double) or double (PETSc's GAMG cycle). "
            "Without this option the cycle is double where single cannot serve: another "
            "-pc_type, another smoother (-mg_levels_*), or -solver_damage_aggregates",
            {{"double", 0}, {"single", 1}}, float_cycle_fits_options() ? 1 : 0);
        if (!single) return 0;
        return g.given("-solver_cycle_precision") ? kGiven : kByDefault;
      });
}

SingleCycle::SingleCycle() = default;
SingleCycle::~SingleCycle() = default;

void SingleCycle::wrapped(const LeverSite& site) {
  lattice_ = &site.lattice;
  ground_ = site.ground;
  scale_ = site.constrained;
  if (!can_wrap(inner_) &&
      site.setting == kByDefault) {  // e.g. a lever of one's own registered inside
    step_aside();
    return;
  }
  if (!can_wrap(inner_)) {
    PCType type = nullptr;
    LEM_PETSC(PCGetType(inner_, &type));
    throw InputError(std::string("-solver_cycle_precision single needs the multigrid "
                                 "preconditioner (-pc_type gamg or mg), not -pc_type ") +
                     (type ? type : "(none)"));
  }
  check_smoother_options();
  fine_ = std::make_unique<FloatBondOperator>(*lattice_, ground_, scale_);
}

void SingleCycle::step_aside() {
  aside_ = true;
  single_ = false;
  levels_.clear();
}

// The smoothers the float cycle copies, checked before any work (the build
// checks the smoother objects again).
void SingleCycle::check_smoother_options() {
  for (const auto& k : kKeptSmoother) {
    const std::string value = given_value(k.name);
    if (!value.empty() && value != k.wanted)
      throw InputError(std::string("-solver_cycle_precision single supports the smoother of "
                                   "the default solver only (-mg_levels_ksp_type chebyshev "
                                   "-mg_levels_pc_type jacobi -mg_levels_ksp_max_it 1), not ") +
                       k.name + " " + value);
  }
}

bool SingleCycle::can_wrap(PC pc) {
  PetscBool mg = PETSC_FALSE;
  LEM_PETSC(PetscObjectTypeCompareAny(reinterpret_cast<PetscObject>(pc), &mg, PCGAMG, PCMG, ""));
  return mg;
}

SingleCycle* SingleCycle::of(KSP ksp) {
  PC pc = nullptr;
  LEM_PETSC(KSPGetPC(ksp, &pc));
  auto* cycle = dynamic_cast<SingleCycle*>(lever_of(pc));
  return cycle && !cycle->aside_ ? cycle : nullptr;
}

PetscErrorCode SingleCycle::apply(PC pc, Vec b, Vec x) {
  PetscFunctionBeginUser;
  SingleCycle* s = nullptr;
  PetscCall(context(pc, &s));
  if (!s->single_ || s->levels_.empty()) {
    PetscCall(PCApply(s->inner_, b, x));
    PetscFunctionReturn(0);
  }
  try {
    const double t = MPI_Wtime();
    Level& fine = *s->levels_.back();
    // K changes in place with every rupture and pinned node, and the double
    // cycle's fine level follows it: read the fine level again and probe its
    // smoother again (checked here, not in a pre-solve hook, which a lever
    // around this one, as the deflation's, would not pass on).
    Mat K = nullptr;
    PetscCall(KSPGetOperators(fine.smoother, nullptr, &K));
    if (object_state(reinterpret_cast<PetscObject>(K)) != fine.operator_state) {
      const double t_refresh = MPI_Wtime();
      s->fine_->refresh();
      const double t_probe = MPI_Wtime();
      s->probe_smoother(fine);
      s->refreshes_ += 1;
      s->refresh_seconds_ += t_probe - t_refresh;
      s->probe_seconds_ += MPI_Wtime() - t_probe;
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
  if (aside_) return;
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
  level.operator_state = object_state(reinterpret_cast<PetscObject>(Pmat));
}

void SingleCycle::residual(int l, Vec b, Vec x, Vec r) {
  Level& level = *levels_[l];
  if (l == static_cast<int>(levels_.size()) - 1)
    fine_->apply(x, r, b, ProductMode::residual);
  else
    level.A.apply(x, r, b, ProductMode::residual);
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
  level.R.apply(level.r, lower.b, nullptr, ProductMode::set);
  level.seconds += MPI_Wtime() - t;
  const int cycles = l == 1 ? 1 : cycles_;
  for (int c = 0; c < cycles; ++c) cycle(l - 1, c == 0);
  t = MPI_Wtime();
  level.P.apply(lower.x, level.x, nullptr, ProductMode::add);
  sweep(false);
  level.transfers += 2;
  level.bytes += level.restrict_bytes + level.interpolate_bytes + level.vector_bytes;
  level.seconds += MPI_Wtime() - t;
}

std::vector<SingleCycle::LevelStats> SingleCycle::level_stats() const {
  std::vector<LevelStats> out;
  const MPI_Comm comm = lattice_->comm;
  for (auto it = levels_.rbegin(); it != levels_.rend(); ++it) {
    const Level& l = **it;
    LevelStats s;
    s.rows = l.rows;
    s.nonzeros = static_cast<long long>(l.nonzeros);
    s.visits = l.visits;
    s.products = l.products;
    s.transfers = l.transfers;
    s.seconds = max_over_ranks(comm, l.seconds);
    s.bytes = sum_over_ranks(comm, l.bytes);
    out.push_back(s);
  }
  return out;
}

std::string SingleCycle::work_line() const {
  if (aside_) return "";
  const MPI_Comm comm = lattice_->comm;
  char line[256];
  std::snprintf(line, sizeof line,
                "single cycle: %.0f applications, %.3g s; %.0f refreshes: %.3g s reading bonds, "
                "%.3g s probing smoothers",
                applications_, max_over_ranks(comm, apply_seconds_), refreshes_,
                max_over_ranks(comm, refresh_seconds_), max_over_ranks(comm, probe_seconds_));
  return line;
}

void SingleCycle::reset_stats() {
  applications_ = apply_seconds_ = 0;
  refreshes_ = refresh_seconds_ = probe_seconds_ = 0;
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
