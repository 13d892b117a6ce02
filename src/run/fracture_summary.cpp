#include "lem/run/fracture_summary.hpp"

#include "lem/base/phase.hpp"
#include "lem/protocol/registry.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

namespace lem {

namespace {

using R = FractureRecord;

// Broken bonds of one phase.
std::function<std::optional<Summary::Value>(const R&)> broken(Phase phase) {
  return [phase](const R& r) { return summary_count(r.result.broken[static_cast<int>(phase)]); };
}

// The sample, the units and the curve's figures.
SummaryTable<R> sample_entries() {
  return {
      {"sample_file", "", "the sample file (empty for a generated lattice)",
       [](const R& r) { return r.sample.sample_file; }},
      {"nodes", "", "nodes of the lattice",
       [](const R& r) { return summary_count(r.setup.sample.stats.nodes); }},
      {"active_bonds", "", "bonds in the system (void bonds of sample files excluded)",
       [](const R& r) { return summary_count(r.setup.active_bonds); }},
      {"mean_bond_length", "length",
       "a: the mean length of the lattice's elements (a sample "
       "file's: every row of `/bonds`, void bonds included); "
       "k = E^φ a, f = σ^φ a² and the load increment are in it",
       [](const R& r) { return r.lattice_a; }},
      {"increment_over_a", "", "load increment per step over a",
       [](const R& r) { return r.options.increment; }},
      {"break_rule", "", "`-fracture_break_rule`", [](const R& r) { return r.options.break_rule; }},
      {"sigma_unit", "stress",
       "the stress unit of the curve: `-fracture_sigma_unit` if given, "
       "else σ^[p] if calibrated, else σ^p (sample files) or 1",
       [](const R& r) { return r.units.strength_unit; }},
      {"E_unit", "stress",
       "the modulus unit: `-fracture_modulus_unit` if given, else E^[p] if "
       "calibrated, else E^p (sample files) or 1",
       [](const R& r) { return r.units.modulus_unit; }},
      {"sigma_hom", "stress", "σ^[p] of the calibration (0 without one)",
       [](const R& r) { return r.calibration.sigma_hom; }},
      {"E_hom", "stress", "E^[p] of the calibration (0 without one)",
       [](const R& r) { return r.calibration.e_hom; }},
      {"E_eff", "stress", "effective modulus: σ/ε of the first equilibrium",
       [](const R& r) { return r.e_eff(); }},
      {"E_eff_over_E_unit", "", "E_eff / E_unit",
       [](const R& r) { return r.e_eff() / r.units.modulus_unit; }},
      {"sigma_eff", "stress", "tensile strength: the peak stress",
       [](const R& r) { return r.sigma_eff(); }},
      {"sigma_eff_over_sigma_unit", "", "sigma_eff / sigma_unit",
       [](const R& r) { return r.sigma_eff() / r.units.strength_unit; }},
      {"strain_at_peak", "", "strain ε_zz at the peak",
       [](const R& r) { return r.result.strain_at_peak; }},
      {"peak_step", "", "load step of the peak",
       [](const R& r) { return summary_count(std::llround(r.result.peak_step)); }},
      {"final_strain", "", "strain where the run ended",
       [](const R& r) { return r.result.final_strain; }},
      {"final_stress_over_sigma_unit", "", "stress where the run ended / sigma_unit",
       [](const R& r) { return r.result.final_stress * r.stress_unit / r.units.strength_unit; }},
  };
}

// What broke and what it took, up to "relaxation".
SummaryTable<R> count_entries() {
  return {
      {"broken", "", "broken bonds, all phases",
       [](const R& r) { return summary_count(r.result.broken_total()); }},
      {"broken_p", "", "broken particle bonds", broken(Phase::p)},
      {"broken_m", "", "broken matrix bonds", broken(Phase::m)},
      {"broken_pp", "", "broken particle–particle contacts", broken(Phase::pp)},
      {"broken_pm", "", "broken particle–matrix interface bonds", broken(Phase::pm)},
      {"n_b", "", "particle damage: broken p bonds / broken bonds",
       [](const R& r) { return r.result.particle_damage(); }},
      {"detached_bonds", "", "bonds of loose pieces, taken out (not ruptures)",
       [](const R& r) { return summary_count(r.result.detached_bonds); }},
      {"pinned_nodes", "", "nodes of loose pieces, pinned",
       [](const R& r) { return summary_count(r.result.pinned_nodes); }},
      {"steps", "", "last load step", [](const R& r) { return summary_count(r.result.steps); }},
      {"visited_steps", "", "load steps evaluated (rows of `curve.csv`)",
       [](const R& r) { return summary_count(r.result.visited_steps); }},
      {"rupture_steps", "", "load steps with ruptures",
       [](const R& r) { return summary_count(r.result.rupture_steps); }},
      {"relaxation_cycles", "", "relaxation cycles (batches of ruptures)",
       [](const R& r) { return summary_count(r.result.relaxation_cycles); }},
      {"solves", "", "linear solves", [](const R& r) { return summary_count(r.result.solves); }},
      {"early_stops", "", "relaxation solves ended once the batch was decided",
       [](const R& r) { return summary_count(r.result.early_stops); }},
      {"decided_steps", "", "load steps that ended on a decided field",
       [](const R& r) { return summary_count(r.result.decided_steps); }},
      {"tie_solves", "", "solves taken on past `-ksp_rtol` to decide near-ties",
       [](const R& r) { return summary_count(r.result.tie_solves); }},
      {"tie_iterations", "",
       "CG iterations of those solves after `-ksp_rtol` (part of "
       "`ksp_iterations`)",
       [](const R& r) { return summary_count(r.result.tie_iterations); }},
      {"ksp_iterations", "", "CG iterations",
       [](const R& r) { return summary_count(r.result.iterations); }},
      {"pc_builds", "", "preconditioner builds",
       [](const R& r) { return summary_count(r.result.preconditioner_builds); }},
      {"fallback_solves", "", "solves finished by the fallback solver (Jacobi-CG)",
       [](const R& r) { return summary_count(r.result.fallback_solves); }},
      {"relaxation", "", "`-fracture_relaxation`", [](const R& r) { return r.options.relaxation; }},
  };
}

// The energies and how the run ended.
SummaryTable<R> closing_entries() {
  return {
      // A plain run solves at every step plus every relaxation cycle.
      {"solves_stepping_estimate", "",
       "steps + relaxation cycles: the solves of a run without "
       "idle skipping",
       [](const R& r) { return summary_count(r.result.steps + r.result.relaxation_cycles); }},
      {"work", "lattice", "external work W at the end (lattice units k a²)",
       [](const R& r) { return r.result.work; }},
      {"stored_energy", "lattice", "elastic energy E stored in the bonds at the end",
       [](const R& r) { return r.result.stored_energy; }},
      {"ground_energy", "lattice",
       "energy G held by the ground springs "
       "(`-lattice_ground_stiffness`) at the end",
       [](const R& r) { return r.result.ground_energy; }},
      {"released_energy", "lattice",
       "energy R released by the relaxations (bonds and ground "
       "springs; dissipated by the ruptures)",
       [](const R& r) { return r.result.released_energy; }},
      {"energy_balance_error", "", "\\|W − E − G − R\\| / W: the solver's error",
       [](const R& r) { return r.result.energy_balance_error; }},
      {"end_reason", "",
       "why the run ended ([fracture](../model/fracture.md), \"Loose pieces "
       "and the end of a run\")",
       [](const R& r) { return r.result.end_reason; }},
      {"warnings", "",
       "`code:count` words, `calibration_` prefixed for the calibration's; "
       "`[]` for a sound run ([fracture](../model/fracture.md), \"Warnings\")",
       [](const R& r) { return r.warnings; }},
      {"resumed", "", "1 if the run resumed from a checkpoint",
       [](const R& r) { return summary_count(r.result.resumed); }},
      {"seconds", "s", "wall time, the parts of a resumed run added",
       [](const R& r) { return r.result.seconds; }},
      {"peak_memory_mb", "MB", "the largest peak resident memory of a rank (of the last part)",
       [](const R& r) { return r.memory.max_mb; }},
      {"peak_memory_mean_mb", "MB", "the mean over the ranks of their peak resident memory",
       [](const R& r) { return r.memory.mean_mb; }},
      {"mpi_ranks", "", "MPI ranks", [](const R& r) { return summary_count(r.ranks); }},
  };
}

// The run's own entries; those of the break rules and relaxation schemes
// (registry.hpp) follow "relaxation".
const SummaryTable<R>& run_table() {
  static const SummaryTable<R> table = [] {
    SummaryTable<R> all = sample_entries();
    for (SummaryTable<R> part : {count_entries(), closing_entries()})
      all.insert(all.end(), part.begin(), part.end());
    return all;
  }();
  return table;
}

}  // namespace

SummaryTable<FractureRecord> fracture_summary_table() {
  SummaryTable<R> table = run_table();
  SummaryTable<R> registered;
  for (const SummaryField& f : registered_summary_fields()) {
    if (std::any_of(table.begin(), table.end(),
                    [&](const SummaryEntry<R>& e) { return std::strcmp(f.name, e.name) == 0; }))
      throw std::invalid_argument(std::string("the summary field '") + f.name +
                                  "' of a break rule or relaxation scheme is an entry of "
                                  "lem_fracture's summary");
    const std::string name = f.name;
    registered.push_back(
        {f.name, f.unit, f.meaning, [name](const R& r) { return r.result.plugin_value(name); }});
  }
  const auto relaxation = std::find_if(table.begin(), table.end(), [](const SummaryEntry<R>& e) {
    return std::strcmp(e.name, "relaxation") == 0;
  });
  table.insert(relaxation + 1, registered.begin(), registered.end());
  return table;
}

std::vector<SummaryField> fracture_summary_fields() {
  return described_fields(fracture_summary_table());
}

}  // namespace lem
