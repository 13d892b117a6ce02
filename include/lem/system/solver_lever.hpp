// Solver levers: optional preconditioners put around the multigrid of the
// elastic system, each a PETSc PC type registered with PCRegister.
//
// The elastic system knows levers only through this header.  A lever is a
// registry entry (its PC type, the option that chooses it, with its help
// string) and a PC type whose data is a SolverLever: the system creates the
// PC by its type name (PETSc's registry), hands it the preconditioner it
// wraps and the data it may read (wrap), puts it in the KSP, and then calls
// the hooks below at the points of a solve.  The built-in levers live in
// the solver module (lem/solver/levers.hpp, src/solver/); a program may add
// its own with register_solver_lever() before it reads its options.
#pragma once

#include "lem/base/options.hpp"
#include "lem/base/petsc_handle.hpp"
#include "lem/system/distributed_lattice.hpp"

#include <petscksp.h>

#include <functional>
#include <string>
#include <vector>

namespace lem {

/// What a lever may read of the system it preconditions.
struct LeverSite {
  const DistributedLattice& lattice;
  Mat K;               // the assembled matrix, which the multigrid is built from
  double ground;       // the diagonal of free dofs (-lattice_ground_stiffness)
  double constrained;  // the diagonal of fixed dofs (a typical bond stiffness)
  double setting;      // the value its option was given (1 for a flag)
};

/// The calls the elastic system makes on a lever.  Every call is
/// collective.
class SolverLever {
 public:
  virtual ~SolverLever() = default;
  /// Take `inner` (the KSP's preconditioner until now) as the preconditioner
  /// this one wraps, and the site.  May throw InputError.
  virtual void wrap(const LeverSite& site, PC inner) = 0;
  /// K changed in place (values).
  virtual void operator_changed() {}
  /// Nodes were pinned (their rows constrained; K changed too).
  virtual void constraints_changed() { operator_changed(); }
  /// Before a build of the preconditioner from the current K.
  virtual void before_build() {}
  /// Before KSPSolve on (b, u), once the preconditioner is set up (u is the
  /// KSP's solution vector and may be moved).
  virtual void prepare(Vec, Vec) {}
  /// After prepare: u already solves K u = b to a factorization's rounding
  /// (the lever solved it directly), so CG need only check its true
  /// residual, which takes no application of the preconditioner.
  virtual bool start_is_solution() const { return false; }
  /// After a KSPSolve that returned without a PETSc error.
  virtual void after_solve() {}
  /// What the lever learnt from the solves, which a checkpoint keeps (each
  /// column shared, never changed once learnt); empty if it learns nothing.
  virtual std::vector<VecHandle> learnt_space() const { return {}; }
  /// A resumed run: the columns the checkpoint kept.
  virtual void restore_learnt_space(std::vector<VecHandle>) {}
  /// The option of a lever that learns ("" if it learns nothing): what it
  /// learns depends on the rank count.
  virtual std::string learning_option() const { return ""; }
  /// A line for the log at the end of a run: what the lever spent, by
  /// stage ("" if it has nothing to say).  Collective.
  virtual std::string work_line() const { return ""; }
};

/// A lever's registry entry.
struct SolverLeverEntry {
  /// Its PC type ("lem_..."), registered with PCRegister.
  std::string type;
  /// PETSc's create function of the type: makes the PC's SolverLever
  /// (make_lever_pc does the PETSc side).
  PetscErrorCode (*create)(PC) = nullptr;
  /// The option that chooses it (shown in messages).
  std::string option;
  /// Reads its options into the group; returns its setting, 0 when the run
  /// does not use it.
  std::function<double(OptionGroup&)> read;
  /// Levers of one non-empty `excludes` word cannot be chosen together; the
  /// word says what is chosen ("one deflation space").
  std::string excludes;
};

/// Add a lever (PETSc's registry gets its type before the options are
/// read, so this may come before PetscInitialize); one of an existing type
/// replaces it.
/// Levers are put around the multigrid in the order of registration, the
/// first innermost.
void register_solver_lever(SolverLeverEntry entry);
const std::vector<SolverLeverEntry>& solver_levers();

/// A lever the options chose, and its setting.
struct LeverChoice {
  std::string type;
  double setting = 1;
};
/// Read the options of every registered lever (group "Solver levers"), in
/// order of registration, and refuse choices that exclude each other.
std::vector<LeverChoice> read_lever_options(MPI_Comm comm);

/// Put each chosen lever around `ksp`'s preconditioner, in order; returns
/// them (owned by their PCs, so by the KSP).
std::vector<SolverLever*> compose_levers(KSP ksp, const std::vector<LeverChoice>& levers,
                                         const LeverSite& site);
/// The SolverLever of a PC made by a lever's type, or nullptr.
SolverLever* lever_of(PC pc);
/// Attach `lever` to `pc` (a lever type's create function calls this), so
/// that lever_of finds it.
void attach_lever(PC pc, SolverLever* lever);

/// The W cycle and one sweep per level on a multigrid PC with levels,
/// unless options set them (the defaults of the multigrid, which a lever
/// applies to the multigrid it wraps after building it).
PetscErrorCode apply_multigrid_level_defaults(PC pc);

}  // namespace lem
