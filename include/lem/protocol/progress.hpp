// Progress lines of a long run, with a time-left estimate after the peak.
#pragma once

#include "lem/protocol/options.hpp"
#include "lem/protocol/state.hpp"

#include <cstdint>
#include <deque>
#include <optional>

namespace lem {

/// After the peak, extrapolates the recent rates of stress and strain (over
/// the last quarter of the time since the peak: the tail slows down) to
/// whichever end comes first, the stop level of the stress or the strain
/// bound.  Before the peak there is no estimate.
/// Wall time of a run across its sessions (a resumed run adds the earlier ones).
struct RunClock {
  double start = 0;           // MPI_Wtime at the start of this session
  double seconds_before = 0;  // earlier sessions
  double elapsed() const;
};

class TimeLeftEstimate {
 public:
  /// stop_level: stress at which the run ends; strain_bound: strain at which
  /// it ends (0: none).  Returns seconds left, or nothing when no rate is
  /// known yet (or before the peak).
  std::optional<double> update(double seconds, double stress, double strain, double peak_stress,
                               double stop_level, double strain_bound);
  bool after_peak() const { return !recent_.empty(); }

 private:
  struct Point {
    double seconds, stress, strain;
  };
  std::deque<Point> recent_;
  double tail_start_ = 0;  // time of the first point after the peak
};

class ProgressReporter {
 public:
  ProgressReporter(const FractureOptions& options, const FractureOutput& output)
      : options_(options), output_(output) {}

  /// One line per load step with ruptures, otherwise at most one per 10 s.
  void step_done(std::int64_t step, double strain, double stress, std::int64_t new_breaks,
                 int cycles, const FractureTally& tally, double elapsed);
  /// During a long avalanche: a line at most every 10 s.
  void relaxing(std::int64_t step, int cycles, std::int64_t new_breaks, double elapsed);

 private:
  const FractureOptions& options_;
  const FractureOutput& output_;
  double last_line_ = 0;  // MPI_Wtime of the last line
  TimeLeftEstimate estimate_;
};

}  // namespace lem
