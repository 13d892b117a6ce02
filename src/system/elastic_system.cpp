#include "lem/system/elastic_system.hpp"

#include "bond_operator.hpp"
#include "convergence_test.hpp"
#include "solver_defaults.hpp"
#include "spectrum_probe.hpp"

#include "lem/base/error.hpp"
#include "lem/base/log.hpp"
#include "lem/base/options.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <string>

namespace lem {
namespace {

// Test hook: LEM_FAULT_SOLVE_FAIL=N makes the N-th solve of the process fail
// as one that neither solver finishes would (tests of that path; a cap on
// the iterations cannot place the failure after the first solve).
bool injected_failure(std::int64_t solve) {
  const char* wanted = std::getenv("LEM_FAULT_SOLVE_FAIL");
  return wanted && std::strtoll(wanted, nullptr, 10) == solve;
}

struct Stages {
  PetscLogStage assembly, pc_setup, solve, solve_tighter;
};

// Registered together, so that -log_view lists them in this order.
const Stages& log_stages() {
  static const Stages stages{log_stage("Assembly"), log_stage("PC setup"), log_stage("Solve"),
                             log_stage("Solve, tighter rtol")};
  return stages;
}

}  // namespace

ElasticSystem::ElasticSystem(DistributedLattice& lattice, const SolverOptions& options)
    : lattice_(lattice) {
  LogStageScope stage(log_stages().assembly);
  const MPI_Comm comm = lattice_.comm;
  const int owned = lattice_.owned;

  // Ghosted displacement vector: owned dofs, then those of the ghost nodes.
  std::vector<PetscInt> ghosts(lattice_.global_index.begin() + owned, lattice_.global_index.end());
  LEM_PETSC(VecCreateGhostBlock(comm, 3, 3 * owned, PETSC_DECIDE,
                                static_cast<PetscInt>(ghosts.size()), ghosts.data(), u_.replace()));
  LEM_PETSC(VecDuplicate(u_, b_.replace()));

  // Exact block preallocation: the diagonal block plus one block per bond.
  std::vector<PetscInt> diag(owned, 1), off(owned, 0);
  double k_sum = 0;
  std::vector<char> has_bond(owned, 0);
  for (int b = 0; b < lattice_.local_bonds(); ++b) {
    const auto [p, q] = lattice_.bond_ends[b];
    for (int e = 0; e < 2; ++e) {
      const int me = e ? q : p, other = e ? p : q;
      if (me >= owned) continue;
      (other < owned ? diag : off)[me] += 1;
      k_sum += lattice_.bond_stiffness[b];
      has_bond[me] = 1;
    }
  }
  LEM_PETSC(MatCreate(comm, K_.replace()));
  LEM_PETSC(MatSetSizes(K_, 3 * owned, 3 * owned, PETSC_DETERMINE, PETSC_DETERMINE));
  LEM_PETSC(MatSetBlockSize(K_, 3));
  LEM_PETSC(MatSetType(K_, MATAIJ));
  default_no_inodes();
  read_petsc_options([&] { LEM_PETSC(MatSetFromOptions(K_)); });
  LEM_PETSC(MatXAIJSetPreallocation(K_, 3, diag.data(), off.data(), nullptr, nullptr));
  LEM_PETSC(MatSetOption(K_, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE));
  LEM_PETSC(MatSetOption(K_, MAT_SYMMETRIC, PETSC_TRUE));
  LEM_PETSC(MatSetOption(K_, MAT_SYMMETRY_ETERNAL, PETSC_TRUE));

  // Constrained rows get a typical diagonal value so that they do not spoil
  // the conditioning: the mean of k over a node's bonds times 1 (trace/3 of
  // sum k n n^T is sum k / 3 per node, i.e. about 2.3 k for 7 bonds).
  double sums[2] = {k_sum, 0};
  for (char h : has_bond) sums[1] += h;
  double totals[2];
  MPI_Allreduce(sums, totals, 2, MPI_DOUBLE, MPI_SUM, comm);
  diagonal_scale_ = totals[1] > 0 ? totals[0] / (3.0 * totals[1]) : 1.0;
  ground_ = diagonal_scale_ * options.ground_stiffness;

  // Rigid-body modes as the near null space of the multigrid preconditioner.
  VecHandle coords;
  LEM_PETSC(VecCreateMPI(comm, 3 * owned, PETSC_DETERMINE, coords.replace()));
  LEM_PETSC(VecSetBlockSize(coords, 3));
  PetscScalar* c = nullptr;
  LEM_PETSC(VecGetArray(coords, &c));
  for (int n = 0; n < owned; ++n)
    for (int a = 0; a < 3; ++a) c[3 * n + a] = lattice_.coords[n][a];
  LEM_PETSC(VecRestoreArray(coords, &c));
  NullSpaceHandle rigid;
  LEM_PETSC(MatNullSpaceCreateRigidBody(coords, rigid.replace()));
  LEM_PETSC(MatSetNearNullSpace(K_, rigid));

  LEM_PETSC(KSPCreate(comm, ksp_.replace()));
  if (options.solver_operator == SolverOperator::bonds)
    bonds_ = std::make_unique<BondOperator>(lattice_, ground_, diagonal_scale_);
  LEM_PETSC(KSPSetOperators(ksp_, operator_matrix(), K_));
  LEM_PETSC(KSPSetInitialGuessNonzero(ksp_, PETSC_TRUE));
  apply_solver_defaults(ksp_);
  if (bonds_) {
    // The fine-level smoother and residual of the multigrid use the bond
    // operator too (they are most of an iteration's products); -pc_use_amat
    // false keeps them on K.
    PC pc;
    LEM_PETSC(KSPGetPC(ksp_, &pc));
    LEM_PETSC(PCSetUseAmat(pc, PETSC_TRUE));
  }
  set_from_options(ksp_);
  // The levers, in one place: each a PC type put around the one before.
  levers_ =
      compose_levers(ksp_, options.levers, LeverSite{lattice_, K_, ground_, diagonal_scale_, 0});
  spectrum_solves_ = options.spectrum_solves;
  spectrum_prefix_ = options.spectrum_prefix;
  install_convergence_test();
  create_fallback();  // now, so that its -fallback_* options count as used
  stage.pop();
}

// The handles destroy the PETSc objects (also when the constructor throws).
ElasticSystem::~ElasticSystem() = default;

Mat ElasticSystem::operator_matrix() const {
  return bonds_ ? bonds_->matrix() : static_cast<Mat>(K_);
}

void ElasticSystem::set_operator(SolverOperator kind) {
  if (kind == SolverOperator::bonds && !bonds_)
    bonds_ = std::make_unique<BondOperator>(lattice_, ground_, diagonal_scale_);
  LEM_PETSC(KSPSetOperators(ksp_, kind == SolverOperator::bonds ? bonds_->matrix() : K_, K_));
  if (kind == SolverOperator::assembled) bonds_.reset();  // the KSP no longer refers to it
  pc_stale_ = true;
}

double ElasticSystem::bond_operator_bytes() const {
  return bonds_ ? bonds_->bytes_per_multiply() : 0.0;
}

void ElasticSystem::add_bond_block(int bond, double k_change) {
  const auto [p, q] = lattice_.bond_ends[bond];
  double n[3];
  bond_direction(lattice_, bond, n);
  for (int e = 0; e < 2; ++e) {
    const int me = e ? q : p, other = e ? p : q;
    if (me >= lattice_.owned) continue;
    const PetscInt row = static_cast<PetscInt>(lattice_.global_index[me]);
    const PetscInt cols[2] = {row, static_cast<PetscInt>(lattice_.global_index[other])};
    const std::uint8_t fr = lattice_.dof_flags[me], fo = lattice_.dof_flags[other];
    PetscScalar values[3 * 6];  // row-major: 3 rows, 6 columns
    for (int a = 0; a < 3; ++a)
      for (int c = 0; c < 3; ++c) {
        const double k = k_change * n[a] * n[c];
        const bool row_fixed = is_fixed(fr, a);
        values[a * 6 + c] = (row_fixed || is_fixed(fr, c)) ? 0.0 : k;
        values[a * 6 + 3 + c] = (row_fixed || is_fixed(fo, c)) ? 0.0 : -k;
      }
    LEM_PETSC(MatSetValuesBlocked(K_, 1, &row, 2, cols, values, ADD_VALUES));
  }
}

void ElasticSystem::assemble() {
  LogStageScope stage(log_stages().assembly);
  LEM_PETSC(MatZeroEntries(K_));
  for (int b = 0; b < lattice_.local_bonds(); ++b) add_bond_block(b, lattice_.bond_stiffness[b]);
  for (int n = 0; n < lattice_.owned; ++n) {
    const std::uint8_t f = lattice_.dof_flags[n];
    PetscScalar block[9] = {};
    for (int a = 0; a < 3; ++a) block[4 * a] = is_fixed(f, a) ? diagonal_scale_ : ground_;
    const PetscInt row = static_cast<PetscInt>(lattice_.global_index[n]);
    // Always touch the diagonal block so that it is part of the pattern.
    LEM_PETSC(MatSetValuesBlocked(K_, 1, &row, 1, &row, block, ADD_VALUES));
  }
  LEM_PETSC(MatAssemblyBegin(K_, MAT_FINAL_ASSEMBLY));
  LEM_PETSC(MatAssemblyEnd(K_, MAT_FINAL_ASSEMBLY));
  if (bonds_) bonds_->read_stiffness();
  operator_changed_ = true;
  for (SolverLever* lever : levers_) lever->operator_changed();
  stage.pop();
}

void ElasticSystem::set_bond_stiffness(int local_bond, double k) {
  const double change = k - lattice_.bond_stiffness[local_bond];
  lattice_.bond_stiffness[local_bond] = k;
  if (bonds_) bonds_->set_stiffness(local_bond, k);
  if (change != 0.0) add_bond_block(local_bond, change);
}

void ElasticSystem::finish_updates() {
  LEM_PETSC(MatAssemblyBegin(K_, MAT_FINAL_ASSEMBLY));
  LEM_PETSC(MatAssemblyEnd(K_, MAT_FINAL_ASSEMBLY));
  operator_changed_ = true;
  for (SolverLever* lever : levers_) lever->operator_changed();
}

void ElasticSystem::assemble_rhs(double top_displacement) {
  // b = -K_fc u_c on free rows, scale * u_c on constrained rows.
  auto prescribed = [&](int node, int a) {
    return (a == 2 && (lattice_.dof_flags[node] & kLoadedTop)) ? top_displacement : 0.0;
  };
  LEM_PETSC(VecZeroEntries(b_));
  PetscScalar* rhs = nullptr;
  LEM_PETSC(VecGetArray(b_, &rhs));
  for (int b = 0; b < lattice_.local_bonds(); ++b) {
    const auto [p, q] = lattice_.bond_ends[b];
    double n[3];
    bond_direction(lattice_, b, n);
    const double k = lattice_.bond_stiffness[b];
    for (int e = 0; e < 2; ++e) {
      const int me = e ? q : p, other = e ? p : q;
      if (me >= lattice_.owned) continue;
      const std::uint8_t fr = lattice_.dof_flags[me], fo = lattice_.dof_flags[other];
      // Relative prescribed displacement seen by this bond along n.
      double stretch = 0;
      for (int c = 0; c < 3; ++c) {
        if (is_fixed(fr, c)) stretch -= n[c] * prescribed(me, c);
        if (is_fixed(fo, c)) stretch += n[c] * prescribed(other, c);
      }
      if (stretch == 0.0) continue;
      for (int a = 0; a < 3; ++a)
        if (!is_fixed(fr, a)) rhs[3 * me + a] += k * n[a] * stretch;
    }
  }
  for (int n = 0; n < lattice_.owned; ++n)
    for (int a = 0; a < 3; ++a)
      if (is_fixed(lattice_.dof_flags[n], a)) rhs[3 * n + a] = diagonal_scale_ * prescribed(n, a);
  LEM_PETSC(VecRestoreArray(b_, &rhs));
}

SolveReport ElasticSystem::solve(double top_displacement, const EarlyStop* early) {
  assemble_rhs(top_displacement);

  // Initial guess: the previous solution scaled to the new load, or the
  // affine stretch for the first solve; constrained values set exactly.
  PetscScalar* u = nullptr;
  LEM_PETSC(VecGetArray(u_, &u));
  const double zlo = lattice_.box.lo[2], height = lattice_.box.length(2);
  const bool first = current_displacement_ == 0.0;
  const double scale = first ? 0.0 : top_displacement / current_displacement_;
  for (int n = 0; n < lattice_.owned; ++n) {
    const std::uint8_t f = lattice_.dof_flags[n];
    for (int a = 0; a < 3; ++a) {
      double& v = u[3 * n + a];
      if (is_fixed(f, a))
        v = (a == 2 && (f & kLoadedTop)) ? top_displacement : 0.0;
      else if (first)
        v = a == 2 ? top_displacement * (lattice_.coords[n][2] - zlo) / height : 0.0;
      else
        v *= scale;
    }
  }
  LEM_PETSC(VecRestoreArray(u_, &u));

  // A preconditioner kept from an earlier K can turn indefinite (e.g. once
  // loose nodes are pinned, their rows stiffen): retry once with a fresh one
  // from the same initial guess before giving up.
  if (!u_start_) LEM_PETSC(VecDuplicate(u_, u_start_.replace()));
  LEM_PETSC(VecCopy(u_, u_start_));
  SolveReport report = attempt_solve(early);
  bool built = report.preconditioner_built;  // by any attempt (restart replays it)
  int failed_iterations = 0;
  if (report.reason < 0 && !report.preconditioner_built) {
    LEM_PETSC(VecCopy(u_start_, u_));
    failed_iterations += report.iterations;
    pc_stale_ = true;
    report = attempt_solve(early);
    built = true;
  }
  if (report.reason < 0) {
    // Multigrid can still fail on a sample held by a hinge-like ligament
    // (seen near complete separation) while plain Jacobi-CG converges: use
    // it for this solve and build a fresh multigrid next time.
    LEM_PETSC(VecCopy(u_start_, u_));
    failed_iterations += report.iterations;
    report = fallback_solve();
    pc_stale_ = true;  // the next solve builds a new multigrid
  }
  report.iterations += failed_iterations;
  report.preconditioner_built = built;
  if (injected_failure(++solves_))
    throw NumericalError("linear solve did not converge: failure injected by "
                         "LEM_FAULT_SOLVE_FAIL at solve " +
                         std::to_string(solves_));
  if (report.reason < 0 || !std::isfinite(report.residual_norm)) {
    std::string hint;
    if (report.reason == KSP_DIVERGED_INDEFINITE_PC || report.reason == KSP_DIVERGED_INDEFINITE_MAT)
      hint = "; the lattice probably contains a floppy part (a mechanism) that the pruning of "
             "under-connected nodes did not remove, e.g. in a very porous sample";
    throw NumericalError(std::string("linear solve did not converge: ") +
                         KSPConvergedReasons[report.reason] + " after " +
                         std::to_string(report.iterations) + " iterations (residual norm " +
                         std::to_string(report.residual_norm) + ")" + hint);
  }
  if (std::find(spectrum_solves_.begin(), spectrum_solves_.end(), solves_) !=
      spectrum_solves_.end()) {
    PC pc = nullptr;
    LEM_PETSC(KSPGetPC(ksp_, &pc));
    probe_spectrum(lattice_, K_, pc, b_, u_start_, rtol(), spectrum_prefix_, solves_, 8);
  }
  current_displacement_ = top_displacement;
  operator_changed_ = false;
  equilibrium_ = !report.stopped_early;
  // The fallback solver runs to the same tolerance as the multigrid's.
  ties_settled_ = equilibrium_ && report.ties_settled;
  field_rtol_ = !equilibrium_                        ? std::numeric_limits<double>::infinity()
                : report.tightened && !ties_settled_ ? tightening_.rtol
                                                     : rtol();
  update_ghosts();
  return report;
}

SolveReport ElasticSystem::solve_to(double rtol, double top_displacement) {
  // Both solvers, since a failed multigrid solve is finished by the fallback.
  struct Tolerance {
    KSP ksp;
    PetscReal rtol = 0, abstol = 0, dtol = 0;
    PetscInt max_it = 0;
  } kept[2];
  kept[0].ksp = ksp_;
  kept[1].ksp = fallback_ksp_;
  for (Tolerance& t : kept) {
    LEM_PETSC(KSPGetTolerances(t.ksp, &t.rtol, &t.abstol, &t.dtol, &t.max_it));
    LEM_PETSC(KSPSetTolerances(t.ksp, rtol, t.abstol, t.dtol, t.max_it));
  }
  SolveReport report;
  tighter_solve_ = true;
  try {
    report = solve(top_displacement);
  } catch (...) {
    tighter_solve_ = false;
    for (Tolerance& t : kept) KSPSetTolerances(t.ksp, t.rtol, t.abstol, t.dtol, t.max_it);
    throw;
  }
  tighter_solve_ = false;
  for (Tolerance& t : kept) LEM_PETSC(KSPSetTolerances(t.ksp, t.rtol, t.abstol, t.dtol, t.max_it));
  return report;
}

double ElasticSystem::rtol() const {
  PetscReal rtol = 0;
  LEM_PETSC(KSPGetTolerances(ksp_, &rtol, nullptr, nullptr, nullptr));
  return rtol;
}

void ElasticSystem::install_convergence_test() {
  auto* c = new ConvergenceTest;
  c->system = this;
  LEM_PETSC(KSPGetAndClearConvergenceTest(ksp_, &c->inner, &c->inner_context, &c->inner_destroy));
  LEM_PETSC(KSPSetConvergenceTest(ksp_, ConvergenceTest::test, c, ConvergenceTest::destroy));
  convergence_ = c;
}

SolveReport ElasticSystem::attempt_solve(const EarlyStop* early) {
  const Stages& stages = log_stages();
  SolveReport report;
  double t0 = MPI_Wtime();
  const bool fresh = pc_stale_ || (operator_changed_ && !reuse_pc_);
  report.preconditioner_built = !pc_ready_ || fresh;
  if (report.preconditioner_built) before_build();
  LogStageScope pc_stage(stages.pc_setup);
  if (pc_ready_ && fresh) {
    set_up_preconditioner();
  } else {
    LEM_PETSC(KSPSetUp(ksp_));
    pc_stale_ = false;
  }
  pc_ready_ = true;
  pc_stage.pop();
  for (SolverLever* lever : levers_) lever->prepare(b_, u_);
  report.setup_seconds = MPI_Wtime() - t0;
  t0 = MPI_Wtime();
  LogStageScope solve_stage(tighter_solve_ ? stages.solve_tighter : stages.solve);
  // Only CG's iterate is the solution vector during the solve.
  PetscBool cg = PETSC_FALSE;
  LEM_PETSC(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(ksp_.get()), KSPCG, &cg));
  convergence_->early = cg ? early : nullptr;
  convergence_->tightening = cg && tightening_.wanted ? &tightening_ : nullptr;
  // A start the outermost lever (the last to prepare) solved directly is
  // checked on CG's true residual: with the preconditioned norm the check
  // would cost an application of the preconditioner, a second pass over
  // the factor.  Not when a bond is in doubt on it: the tightened solve
  // must bring its norm down by -fracture_tie_rtol / -ksp_rtol, which the
  // error (the preconditioned norm) does and a true residual already at
  // a factorization's rounding floor cannot.
  bool start_solved = cg && !levers_.empty() && levers_.back()->start_is_solution();
  if (start_solved && convergence_->tightening) {
    update_ghosts();
    start_solved = !tightening_.wanted();
  }
  KSPNormType kept_norm = KSP_NORM_DEFAULT;
  if (start_solved) {
    LEM_PETSC(KSPGetNormType(ksp_, &kept_norm));
    LEM_PETSC(KSPSetNormType(ksp_, KSP_NORM_UNPRECONDITIONED));
  }
  convergence_->tightened_at = -1;
  convergence_->settled = false;
  convergence_->stopped = false;
  convergence_->error = nullptr;
  const PetscErrorCode solved = KSPSolve(ksp_, b_, u_);
  convergence_->early = nullptr;
  convergence_->tightening = nullptr;
  if (start_solved && !solved) LEM_PETSC(KSPSetNormType(ksp_, kept_norm));
  if (!solved)
    for (SolverLever* lever : levers_) lever->after_solve();
  if (convergence_->error) std::rethrow_exception(convergence_->error);
  if (solved) {
    // A PETSc error inside KSPSolve leaves the solver mid-cycle: destroying
    // it as the exception unwinds can crash before the message is shown, so
    // it is leaked (the run ends on this error).
    ksp_.release();
    throw PetscFailure("KSPSolve(ksp_, b_, u_)", solved);
  }
  report.stopped_early = convergence_->stopped;
  solve_stage.pop();
  report.solve_seconds = MPI_Wtime() - t0;
  PetscInt its = 0;
  PetscReal rnorm = 0;
  LEM_PETSC(KSPGetIterationNumber(ksp_, &its));
  LEM_PETSC(KSPGetResidualNorm(ksp_, &rnorm));
  LEM_PETSC(KSPGetConvergedReason(ksp_, &report.reason));
  report.iterations = static_cast<int>(its);
  report.residual_norm = rnorm;
  if (convergence_->tightened_at >= 0) {
    report.tightened = true;
    report.tightened_iterations = static_cast<int>(its - convergence_->tightened_at);
    report.ties_settled = convergence_->settled;
  }
  return report;
}

void ElasticSystem::create_fallback() {
  {
    LEM_PETSC(KSPCreate(lattice_.comm, fallback_ksp_.replace()));
    apply_fallback_defaults(fallback_ksp_);
    PetscReal rtol, abstol, dtol;
    PetscInt max_it;
    LEM_PETSC(KSPGetTolerances(ksp_, &rtol, &abstol, &dtol, &max_it));
    LEM_PETSC(KSPSetTolerances(fallback_ksp_, rtol, abstol, dtol, 200000));
    set_from_options(fallback_ksp_);
  }
}

SolveReport ElasticSystem::fallback_solve() {
  LEM_PETSC(KSPSetOperators(fallback_ksp_, K_, K_));
  LogStageScope stage(tighter_solve_ ? log_stages().solve_tighter : log_stages().solve);
  SolveReport report;
  const double t0 = MPI_Wtime();
  LEM_PETSC(KSPSolve(fallback_ksp_, b_, u_));
  report.solve_seconds = MPI_Wtime() - t0;
  PetscInt its = 0;
  LEM_PETSC(KSPGetIterationNumber(fallback_ksp_, &its));
  LEM_PETSC(KSPGetResidualNorm(fallback_ksp_, &report.residual_norm));
  LEM_PETSC(KSPGetConvergedReason(fallback_ksp_, &report.reason));
  report.iterations = static_cast<int>(its);
  report.used_fallback = true;
  return report;
}

void ElasticSystem::set_reuse_preconditioner(bool reuse) {
  reuse_pc_ = reuse;
  LEM_PETSC(KSPSetReusePreconditioner(ksp_, reuse ? PETSC_TRUE : PETSC_FALSE));
}

void ElasticSystem::rebuild_preconditioner() { pc_stale_ = true; }

void ElasticSystem::before_build() {
  for (SolverLever* lever : levers_) lever->before_build();
}

void ElasticSystem::build_preconditioner() {
  before_build();
  LogStageScope stage(log_stages().pc_setup);
  set_up_preconditioner();
  stage.pop();
  pc_ready_ = true;
}

// KSPSetUp sets the preconditioner up again only for operators given since
// the last set-up (KSPSetOperators); K is changed in place, so hand it over
// again, or the preconditioner of the first solve would stay forever.
void ElasticSystem::set_up_preconditioner() {
  LEM_PETSC(KSPSetOperators(ksp_, operator_matrix(), K_));
  LEM_PETSC(KSPSetReusePreconditioner(ksp_, PETSC_FALSE));
  LEM_PETSC(KSPSetUp(ksp_));
  LEM_PETSC(KSPSetReusePreconditioner(ksp_, reuse_pc_ ? PETSC_TRUE : PETSC_FALSE));
  pc_stale_ = false;
}


void ElasticSystem::pin_nodes(const std::vector<int>& local_nodes) {
  for (int n : local_nodes) {
    const std::uint8_t old = lattice_.dof_flags[n];
    lattice_.dof_flags[n] = kFixX | kFixY | kFixZ | kPinned;
    if (n >= lattice_.owned || (old & kPinned)) continue;
    // Free rows carried the ground spring, fixed rows the constrained scale.
    PetscScalar block[9] = {};
    for (int a = 0; a < 3; ++a) block[4 * a] = is_fixed(old, a) ? 0.0 : diagonal_scale_ - ground_;
    const PetscInt row = static_cast<PetscInt>(lattice_.global_index[n]);
    LEM_PETSC(MatSetValuesBlocked(K_, 1, &row, 1, &row, block, ADD_VALUES));
  }
  if (bonds_) bonds_->constraints_changed();
  for (SolverLever* lever : levers_) lever->constraints_changed();
}

}  // namespace lem
