// Warnings of a run that completes but whose result is degraded
// (docs/model/fracture.md, "Warnings"): rank 0 prints each on stderr as one line
// naming the cause and the option to change, the result lists them, and
// -fracture_strict makes them errors (NumericalError, exit 2).
#pragma once

#include "lem/protocol/options.hpp"
#include "lem/protocol/state.hpp"

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace lem {

/// One kind of degradation and how often it was seen.
struct RunWarning {
  std::string code;  // short: energy_balance, fallback_solver, coarse_increment
  std::int64_t count = 0;
};

/// "code:count" words for the summary, each prefixed by `prefix`.
std::vector<std::string> warning_words(const std::vector<RunWarning>& warnings,
                                       const std::string& prefix = "");

class RunWarnings {
 public:
  /// `dir`: the run's folder, named in each warning.
  RunWarnings(const FractureOptions& options, std::string dir)
      : options_(options), dir_(std::move(dir)) {}

  /// A resumed run: fallback solves before the checkpoint were reported then.
  void resumed(const FractureTally& tally) { fallback_said_ = tally.fallback_solves > 0; }

  /// After a load step: the first solve that needed the fallback solver is
  /// reported at once (strict: NumericalError).  Collective in effect (the
  /// tally is the same on every rank).
  void after_step(const FractureTally& tally);

  /// At the end of the run: the energy balance, the load step of the peak
  /// (judged only when the stress has fallen from it: `past_peak`), and
  /// the fallback count.  Strict: NumericalError naming the first one.
  void at_end(const FractureTally& tally, double energy_balance_error, double peak_step,
              bool past_peak);

  const std::vector<RunWarning>& list() const { return list_; }

 private:
  void raise(const std::string& code, std::int64_t count, const std::string& message);

  const FractureOptions& options_;
  std::string dir_;
  std::vector<RunWarning> list_;
  bool fallback_said_ = false;
};

}  // namespace lem
