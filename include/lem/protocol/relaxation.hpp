// Relaxation at a fixed load (paper appendix A): break the critical bonds,
// pin the pieces they cut loose, solve, and repeat until no bond is
// critical.  `Relaxation` is the room for other schemes (local patch solves
// before a global one); `GlobalRelaxation` is the paper's cycle, where
// every solve is a global one, and the reference the others are tested
// against.
#pragma once

#include "lem/distributed_lattice.hpp"
#include "lem/elastic_system.hpp"
#include "lem/protocol/break_rule.hpp"
#include "lem/protocol/damage_ledger.hpp"
#include "lem/protocol/options.hpp"
#include "lem/protocol/preconditioner_policy.hpp"
#include "lem/protocol/progress.hpp"
#include "lem/protocol/recorder.hpp"
#include "lem/protocol/state.hpp"
#include "lem/pieces.hpp"

#include <cstdint>
#include <functional>

namespace lem {

struct RelaxationOutcome {
  int cycles = 0;              // solves after ruptures
  std::int64_t broken = 0;     // bonds broken at this load
  bool disconnected = false;   // no piece joins the bottom to the top face any more
};

/// The parts of the protocol a relaxation works with.
struct RelaxationParts {
  DistributedLattice& lattice;
  ElasticSystem& system;
  const FractureOptions& options;
  const CriticalBonds& critical;
  DamageLedger& ledger;
  PreconditionerPolicy& solver;
  FractureRecorder& recorder;
  ProgressReporter& progress;
  const RunClock& clock;
  FractureTally& tally;
  /// Called between relaxation cycles of load step `step`, after `cycles`
  /// of them, on every rank (each cycle ends on a global solve); it may
  /// throw to leave the relaxation there (a stop request).
  std::function<void(std::int64_t step, int cycles)> between_cycles = {};
};

class Relaxation {
 public:
  explicit Relaxation(const RelaxationParts& parts);
  virtual ~Relaxation() = default;
  /// Starting from an equilibrium at `top_displacement`, break and relax
  /// until no bond is critical in the global field, the faces separate, or
  /// (options.stop_within_step) the stress falls below the stop level.
  /// Ends on a global equilibrium.  Collective.
  virtual RelaxationOutcome relax(std::int64_t step, double top_displacement, double strain,
                                  double stress_before) = 0;

 protected:
  /// Break `batch` as one numbered batch (generation `cycle` of this load
  /// step), pin the pieces it cut loose.  Returns whether some piece still
  /// joins the faces.  Collective.
  bool break_batch(const std::vector<Rupture>& batch, std::int64_t step, int cycle,
                   double strain);
  /// Count a broken batch in `out` (one more cycle) and report progress.
  void note_batch(std::int64_t step, const std::vector<Rupture>& batch, RelaxationOutcome& out);
  /// A relaxation solve after a batch; with options.decision_safety > 0 it
  /// may end as soon as the next batch is decided (CriticalBonds::decided).
  /// A solve that leaves no bond critical has gone to -ksp_rtol.  Collective.
  SolveReport solve_for_decision(double top_displacement);
  /// The batch that breaks now in the current equilibrium: when some bond is
  /// in doubt (CriticalBonds::in_doubt), decided on a re-solve to
  /// options.tie_rtol first.  Collective.
  std::vector<Rupture> next_batch(double top_displacement);
  /// options.stop_within_step and the stress has fallen below the stop level.
  bool stress_fell(double stress_before) const;
  /// Before every cycle but the first: RelaxationParts::between_cycles.
  void next_cycle(std::int64_t step, const RelaxationOutcome& out) const;

  RelaxationParts p_;

 private:
  PieceFinder pieces_;
};

/// The paper's cycle: every relaxation is a global solve.
class GlobalRelaxation : public Relaxation {
 public:
  using Relaxation::Relaxation;
  RelaxationOutcome relax(std::int64_t step, double top_displacement, double strain,
                          double stress_before) override;
};

}  // namespace lem
