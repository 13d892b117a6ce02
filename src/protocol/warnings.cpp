#include "lem/protocol/warnings.hpp"

#include "lem/base/error.hpp"
#include "lem/base/log.hpp"

#include <cstdio>

namespace lem {

std::vector<std::string> warning_words(const std::vector<RunWarning>& warnings,
                                       const std::string& prefix) {
  std::vector<std::string> words;
  for (const auto& w : warnings) words.push_back(prefix + w.code + ":" + std::to_string(w.count));
  return words;
}

namespace {

// One line, with the folder: a calibration warns for its own run.
void print(const std::string& code, const std::string& dir, const std::string& message) {
  say_warning("warning [%s] in %s: %s\n", code.c_str(), dir.c_str(), message.c_str());
}

}  // namespace

void RunWarnings::raise(const std::string& code, std::int64_t count, const std::string& message) {
  if (options_.strict)
    throw NumericalError(message + " [" + code + ": an error under -fracture_strict]");
  print(code, dir_, message);
  list_.push_back({code, count});
}

void RunWarnings::after_step(const FractureTally& tally) {
  if (tally.fallback_solves == 0 || fallback_said_) return;
  fallback_said_ = true;
  const std::string message =
      "a solve at step " + std::to_string(tally.steps) +
      " failed twice with the multigrid "
      "solver and was finished by the fallback solver (CG + Jacobi, slow); check -ksp_max_it, "
      "-ksp_rtol, -ksp_type and the -pc_* options";
  // Strict: thrown within the load step, so the run keeps the checkpoint of
  // the step before and resumes from it with better solver options.
  if (options_.strict)
    throw NumericalError(message + " [fallback_solver: an error under -fracture_strict]");
  print("fallback_solver", dir_, message + " (the count follows at the end)");
}

void RunWarnings::at_end(const FractureTally& tally, double energy_balance_error, double peak_step,
                         bool past_peak) {
  char text[512];
  if (options_.warn_energy_error > 0 && !(energy_balance_error <= options_.warn_energy_error)) {
    std::snprintf(text, sizeof(text),
                  "the energy balance error |W - E - G - R|/W = %.2e exceeds "
                  "-fracture_warn_energy = %g: the solves are not converged enough for the "
                  "curve and the peak to be trusted; lower -ksp_rtol (default 1e-8)",
                  energy_balance_error, options_.warn_energy_error);
    raise("energy_balance", 1, text);
  }
  if (options_.warn_peak_steps > 0 && past_peak &&
      peak_step < static_cast<double>(options_.warn_peak_steps) - 0.5) {
    std::snprintf(text, sizeof(text),
                  "the peak stress is reached at load step %.0f, before -fracture_warn_peak_steps "
                  "= %lld: -fracture_increment = %g is too coarse for the avalanche that ends "
                  "the rise (the peak comes out low); take it below %.2g",
                  peak_step, static_cast<long long>(options_.warn_peak_steps), options_.increment,
                  options_.increment * peak_step / static_cast<double>(options_.warn_peak_steps));
    raise("coarse_increment", 1, text);
  }
  if (tally.fallback_solves > 0) {
    std::snprintf(text, sizeof(text),
                  "%lld of %lld solves were finished by the fallback solver (CG + Jacobi) after "
                  "the multigrid failed twice; check -ksp_max_it, -ksp_rtol, -ksp_type and the "
                  "-pc_* options",
                  static_cast<long long>(tally.fallback_solves),
                  static_cast<long long>(tally.solves));
    raise("fallback_solver", tally.fallback_solves, text);
  }
}

}  // namespace lem
