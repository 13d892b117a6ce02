// When the kept preconditioner is rebuilt, and the bookkeeping of every
// solve (counts, builds in the damage ledger).  A rebuild is asked for after
// `rebuild_after_ruptures` ruptures since the last build, or when a
// relaxation solve takes more than `growth` times the iterations of the
// first relaxation solve after the last build.
#pragma once

#include "lem/system/elastic_system.hpp"
#include "lem/protocol/damage_ledger.hpp"
#include "lem/protocol/state.hpp"

#include <cstdint>

namespace lem {

/// The rules alone (no system): each returns true when a rebuild is due.
struct RebuildRule {
  std::int64_t after_ruptures = 2000;  // 0: never by count
  double iteration_growth = 1.5;       // 0: never by iterations
  bool after_new_ruptures(PreconditionerState& s, std::int64_t ruptures) const;
  bool after_solve(PreconditionerState& s, int iterations, bool built, bool relaxation) const;
};

class PreconditionerPolicy {
 public:
  PreconditionerPolicy(ElasticSystem& system, DamageLedger& ledger, RebuildRule rule,
                       PreconditionerState& state, FractureTally& tally);
  /// Solve for the top displacement, count it, apply the rule.  A solve
  /// that `early` ends before -ksp_rtol does not enter the iteration rule.
  SolveReport solve(double top_displacement, bool relaxation, const EarlyStop* early = nullptr);
  /// A solve to `rtol` instead of -ksp_rtol, counted; outside the iteration rule.
  SolveReport solve_to(double rtol, double top_displacement);
  void note_ruptures(std::int64_t ruptures);

 private:
  SolveReport count(const SolveReport& report, bool relaxation);

  ElasticSystem& system_;
  DamageLedger& ledger_;
  RebuildRule rule_;
  PreconditionerState& state_;
  FractureTally& tally_;
};

}  // namespace lem
