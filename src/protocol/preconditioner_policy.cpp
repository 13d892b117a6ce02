#include "lem/protocol/preconditioner_policy.hpp"

#include <algorithm>

namespace lem {

bool RebuildRule::after_new_ruptures(PreconditionerState& s, std::int64_t ruptures) const {
  s.ruptures_since_build += ruptures;
  return after_ruptures > 0 && s.ruptures_since_build >= after_ruptures;
}

bool RebuildRule::after_solve(PreconditionerState& s, int iterations, bool built,
                              bool relaxation) const {
  if (built) {
    s.ruptures_since_build = 0;
    s.baseline_iterations = 0;
  }
  if (!relaxation) return false;
  if (s.baseline_iterations == 0) {
    s.baseline_iterations = std::max(1, iterations);
    return false;
  }
  return iteration_growth > 0 &&
         iterations > iteration_growth * static_cast<double>(s.baseline_iterations);
}

PreconditionerPolicy::PreconditionerPolicy(ElasticSystem& system, DamageLedger& ledger,
                                           RebuildRule rule, PreconditionerState& state,
                                           FractureTally& tally)
    : system_(system), ledger_(ledger), rule_(rule), state_(state), tally_(tally) {}

SolveReport PreconditionerPolicy::solve(double top_displacement, bool relaxation,
                                        const EarlyStop* early) {
  return count(system_.solve(top_displacement, early), relaxation);
}

SolveReport PreconditionerPolicy::solve_to(double rtol, double top_displacement) {
  return count(system_.solve_to(rtol, top_displacement), false);
}

SolveReport PreconditionerPolicy::count(const SolveReport& report, bool relaxation) {
  tally_.solves += 1;
  tally_.early_stops += report.stopped_early;
  tally_.iterations += report.iterations;
  tally_.fallback_solves += report.used_fallback;
  tally_.tie_solves += report.tightened;
  tally_.tie_iterations += report.tightened_iterations;
  if (report.preconditioner_built) {
    tally_.preconditioner_builds += 1;
    ledger_.record_build();
  }
  // The iterations for near-ties say nothing of the preconditioner's age.
  const int own = report.iterations - report.tightened_iterations;
  if (rule_.after_solve(state_, own, report.preconditioner_built,
                        relaxation && !report.stopped_early))
    system_.rebuild_preconditioner();
  return report;
}

void PreconditionerPolicy::note_ruptures(std::int64_t ruptures) {
  if (rule_.after_new_ruptures(state_, ruptures)) system_.rebuild_preconditioner();
}

}  // namespace lem
