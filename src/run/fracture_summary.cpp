#include "lem/run/fracture_summary.hpp"

#include "lem/protocol/registry.hpp"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>

namespace lem {

namespace {

// The run's own entries; those of the break rules and relaxation schemes
// (registry.hpp) follow "relaxation".
const std::vector<SummaryField>& run_fields() {
  static const std::vector<SummaryField> fields = {
      {"sample_file", "", "the sample file (empty for a generated lattice)"},
      {"nodes", "", "nodes of the lattice"},
      {"active_bonds", "", "bonds in the system (void bonds of sample files excluded)"},
      {"mean_bond_length", "length",
       "a: the mean length of the lattice's elements (a sample "
       "file's: every row of `/bonds`, void bonds included); "
       "k = E^φ a, f = σ^φ a² and the load increment are in it"},
      {"increment_over_a", "", "load increment per step over a"},
      {"break_rule", "", "`-fracture_break_rule`"},
      {"sigma_unit", "stress",
       "the stress unit of the curve: `-fracture_sigma_unit` if given, "
       "else σ^[p] if calibrated, else σ^p (sample files) or 1"},
      {"E_unit", "stress",
       "the modulus unit: `-fracture_modulus_unit` if given, else E^[p] if "
       "calibrated, else E^p (sample files) or 1"},
      {"sigma_hom", "stress", "σ^[p] of the calibration (0 without one)"},
      {"E_hom", "stress", "E^[p] of the calibration (0 without one)"},
      {"E_eff", "stress", "effective modulus: σ/ε of the first equilibrium"},
      {"E_eff_over_E_unit", "", "E_eff / E_unit"},
      {"sigma_eff", "stress", "tensile strength: the peak stress"},
      {"sigma_eff_over_sigma_unit", "", "sigma_eff / sigma_unit"},
      {"strain_at_peak", "", "strain ε_zz at the peak"},
      {"peak_step", "", "load step of the peak"},
      {"final_strain", "", "strain where the run ended"},
      {"final_stress_over_sigma_unit", "", "stress where the run ended / sigma_unit"},
      {"broken", "", "broken bonds, all phases"},
      {"broken_p", "", "broken particle bonds"},
      {"broken_m", "", "broken matrix bonds"},
      {"broken_pp", "", "broken particle–particle contacts"},
      {"broken_pm", "", "broken particle–matrix interface bonds"},
      {"n_b", "", "particle damage: broken p bonds / broken bonds"},
      {"detached_bonds", "", "bonds of loose pieces, taken out (not ruptures)"},
      {"pinned_nodes", "", "nodes of loose pieces, pinned"},
      {"steps", "", "last load step"},
      {"visited_steps", "", "load steps evaluated (rows of `curve.csv`)"},
      {"rupture_steps", "", "load steps with ruptures"},
      {"relaxation_cycles", "", "relaxation cycles (batches of ruptures)"},
      {"solves", "", "linear solves"},
      {"early_stops", "", "relaxation solves ended once the batch was decided"},
      {"decided_steps", "", "load steps that ended on a decided field"},
      {"tie_solves", "", "solves taken on past `-ksp_rtol` to decide near-ties"},
      {"tie_iterations", "",
       "CG iterations of those solves after `-ksp_rtol` (part of "
       "`ksp_iterations`)"},
      {"ksp_iterations", "", "CG iterations"},
      {"pc_builds", "", "preconditioner builds"},
      {"fallback_solves", "", "solves finished by the fallback solver (Jacobi-CG)"},
      {"relaxation", "", "`-fracture_relaxation`"},
      {"solves_stepping_estimate", "",
       "steps + relaxation cycles: the solves of a run without "
       "idle skipping"},
      {"work", "lattice", "external work W at the end (lattice units k a²)"},
      {"stored_energy", "lattice", "elastic energy E stored in the bonds at the end"},
      {"ground_energy", "lattice",
       "energy G held by the ground springs "
       "(`-lattice_ground_stiffness`) at the end"},
      {"released_energy", "lattice",
       "energy R released by the relaxations (bonds and ground "
       "springs; dissipated by the ruptures)"},
      {"energy_balance_error", "", "\\|W − E − G − R\\| / W: the solver's error"},
      {"end_reason", "",
       "why the run ended ([fracture](../model/fracture.md), \"Loose pieces "
       "and the end of a run\")"},
      {"warnings", "",
       "`code:count` words, `calibration_` prefixed for the calibration's; "
       "`[]` for a sound run ([fracture](../model/fracture.md), \"Warnings\")"},
      {"resumed", "", "1 if the run resumed from a checkpoint"},
      {"seconds", "s", "wall time (of the last part for a resumed run)"},
      {"peak_memory_mb", "MB", "the largest peak resident memory of a rank (of the last part)"},
      {"peak_memory_mean_mb", "MB", "the mean over the ranks of their peak resident memory"},
      {"mpi_ranks", "", "MPI ranks"},
  };
  return fields;
}

}  // namespace

std::vector<SummaryField> fracture_summary_fields() {
  std::vector<SummaryField> fields = run_fields();
  const std::vector<SummaryField> registered = registered_summary_fields();
  for (const SummaryField& f : registered)
    if (std::any_of(fields.begin(), fields.end(),
                    [&](const SummaryField& g) { return std::strcmp(f.name, g.name) == 0; }))
      throw std::invalid_argument(std::string("the summary field '") + f.name +
                                  "' of a break rule or relaxation scheme is an entry of "
                                  "lem_fracture's summary");
  const auto relaxation = std::find_if(fields.begin(), fields.end(), [](const SummaryField& f) {
    return std::strcmp(f.name, "relaxation") == 0;
  });
  fields.insert(relaxation + 1, registered.begin(), registered.end());
  return fields;
}

}  // namespace lem
