#include "lem/protocol/options.hpp"

#include "lem/base/error.hpp"
#include "lem/base/options.hpp"
#include "lem/protocol/registry.hpp"

#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

namespace lem {

namespace {

// One of the registered names (`entries`: break_rules() or
// relaxation_schemes()), the help listing each with its own; then the
// options of each.
template <class Entry>
std::string read_registered(OptionGroup& g, const char* name, const std::string& what,
                            const std::vector<Entry>& entries, const std::string& def) {
  std::string help = what;
  std::vector<std::pair<const char*, std::size_t>> words;
  std::size_t def_index = 0;
  for (std::size_t i = 0; i < entries.size(); ++i) {
    help += (i ? "; " : ": ") + entries[i].name + " = " + entries[i].help;
    words.emplace_back(entries[i].name.c_str(), i);
    if (entries[i].name == def) def_index = i;
  }
  const std::string chosen =
      entries[g.choice<std::size_t>(name, help.c_str(), words, def_index)].name;
  // The options of every one, chosen or not: -help lists them, and a
  // misspelt one is an error whichever is chosen.
  for (const Entry& e : entries) {
    if (!e.read_options) continue;
    const std::size_t first = registered_options().size();
    e.read_options(g);
    if (e.name == chosen) continue;
    // An option of one not chosen would be ignored without a word.
    for (std::size_t i = first; i < registered_options().size(); ++i)
      if (registered_options()[i].given)
        throw InputError("option " + registered_options()[i].name + " belongs to " + name + " " +
                         e.name + ", but this run uses " + name + " " + chosen +
                         ": drop the option, or choose " + e.name);
  }
  return chosen;
}

// The smallest -fracture_increment (in a) whose steps the protocol resolves
// (the option's help says why).
constexpr double kMinIncrement = 1e-7;

// -fracture_increment, the break rule (and every rule's options), the end
// and the preconditioner rebuilds.
void read_protocol_options(MPI_Comm comm, FractureOptions& o) {
  OptionGroup g(comm, "Fracture protocol (paper sect. 2.3, appendix A)");
  o.increment = g.real("-fracture_increment",
                       "Top displacement added per load step, in "
                       "units of the mean bond length a (paper: 3e-4).  At least 1e-7: the "
                       "first ruptures of the smallest samples (a strain of about 1e-3 over "
                       "about 10 a) would otherwise come after more than 1e5 load steps, where "
                       "one step changes the bond forces by less than the near-tie band "
                       "(-fracture_tie_band x -ksp_rtol = 1e-5 of the mean threshold), so the "
                       "solver's error and not the load would decide the ruptures",
                       o.increment, kMinIncrement, 0.01);
  o.break_rule = read_registered(g, "-fracture_break_rule",
                                 "Which critical bonds break in a "
                                 "relaxation cycle",
                                 break_rules(), o.break_rule);
  o.skip_idle = g.flag("-fracture_skip_idle",
                       "Jump over load steps at which no bond breaks "
                       "(exact: the system is linear between ruptures)",
                       o.skip_idle);
  o.stop_fraction = g.real("-fracture_stop_fraction",
                           "End the run once the stress has "
                           "fallen below this fraction of the peak",
                           o.stop_fraction, 0.0, 1.0, true, true);
  o.max_strain_ratio = g.real("-fracture_max_strain_ratio",
                              "End the run once the strain "
                              "exceeds this multiple of the strain at the peak (the slow "
                              "post-failure tail; 0: no limit).  Above 1: at 1 or less the "
                              "run would end at the peak itself, before the stress can fall "
                              "after it",
                              o.max_strain_ratio, 0.0, 1e9);
  if (o.max_strain_ratio != 0 && !(o.max_strain_ratio > 1)) {
    std::ostringstream s;
    s << "option -fracture_max_strain_ratio = " << o.max_strain_ratio << " is out of range: "
      << "allowed 0 (no limit) or above 1 (at 1 or less the run ends at its peak, before the "
      << "stress can fall after it)";
    throw InputError(s.str());
  }
  o.max_steps = g.integer("-fracture_max_steps", "Largest load step (the run ends there)",
                          o.max_steps, 1, 1'000'000'000);
  o.rebuild_after_ruptures = g.integer("-fracture_pc_rebuild_ruptures",
                                       "Rebuild the preconditioner after this many ruptures "
                                       "since the last build (0: never for this reason)",
                                       o.rebuild_after_ruptures, 0, 1'000'000'000);
  o.rebuild_iteration_growth =
      g.real("-fracture_pc_rebuild_growth",
             "Rebuild the preconditioner when a relaxation solve "
             "takes more than this times the iterations of the first one after the last build (0: "
             "never for this reason)",
             o.rebuild_iteration_growth, 0.0, 1e6);
}

// The relaxation scheme (and every scheme's options), decided solves and
// near-ties.
void read_relaxation_options(MPI_Comm comm, FractureOptions& o) {
  OptionGroup g(comm, "Relaxation after ruptures (docs/model/fracture.md)");
  o.relaxation = read_registered(g, "-fracture_relaxation",
                                 "How a load step is relaxed "
                                 "after ruptures",
                                 relaxation_schemes(), o.relaxation);
  o.decision_safety =
      g.real("-fracture_decision_safety",
             "End a relaxation solve (CG) before -ksp_rtol as soon as "
             "it decides the next batch: one bond force is above its threshold and every one is "
             "farther from it than this many times the error of the field (the largest change of "
             "any force over the last -fracture_decision_interval iterations, times the tail of "
             "their series).  0: every solve to -ksp_rtol (the reference)",
             o.decision_safety, 0.0, 1e6);
  o.decided_closing =
      g.flag("-fracture_decided_closing",
             "With -fracture_decision_safety > 0: a load step may also "
             "end on an unfinished solve that decides that no bond breaks (every force farther "
             "from its threshold than its error, and sigma_zz within 1e-6 of the peak); the field "
             "is solved to -ksp_rtol before it is kept (a peak, snapshots, the end).  false: every "
             "load step ends on a solve to -ksp_rtol",
             o.decided_closing);
  o.decision_interval =
      static_cast<int>(g.integer("-fracture_decision_interval",
                                 "CG iterations between two decision checks (each "
                                 "computes every bond force, about one matrix product)",
                                 o.decision_interval, 1, 1000));
  o.tie_band = g.real(
      "-fracture_tie_band",
      "Near-ties: a bond whose force differs from its level (threshold, "
      "or the force floor) by less than this times -ksp_rtol times the mean positive "
      "threshold, and exceeds half that level, is decided on the field solved on to "
      "-fracture_tie_rtol, so that solver noise (which depends on the rank count) decides no "
      "rupture.  0: decide on the field as solved",
      o.tie_band, 0.0, 1e12);
  o.tie_rtol = g.real("-fracture_tie_rtol",
                      "Relative tolerance to which a solve that meets -ksp_rtol "
                      "goes on (in the same CG run) when a bond is in doubt "
                      "(-fracture_tie_band); nothing more when -ksp_rtol is not above it",
                      o.tie_rtol, 0.0, 1.0, true);
}

// Warnings of a degraded result.
void read_warning_options(MPI_Comm comm, FractureOptions& o) {
  OptionGroup g(comm, "Warnings of a degraded result (docs/model/fracture.md, \"Warnings\")");
  o.warn_energy_error =
      g.real("-fracture_warn_energy",
             "Warn when the energy balance error |W - E - G - R|/W at "
             "the end exceeds this (converged runs: below 1e-6; -ksp_rtol 1e-4 gives about 1e-4; "
             "0: no check)",
             o.warn_energy_error, 0.0, 1.0);
  o.warn_peak_steps = g.integer(
      "-fracture_warn_peak_steps",
      "Warn when the peak stress is reached before this load "
      "step: -fracture_increment is then too coarse to resolve the avalanche that ends the "
      "rise (0: no check)",
      o.warn_peak_steps, 0, 1'000'000'000);
  o.strict = g.flag("-fracture_strict",
                    "Make every warning an error (exit 2): the energy "
                    "balance, the peak steps, and the first solve that needs the fallback "
                    "solver (-fallback_ksp_*)",
                    o.strict);
}

// Threshold disorder.
void read_disorder_options(MPI_Comm comm, FractureOptions& o) {
  OptionGroup g(comm, "Threshold disorder (seeded; the same on any rank count)");
  o.disorder =
      g.choice<ThresholdDisorder>("-strength_disorder", "Random factor on the breaking thresholds",
                                  {{"none", ThresholdDisorder::none},
                                   {"uniform", ThresholdDisorder::uniform},
                                   {"weibull", ThresholdDisorder::weibull}},
                                  ThresholdDisorder::none);
  o.disorder_width = g.real("-strength_disorder_width",
                            "uniform: factor drawn in "
                            "[1 - w, 1 + w]",
                            0.2, 0.0, 1.0, false, true);
  o.weibull_modulus = g.real("-strength_weibull_modulus",
                             "weibull: shape m of the "
                             "mean-one Weibull factor",
                             o.weibull_modulus, 0.0, 1000.0, true);
  o.disorder_seed = static_cast<std::uint64_t>(
      g.integer("-strength_disorder_seed", "Seed of the threshold factors", 1, 0, PETSC_MAX_INT));
  const std::string phases = g.string("-strength_disorder_phases",
                                      "Comma-separated bond "
                                      "phases that get the factor (p, m, pp, pm)",
                                      "p,m,pp,pm");
  o.disorder_phases.fill(false);
  std::stringstream list(phases);
  for (std::string item; std::getline(list, item, ',');) {
    const auto phase = parse_phase(item);
    if (!phase || *phase == Phase::v)  // void bonds carry nothing
      throw InputError("option -strength_disorder_phases: '" + item +
                       "' is not a bond "
                       "phase; allowed: p, m, pp, pm");
    o.disorder_phases[static_cast<int>(*phase)] = true;
  }
}

// Checkpoints and resume.
void read_checkpoint_options(MPI_Comm comm, FractureOptions& o) {
  OptionGroup g(comm, "Checkpoint and restart");
  o.checkpoint_steps = g.integer("-checkpoint_steps",
                                 "Write a checkpoint every this many "
                                 "load steps (0: not by steps)",
                                 0, 0, 1'000'000'000);
  o.checkpoint_seconds = g.real("-checkpoint_seconds",
                                "Write a checkpoint when this much "
                                "wall time has passed since the last one (0: not by time); "
                                "SIGTERM or SIGUSR1 also write one and stop the run",
                                600.0, 0.0, 1e9);
  o.resume = g.flag("-checkpoint_resume",
                    "Resume from the checkpoint in -output_dir if there "
                    "is one (false: start over and overwrite it)",
                    true);
}

}  // namespace

FractureOptions read_fracture_options(MPI_Comm comm) {
  FractureOptions o;
  read_protocol_options(comm, o);
  read_relaxation_options(comm, o);
  read_warning_options(comm, o);
  read_disorder_options(comm, o);
  read_checkpoint_options(comm, o);
  return o;
}

}  // namespace lem
