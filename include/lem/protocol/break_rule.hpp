// The break rule (paper sect. 2.1, appendix A): which bonds are critical in
// the current field, and at which load step the next one will be.
//
// A bond is critical when its tension exceeds its threshold strictly and
// exceeds the force floor (1e-6 of the mean positive threshold): below the
// floor a force is solver noise, so bonds of zero threshold (bare contacts)
// break only on a real tension.  Bonds never break in compression.
//
// A force carries the solver's error, which differs with the rank count.  A
// bond whose force is within a band of that error around its level
// (threshold or floor) is "in doubt": the protocol decides it on a tighter
// re-solve instead (docs/model/fracture-decisions.md, "Near-ties and the rank count").
#pragma once

#include "lem/system/distributed_lattice.hpp"
#include "lem/protocol/options.hpp"
#include "lem/protocol/state.hpp"

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace lem {

struct Rupture {
  std::int64_t id;  // global bond id
  double ratio;     // force / threshold (infinite for a zero threshold)
  double force, threshold;
  double x, y, z;  // bond midpoint
  std::int32_t phase, pad;
};

/// t > f and t > floor.
bool is_critical(double tension, double threshold, double force_floor);
/// Larger ratio first, then smaller id: one order on every rank count.
bool more_critical(const Rupture& a, const Rupture& b);
/// The system is linear between ruptures: a bond with tension t at step n
/// (t > 0) first exceeds max(f, floor) at step floor(n f / t) + 1.
double first_breaking_step(std::int64_t step, double tension, double threshold, double force_floor);
/// Lower edge of the doubt band around `level`: max(level - band, level / 2).
/// Half the level bounds it so that a bare contact whose force is noise
/// around zero is never in doubt.
double doubt_edge(double level, double band);
/// doubt_edge(level, band) < t <= level + band (never with band 0).
bool in_doubt(double tension, double level, double band);

/// Which of a field's critical bonds break in one relaxation cycle: the
/// rule of -fracture_break_rule (registry.hpp lists them by name).
class BreakRule {
 public:
  virtual ~BreakRule() = default;
  /// The bonds that break now, from `critical`: every critical bond of the
  /// field, the same list on every rank, ordered by id (so the answer must
  /// depend on nothing else to keep runs independent of the rank count).
  /// Not empty when `critical` is not.
  virtual std::vector<Rupture> batch(std::vector<Rupture> critical) const = 0;
  /// Whether the batch follows from which bonds are critical alone: then a
  /// solve may stop as soon as its field shows that set (decided solves).
  /// A rule that ranks the critical bonds by their forces needs converged
  /// forces and answers false.
  virtual bool set_decides_batch() const = 0;
  /// The values of the summary fields its registry entry declares, by name,
  /// from the tally of the finished run (a rule keeps no state: its batch
  /// is a function of the critical set, so a resumed run reports the same).
  virtual std::vector<std::pair<std::string, double>> report(const FractureTally& run) const {
    (void)run;
    return {};
  }
};

/// The paper's rule: every critical bond breaks.
std::unique_ptr<BreakRule> make_all_critical_rule();
/// The most critical bond only (more_critical: largest ratio, then id).
std::unique_ptr<BreakRule> make_most_critical_rule();

/// What a field that is no equilibrium decides, given an error estimate of
/// every force (CriticalBonds::decide).
enum class FieldDecision {
  undecided,  // some force within its error of its level, or in doubt
  breaks,     // some bond critical beyond its error, none undecided
  holds,      // no bond critical, none within its error of its level
};

/// The error left in a converging solve's forces, from the largest change
/// of any force between checks a few CG iterations apart: while that change
/// E shrinks by a factor rho < 1 per check, what is left of any force's
/// error is at most the rest of the series, E rho / (1 - rho) (each later
/// change is at most the largest).
class ErrorTail {
 public:
  /// The factor g >= 1 for which g E bounds the error left after a check
  /// whose change is E = `change`; 0 while the changes do not shrink.
  double next(double change);
  void restart() { earlier_ = 0; }

 private:
  double earlier_ = 0;  // E of the check before, 0: none yet
};

class CriticalBonds {
 public:
  /// Collective (the force floor is a global mean of the thresholds).
  /// `tie_band`: width of the doubt band in units of the mean positive
  /// threshold (0: no bond is ever in doubt).
  /// `rule` must outlive the object.
  CriticalBonds(const DistributedLattice& lattice, const BreakRule& rule, double tie_band = 0);

  /// The bonds that break now under the rule, the same list on every rank.
  /// Collective; throws NumericalError naming a bond with a non-finite force.
  std::vector<Rupture> find(const std::vector<double>& tensions) const;

  /// Whether some bond is in doubt (in_doubt).  Collective.
  bool in_doubt(const std::vector<double>& tensions) const;
  /// Whether every bond in doubt is farther than `error` from its level:
  /// a field whose forces are within `error` of the converged ones then
  /// decides them as the converged field would.  Collective.
  bool doubts_decided(const std::vector<double>& tensions, double error) const;

  /// The error bound of every force of an unfinished field: `safety` times
  /// the largest change of any force since the `earlier` field (the check
  /// field of a decided solve, which holds the error's tail: Relaxation::
  /// solve_for_decision).  The same for every bond.  Collective.
  double force_error(const std::vector<double>& tensions, const std::vector<double>& earlier,
                     double safety) const;

  /// What an unfinished field decides, with the error of every force
  /// bounded by force_error(tensions, earlier, safety):
  /// `breaks` when at least one bond is critical beyond its error and no
  /// bond is within its error of its level or in doubt (the critical set is
  /// then the converged field's; only under a rule whose batch follows from
  /// the critical set), `holds` when
  /// moreover no bond is critical.  Collective.
  FieldDecision decide(const std::vector<double>& tensions, const std::vector<double>& earlier,
                       double safety) const;

  /// First load step after `step` at which a bond becomes critical, or
  /// enters its doubt band, if the field is scaled from `step` (at most
  /// max_steps + 1).  With `earlier` (a field that is no equilibrium), each
  /// force is taken at the top of its error bound (force_error): the step
  /// is then never later than the converged field's.  Collective.
  std::int64_t next_step(const std::vector<double>& tensions, std::int64_t step,
                         std::int64_t max_steps, const std::vector<double>* earlier = nullptr,
                         double safety = 0) const;

  /// Throws InputError when the first increment already overloads more than
  /// 1e-3 of the bonds of positive threshold (the increment skips the
  /// elastic regime).  Collective.
  void check_first_increment(const std::vector<double>& tensions, double increment) const;

  const BreakRule& rule() const { return rule_; }
  double force_floor() const { return force_floor_; }
  /// Width of the doubt band (a force; 0: off).
  double tie_band() const { return band_; }
  /// Mean of the positive thresholds (1 when there is none).
  double mean_threshold() const { return mean_threshold_; }

 private:
  double level(int bond) const;  // the force above which the bond is critical

  const DistributedLattice& lattice_;
  const BreakRule& rule_;
  double mean_threshold_ = 1, force_floor_ = 0, band_ = 0;
};

}  // namespace lem
