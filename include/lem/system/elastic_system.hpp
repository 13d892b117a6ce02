// The distributed stiffness system K u = b of a spring lattice under uniaxial
// tension, solved with PETSc's KSP (CG + algebraic multigrid by default).
//
// K is an MPIAIJ (or BAIJ, from -mat_type) matrix with block size 3 whose
// nonzero pattern is fixed at construction from the bond graph: changing a
// bond's stiffness (a rupture is k -> 0) adds the difference of its 6x6 block
// in place.  Each rank assembles only its own rows, from the bonds touching
// its nodes, so assembly needs no communication.  Constrained degrees of
// freedom keep identity rows and columns (scaled by a typical diagonal value);
// their prescribed values enter through the right-hand side.
#pragma once

#include "lem/system/distributed_lattice.hpp"
#include "lem/system/solver_lever.hpp"
#include "lem/base/petsc_handle.hpp"

#include <petscksp.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace lem {

class BondOperator;

/// The most columns a lever learns (-solver_ritz_deflation), which a
/// checkpoint holds.
constexpr int kMostRitzColumns = 64;

/// The operator CG applies: the assembled matrix K, or K applied bond by bond
/// (the preconditioner is built from the assembled K either way).
enum class SolverOperator { assembled, bonds };

struct SolveReport {
  int iterations = 0;
  double residual_norm = 0;
  KSPConvergedReason reason = KSP_CONVERGED_ITERATING;
  double setup_seconds = 0;           // KSPSetUp: preconditioner build (0 when reused)
  double solve_seconds = 0;           // KSPSolve
  bool preconditioner_built = false;  // this solve (re)built the preconditioner
  bool used_fallback = false;         // multigrid failed twice; CG + Jacobi (-fallback_*) solved
  bool stopped_early = false;         // an EarlyStop test ended the solve before -ksp_rtol
  bool tightened = false;             // went on from -ksp_rtol for near-ties (Tightening)
  int tightened_iterations = 0;       // of `iterations`, those after that point
  bool ties_settled = false;          // ... and ended when Tightening::settled said so
};

/// A tighter tolerance that a CG solve may go on to once it meets
/// -ksp_rtol, in the same Krylov space: `wanted()`, asked at that point
/// with the iterate current (ghosts included), says whether this field
/// needs it.  Then, if set, `settled()` is asked at that point and every
/// `interval` iterations after it, and true ends the solve before `rtol`
/// (the caller has decided what it needed).  A CG restarted from the
/// converged field must find the slow modes again.  Collective: every rank
/// must return the same answers.
struct Tightening {
  double rtol = 0;
  std::function<bool()> wanted;
  std::function<bool()> settled = {};
  int interval = 4;
};

/// A test that may end a CG solve before -ksp_rtol: every `interval`
/// iterations the system makes the iterate current (ghosts included) and
/// calls `decided()`, which may read bond_tensions(); true ends the solve.
/// Collective: every rank must return the same answer.
struct EarlyStop {
  int interval = 4;
  std::function<bool()> decided;
  /// Called when CG starts from the initial guess (a failed attempt is
  /// retried from it): iterates of an earlier attempt are no baseline.
  std::function<void()> restart = {};
};

/// Macroscopic response to a top displacement (paper sect. 2.3).
struct TensionResponse {
  double top_displacement = 0;  // Delta
  double reaction = 0;          // total z force applied on the top nodes
  double stress_zz = 0;         // reaction / cross-section
  double strain_zz = 0;         // Delta / height
  double strain_xx = 0,
         strain_yy = 0;      // lateral_strains(): face displacements, rotation about z removed
  double young_modulus = 0;  // stress_zz / strain_zz
  double poisson_ratio = 0;  // -(strain_xx + strain_yy) / (2 strain_zz)
  double stored_energy = 0;  // 1/2 sum_bonds k (stretch)^2
  double ground_energy = 0;  // 1/2 sum_free dofs g u^2: the ground springs (g = ground_)
  double external_work = 0;  // 1/2 reaction * Delta
};

/// The KSP of patch solves (relax_patch): CG + Jacobi by default, to `rtol`,
/// then the -patch_ksp_* / -patch_pc_* options.  The caller destroys it.
KSP create_patch_solver(MPI_Comm comm, double rtol);
/// The program's own solver settings; PETSc's -ksp_*, -pc_* and -mat_*
/// options are read by the solver objects themselves.
struct SolverOptions {
  /// -lattice_ground_stiffness, relative to the mean nodal stiffness.
  double ground_stiffness = 1e-10;
  /// -solver_operator: what CG multiplies by.
  SolverOperator solver_operator = SolverOperator::bonds;
  /// The solver levers chosen by their options, in the order they are put
  /// around the multigrid (lem/system/solver_lever.hpp).
  std::vector<LeverChoice> levers;
  /// -solver_spectrum_solves / -solver_spectrum_prefix: the solves (counted
  /// from 1 by the process) at which the spectrum probe runs, and where it
  /// writes (a diagnostic; src/system/spectrum_probe.hpp).
  std::vector<std::int64_t> spectrum_solves;
  std::string spectrum_prefix = "spectrum";
};
/// Read -lattice_ground_stiffness and record the solver defaults (CG +
/// GAMG, ...) in the option registry, so that -help and the provenance show
/// them.  With -help, PETSc also lists its own KSP and PC options.
SolverOptions read_solver_options(MPI_Comm comm);

class ElasticSystem {
 public:
  /// Creates the matrix (exact preallocation), vectors and KSP with the
  /// solver defaults, then lets the -mat_type, -ksp_* and -pc_* options
  /// override them.  Does not assemble.
  ElasticSystem(DistributedLattice& lattice, const SolverOptions& options);
  ~ElasticSystem();
  ElasticSystem(const ElasticSystem&) = delete;
  ElasticSystem& operator=(const ElasticSystem&) = delete;

  /// Assemble K from the current bond stiffnesses.
  void assemble();
  /// Change one local bond's stiffness in place (every rank holding the bond
  /// must call this for it; the pattern of K never changes).  Call
  /// finish_updates() collectively before the next solve.
  void set_bond_stiffness(int local_bond, double k);
  void finish_updates();

  /// Solve for a top displacement.  The previous solution (scaled to the new
  /// load) is the initial guess.  Throws NumericalError if KSP diverges.
  /// With `early` (CG only), the solve may end before -ksp_rtol when the
  /// test says so; the state is then no equilibrium until the next full
  /// solve, and the field kept by the test's last mark_check() stays beside
  /// it (the certificate of its decisions).
  SolveReport solve(double top_displacement, const EarlyStop* early = nullptr);
  /// The same to relative tolerance `rtol` instead of -ksp_rtol (the
  /// fallback solver too); the tolerances are restored afterwards.
  SolveReport solve_to(double rtol, double top_displacement);
  /// -ksp_rtol.
  double rtol() const;
  /// Every later solve that meets -ksp_rtol (above `t.rtol`) asks
  /// `t.wanted()` and, if so, goes on to `t.rtol` (SolveReport::tightened).
  /// An empty `t.wanted` removes it.
  void set_tightening(Tightening t) { tightening_ = std::move(t); }
  /// The relative tolerance the field meets: that of the solve that made
  /// it, or the Tightening's if it went on to it (infinity when not
  /// at_equilibrium()).
  double field_rtol() const { return field_rtol_; }
  /// Whether the last solve went on past -ksp_rtol until Tightening::
  /// settled() said so (false again once the field is scaled or replaced).
  bool ties_settled() const { return ties_settled_; }

  /// Keep the current preconditioner for later solves even when K changes
  /// (it is built anyway by the first solve).  rebuild_preconditioner() makes
  /// the next solve build a fresh one from the current K.
  void set_reuse_preconditioner(bool reuse);
  void rebuild_preconditioner();
  bool preconditioner_rebuild_pending() const { return pc_stale_; }
  /// Build the preconditioner from the current K now (restart replay).
  void build_preconditioner();

  /// The system is linear in the load: while K is unchanged since the last
  /// solve, the solution for another top displacement is the last one scaled
  /// (with the check field of a decided solve).  No solve; throws
  /// std::logic_error if K changed since.
  void rescale(double top_displacement);

  /// Whether the field solves K u = b to -ksp_rtol (false after a solve
  /// that an EarlyStop test ended).
  bool at_equilibrium() const { return equilibrium_; }
  /// Inside an EarlyStop test: keep the current CG iterate as the check
  /// field (an error estimate of a force is then its change since).
  void mark_check();
  /// Inside an EarlyStop test that ends the solve: move the check field to
  /// u + factor (u_check - u), the far end of the error bound it stands for.
  void stretch_check(double factor);
  /// Tensions of the check field (only when not at_equilibrium()).
  std::vector<double> check_tensions() const;
  /// sigma_zz of a field with these bond tensions (response().stress_zz of
  /// the current ones).  Collective.
  double stress_of(const std::vector<double>& tensions) const;

  /// Pin the given local nodes (every rank passes its local copies, owned
  /// and ghost): their rows become constrained at zero displacement.  Their
  /// bonds must already carry k = 0.  Call finish_updates() afterwards.
  void pin_nodes(const std::vector<int>& local_nodes);

  /// Owned displacements as a flat array (3 per owned node), the check
  /// field's the same way (empty at an equilibrium), and the top
  /// displacement they belong to; set_state restores them (restart: the
  /// values must be those of the current K).
  std::vector<double> solution() const;
  std::vector<double> check_solution() const;
  double top_displacement() const { return current_displacement_; }
  void set_state(const std::vector<double>& owned, double top_displacement,
                 const std::vector<double>& owned_check = {});
  /// What the solver learnt from the solves so far, which a resumed run
  /// needs to solve as the uninterrupted one: the space of the lever that
  /// learns (-solver_ritz_deflation), its columns shared (a column never
  /// changes once learnt); empty without one.
  std::vector<VecHandle> learnt_space() const;
  /// A resumed run: the learnt space, each column as this rank's owned
  /// values (laid out as solution()); ignored without the option.
  void restore_learnt_space(const std::vector<std::vector<double>>& columns);
  /// The option that learns between solves ("" if none): what it learns
  /// depends on the rank count, so a checkpoint of another rank count
  /// cannot be continued as either uninterrupted run would.
  std::string learning_option() const;

  /// Relax only the given owned nodes (every other displacement held): solve
  /// K_PP du_P = r_P for the out-of-balance forces r = b - K u of the current
  /// K and load, by CG (options prefix -patch_, default Jacobi) to `rtol` of
  /// |r_P|, and add du_P.  Collective (a rank may pass no node).  The state
  /// is then no equilibrium of K: only solve() makes it one again.  A patch
  /// solve that does not converge leaves u unchanged (reason < 0).
  SolveReport relax_patch(const std::vector<int>& owned_nodes, double rtol);

  TensionResponse response() const;
  /// Tension of every local bond (positive when stretched): k n.(u_j - u_i).
  std::vector<double> bond_tensions() const;
  /// Displacements of the owned nodes.
  std::vector<Point> owned_displacements() const;

  Mat matrix() const { return K_; }
  /// The operator CG uses: the bond operator's shell, or K itself.
  Mat operator_matrix() const;
  /// Change the operator of CG (benchmarks; the solver keeps its settings).
  void set_operator(SolverOperator kind);
  /// Bytes one product of the bond operator moves (its model; 0 when unused).
  double bond_operator_bytes() const;
  KSP ksp() const { return ksp_; }
  /// The levers around the multigrid, innermost first.
  const std::vector<SolverLever*>& levers() const { return levers_; }
  /// Typical diagonal value used on constrained rows.
  double constrained_diagonal() const { return diagonal_scale_; }

 private:
  void add_bond_block(int bond, double k_change);
  void assemble_rhs(double top_displacement);
  void update_ghosts() const;
  SolveReport attempt_solve(const EarlyStop* early);
  struct ConvergenceTest;
  void install_convergence_test();
  void set_up_preconditioner();  // from the current K, now
  void before_build();           // the levers' hook, before a build
  void create_fallback();
  SolveReport fallback_solve();
  Point local_displacement(const PetscScalar* u_local, int node) const;

  DistributedLattice& lattice_;
  MatHandle K_;
  VecHandle u_;  // ghosted: owned values followed by ghost values
  VecHandle b_;
  VecHandle u_start_;  // initial guess kept for a retry
  VecHandle u_check_;  // ghosted: the check field of a decided solve (mark_check)
  KspHandle ksp_;
  ConvergenceTest* convergence_ = nullptr;  // owned by ksp_ (destroyed with it)
  KspHandle fallback_ksp_;                  // CG + Jacobi, for solves the multigrid fails
  std::vector<SolverLever*> levers_;        // owned by their PCs (so by ksp_)
  std::unique_ptr<BondOperator> bonds_;     // -solver_operator bonds
  double diagonal_scale_ = 1.0;
  double ground_ = 0.0;  // diagonal added on free dofs (-lattice_ground_stiffness)
  double current_displacement_ = 0.0;
  bool operator_changed_ = true;
  bool equilibrium_ = false;                   // u_ solves K u = b to -ksp_rtol (not stopped early)
  bool reuse_pc_ = false;                      // keep the preconditioner when K changes
  bool pc_stale_ = false;                      // the next solve must build a fresh preconditioner
  bool pc_ready_ = false;                      // a preconditioner has been built
  bool tighter_solve_ = false;                 // in solve_to: -log_view stage "Solve, tighter rtol"
  Tightening tightening_;                      // set_tightening
  double field_rtol_ = 0;                      // field_rtol()
  bool ties_settled_ = false;                  // ties_settled()
  std::int64_t solves_ = 0;                    // by this process (test hook LEM_FAULT_SOLVE_FAIL)
  std::vector<std::int64_t> spectrum_solves_;  // -solver_spectrum_solves
  std::string spectrum_prefix_;
};

}  // namespace lem
