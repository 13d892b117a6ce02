// Relaxation at a fixed load (paper appendix A): break the critical bonds,
// pin the pieces they cut loose, solve, and repeat until no bond is
// critical.  `Relaxation` holds that loop, once, and the room for other
// schemes: what a cycle does after its batch broke (local patch solves
// before a global one); `GlobalRelaxation` is the paper's cycle, where
// every solve is a global one, and the reference the others are tested
// against.
#pragma once

#include "lem/system/distributed_lattice.hpp"
#include "lem/system/elastic_system.hpp"
#include "lem/protocol/break_rule.hpp"
#include "lem/protocol/damage_ledger.hpp"
#include "lem/protocol/options.hpp"
#include "lem/protocol/preconditioner_policy.hpp"
#include "lem/protocol/progress.hpp"
#include "lem/protocol/recorder.hpp"
#include "lem/protocol/state.hpp"
#include "lem/system/pieces.hpp"

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace lem {

struct RelaxationOutcome {
  int cycles = 0;             // solves after ruptures
  std::int64_t broken = 0;    // bonds broken at this load
  bool disconnected = false;  // no piece joins the bottom to the top face any more
};

/// How a relaxation cycle (Relaxation::cycle) ended.
struct CycleEnd {
  bool joined = true;          // some piece still joins the faces
  bool stopped_early = false;  // its last solve ended on a decided field
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
  /// Whether a load step that would end on a decided field (no
  /// equilibrium) with this stress must end on an equilibrium instead: the
  /// field is kept (a peak candidate, a snapshot, the end of the run).
  std::function<bool(double stress)> needs_equilibrium = {};
};

/// The error of sigma_zz on a field a load step ends on, at most, relative
/// to the peak (-fracture_decided_closing).
constexpr double kClosingStressTolerance = 1e-6;

class Relaxation {
 public:
  explicit Relaxation(const RelaxationParts& parts);
  virtual ~Relaxation();
  Relaxation(const Relaxation&) = delete;
  Relaxation& operator=(const Relaxation&) = delete;
  /// Starting from the field at `top_displacement` (an equilibrium, or a
  /// decided field with its check field), break and relax until no bond is
  /// critical in the global field, the faces separate, or
  /// (options.stop_within_step) the stress falls below the stop level.
  /// Ends on a global equilibrium, or on a decided field that decides that
  /// nothing more breaks (options.decided_closing) unless needs_equilibrium
  /// says it is kept.  The loop of every scheme: between cycles next_cycle,
  /// then the batch of the field (next_batch), broken (break_batch), and the
  /// scheme's `cycle`; a run whose stress fell ends on an equilibrium.  A
  /// scheme changes `cycle`; it may wrap this (and call it).  Collective.
  virtual RelaxationOutcome relax(std::int64_t step, double top_displacement, double strain,
                                  double stress_before);
  /// What the scheme must carry over a checkpoint besides the protocol's
  /// state (its counters), as bytes: taken at every held equilibrium,
  /// given back on resume.  A scheme with nothing to carry keeps the
  /// defaults; restore_state then refuses a non-empty state.
  virtual std::string saved_state() const { return {}; }
  /// Throws std::runtime_error when `bytes` are not a state of this scheme.
  virtual void restore_state(const std::string& bytes);
  /// The values of the summary fields its registry entry declares, by name
  /// (the local scheme's patch_* entries); empty by default.
  virtual std::vector<std::pair<std::string, double>> report() const { return {}; }

 protected:
  /// One relaxation cycle after `batch` broke (`joined`: some piece still
  /// joins the faces): the scheme's solves, ending on a global field that
  /// the next batch is read from (an equilibrium, or a decided field of
  /// solve_for_decision), and note_batch for `batch` and every batch it
  /// breaks itself.  Collective.
  virtual CycleEnd cycle(std::int64_t step, double top_displacement, double strain,
                         const std::vector<Rupture>& batch, bool joined,
                         RelaxationOutcome& out) = 0;
  /// Break `batch` as one numbered batch (generation `cycle` of this load
  /// step), pin the pieces it cut loose.  Returns whether some piece still
  /// joins the faces.  Collective.
  bool break_batch(const std::vector<Rupture>& batch, std::int64_t step, int cycle, double strain);
  /// Count a broken batch in `out` (one more cycle) and report progress.
  void note_batch(std::int64_t step, const std::vector<Rupture>& batch, RelaxationOutcome& out);
  /// A relaxation solve after a batch; with options.decision_safety > 0 it
  /// may end as soon as the field decides the next batch, or (with
  /// options.decided_closing) that nothing more breaks (CriticalBonds::
  /// decide, decision_stands).  Collective.
  SolveReport solve_for_decision(double top_displacement);
  /// The batch that breaks now: on an equilibrium, its critical bonds, those
  /// in doubt (CriticalBonds::in_doubt) decided on a re-solve to
  /// options.tie_rtol first; on a decided field, the bonds its certificate
  /// decides, after a decided solve where it decides nothing.  Collective.
  std::vector<Rupture> next_batch(double top_displacement);
  /// options.stop_within_step and the stress has fallen below the stop
  /// level: stop_fraction of the curve's peak, the level of end_reason.
  bool stress_fell() const;
  /// Before every cycle but the first: RelaxationParts::between_cycles.
  void next_cycle(std::int64_t step, const RelaxationOutcome& out) const;

  RelaxationParts p_;

 private:
  /// With LEM_CHECK_DECISIONS set (tests): the field is solved on to 1e-12
  /// and put back; throws std::logic_error when its critical set differs
  /// from `tensions`' (the forces of the decided field).  Collective.
  void check_decision(const std::vector<double>& tensions);
  /// Decided solves are on (a safety > 0 and the rule `all`).
  bool decides_early() const;
  /// Whether `decision` of a field with these tensions (and those of its
  /// check iterate) lets a solve stop: it breaks, or it holds with closing
  /// solves on and its stress certain to kClosingStressTolerance.
  bool decision_stands(FieldDecision decision, const std::vector<double>& now,
                       const std::vector<double>& earlier) const;
  /// The forces a decided solve stopped on, and the solve count after it
  /// (tally.solves): next_batch takes its batch from them without deciding
  /// again while no other solve came in between.
  struct DecidedForces {
    std::vector<double> tensions;
    std::int64_t solves = -1;
  } decided_;
  /// Tightening::settled of the near-ties: whether the certificate of the
  /// decided solves (ErrorTail) puts every bond in doubt beyond its error.
  bool ties_settled();
  std::vector<double> tie_check_;  // the forces at the last check
  ErrorTail tie_tail_;
  PieceFinder pieces_;
};

/// The paper's cycle: every relaxation is a global solve.
class GlobalRelaxation : public Relaxation {
 public:
  using Relaxation::Relaxation;

 protected:
  CycleEnd cycle(std::int64_t step, double top_displacement, double strain,
                 const std::vector<Rupture>& batch, bool joined, RelaxationOutcome& out) override;
};

}  // namespace lem
