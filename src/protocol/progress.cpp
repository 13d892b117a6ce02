#include "lem/protocol/progress.hpp"

#include "lem/base/log.hpp"

#include <mpi.h>

#include <algorithm>
#include <cstdio>

namespace lem {

double RunClock::elapsed() const { return seconds_before + MPI_Wtime() - start; }

std::optional<double> TimeLeftEstimate::update(double seconds, double stress, double strain,
                                               double peak_stress, double stop_level,
                                               double strain_bound) {
  if (stress >= peak_stress || peak_stress <= 0) {
    recent_.clear();
    return std::nullopt;
  }
  if (recent_.empty()) tail_start_ = seconds;
  recent_.push_back({seconds, stress, strain});
  const double window = std::max(10.0, 0.25 * (seconds - tail_start_));
  while (recent_.size() > 2 && seconds - recent_[1].seconds > window) recent_.pop_front();
  const Point& old = recent_.front();
  const double dt = seconds - old.seconds;
  double left = -1;
  if (dt > 0 && old.stress > stress) left = (stress - stop_level) / ((old.stress - stress) / dt);
  if (dt > 0 && strain_bound > 0 && strain > old.strain) {
    const double to_bound = (strain_bound - strain) / ((strain - old.strain) / dt);
    left = left < 0 ? to_bound : std::min(left, to_bound);
  }
  if (left < 0) return std::nullopt;
  return std::max(0.0, left);
}

void ProgressReporter::step_done(std::int64_t step, double strain, double stress,
                                 std::int64_t new_breaks, int cycles, const FractureTally& t,
                                 double elapsed) {
  const double now = MPI_Wtime();
  if (new_breaks == 0 && now - last_line_ < 10.0) return;
  last_line_ = now;
  const double bound =
      options_.max_strain_ratio > 0 ? options_.max_strain_ratio * t.strain_at_peak : 0.0;
  const auto left = estimate_.update(elapsed, stress, strain, t.peak_stress,
                                     options_.stop_fraction * t.peak_stress, bound);
  char estimate[48];
  if (left)
    std::snprintf(estimate, sizeof(estimate), "~%lld s left", static_cast<long long>(*left));
  else
    std::snprintf(estimate, sizeof(estimate), "%s",
                  estimate_.after_peak() ? "after the peak" : "before the peak");
  const double norm = output_.stress_unit / output_.strength_unit;
  say("step %7lld  eps %.4e  sigma/sigma_u %.4f (peak %.4f)  broken %lld (+%lld in %d cycles)  "
      "loose nodes %lld  solves %lld  its %lld  PC builds %lld  %.1f s  %s\n",
      (long long)step, strain, stress * norm, t.peak_stress * norm, (long long)t.broken_total(),
      (long long)new_breaks, cycles, (long long)t.pinned_nodes, (long long)t.solves,
      (long long)t.iterations, (long long)t.preconditioner_builds, elapsed, estimate);
}

void ProgressReporter::relaxing(std::int64_t step, int cycles, std::int64_t new_breaks,
                                double elapsed) {
  const double now = MPI_Wtime();
  if (now - last_line_ < 10.0) return;
  last_line_ = now;
  say("step %7lld  relaxing: cycle %d, %lld bonds broken at this step so far, %.1f s\n",
      (long long)step, cycles, (long long)new_breaks, elapsed);
}

}  // namespace lem
