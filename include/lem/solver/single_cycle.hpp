// The multigrid cycle of the elastic solver applied in single precision
// (-solver_cycle_precision single, the default).
//
// CG stays in double precision with its double operator; only the
// preconditioner changes.  At every build of the preconditioner GAMG builds
// its hierarchy from K as always; this object then copies what one cycle
// reads into float: the fine level as the bond arrays (two 32-bit node
// indices and sqrt(k) n per bond, 20 bytes read per bond instead of 40;
// sqrt(k) n, the Jacobi diagonal and the Chebyshev step are read again
// whenever K changed, as the double cycle's fine level follows every
// rupture even while the multigrid is kept), every coarser
// operator, interpolation and restriction as a block-sparse matrix of float
// blocks (the 6 x 6 blocks of the rigid-body aggregates, one 32-bit index per
// block: about 4 bytes per nonzero instead of 12), and each Chebyshev/Jacobi
// smoother as its inverse diagonal and step.  It then applies the same
// cycle (V or W, one smoothing step before and after, the coarsest grid
// solved by GAMG's own double-precision solver) with float matrices and
// double vectors: the ghost exchanges stay PETSc's scatters.  The cycle is
// a fixed symmetric positive definite operator, which is all CG needs; the
// solution is as accurate as with the double cycle (the residual CG tests
// is the double one).
//
// Supported smoothers: GAMG's default Chebyshev with Jacobi, one sweep per
// level (-mg_levels_ksp_max_it 1, the solver's default); other settings are
// refused with a message naming them.
//
// It is a solver lever (a PC type, lem_single_cycle, chosen by
// -solver_cycle_precision single) registered first, so the innermost: it
// copies the multigrid's own levels and must wrap the multigrid itself.
#pragma once

#include "lem/base/petsc_handle.hpp"
#include "lem/solver/wrapped_lever.hpp"
#include "lem/system/distributed_lattice.hpp"

#include <petscksp.h>

#include <memory>
#include <string>
#include <vector>

namespace lem {

struct FloatBondOperator;  // float_operators.hpp (the fine level in float)

class SingleCycle final : public WrappedLever {
 public:
  static constexpr const char* kType = "lem_single_cycle";
  static constexpr const char* kName = "multigrid cycle in single precision";
  /// The registry entry: -solver_cycle_precision double|single (0, or
  /// kGiven when given, kByDefault when single is the default).
  static SolverLeverEntry entry();
  static constexpr double kGiven = 1, kByDefault = 2;

  SingleCycle();
  ~SingleCycle() override;

  /// The single-precision cycle (true, the default) or the inner
  /// double-precision multigrid itself (false): benchmarks compare both.
  void use_single(bool single) { single_ = single; }
  bool single() const { return single_; }

  /// The cycle that is `ksp`'s preconditioner, or nullptr if it is none
  /// (or one that stepped aside).
  static SingleCycle* of(KSP ksp);
  /// Whether `pc` is PETSc's own multigrid (gamg or mg): the preconditioners
  /// whose levels this class (and lem_bench's per-level accounting) walks.
  static bool can_wrap(PC pc);
  /// The inner (double-precision) multigrid.
  PC inner() const { return inner_; }

  /// Counts and times of the float cycle, per level, finest first, since
  /// the last reset (PCApply calls).
  struct LevelStats {
    long long rows = 0, nonzeros = 0;  // global (fine level: 9 per bond, as K's blocks)
    double visits = 0;                 // cycle visits
    double products = 0;               // operator products (smoother + residual)
    double transfers = 0;              // restriction + interpolation products
    double seconds = 0;                // max over ranks
    double bytes = 0;                  // model, summed over ranks
  };
  std::vector<LevelStats> level_stats() const;
  double applications() const { return applications_; }
  /// Seconds spent in the float cycle on this rank (since the last reset),
  /// the fine-level refreshes included.
  double apply_seconds() const { return apply_seconds_; }
  /// How often an application found K changed and read the fine level
  /// again: the bonds (refresh_seconds) and the smoother's diagonal and
  /// step (probe_seconds), seconds on this rank since the last reset.
  double refreshes() const { return refreshes_; }
  double refresh_seconds() const { return refresh_seconds_; }
  double probe_seconds() const { return probe_seconds_; }
  /// "single cycle: N applications, X s; R refreshes: Y s reading bonds,
  /// Z s probing smoothers", the seconds the most of any rank.  Collective.
  std::string work_line() const override;
  void reset_stats();
  /// Bytes of this rank's float copies.
  double memory_bytes() const;

 private:
  friend class WrappedLever;
  struct Level;
  /// Throws InputError unless the wrapped PC is a multigrid with the
  /// smoother the cycle copies.
  void wrapped(const LeverSite& site) override;
  void inner_built() override { build(); }
  static PetscErrorCode apply(PC pc, Vec b, Vec x);
  static void check_smoother_options();
  void build();
  void cycle(int level, bool zero_guess);
  void residual(int level, Vec b, Vec x, Vec r);  // r = b - A x
  void probe_smoother(Level& level);

  const DistributedLattice* lattice_ = nullptr;
  double ground_ = 0, scale_ = 0;
  bool single_ = true;
  // Chosen by default, it steps aside (applies what it wraps, and copies
  // nothing) around a preconditioner that is no multigrid; given, it refuses.
  bool aside_ = false;
  void step_aside();
  int cycles_ = 2;                              // 1 V, 2 W
  std::vector<std::unique_ptr<Level>> levels_;  // coarsest first, as PCMG numbers them
  std::unique_ptr<FloatBondOperator> fine_;
  double applications_ = 0, apply_seconds_ = 0;
  double refreshes_ = 0, refresh_seconds_ = 0, probe_seconds_ = 0;
};

}  // namespace lem
