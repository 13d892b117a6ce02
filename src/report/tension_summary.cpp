#include "lem/report/tension_summary.hpp"

#include "lem/base/phase.hpp"
#include "lem/setup/units.hpp"

#include <algorithm>
#include <cmath>

namespace lem {

namespace {

// What lem_tension's summary is written from.
struct TensionRecord {
  const SampleOptions& sample;
  const SetupReport& setup;
  double mean_bond_length;
  const TensionResponse& response;
  const SolveReport& solve;
  int ranks;
  const PeakMemory& memory;
  StressUnit unit;  // of the moduli (setup/units.hpp)
  bool from_file() const { return !sample.sample_file.empty(); }
  double e_p() const { return sample.phases.modulus[static_cast<int>(Phase::p)]; }
};

using R = TensionRecord;

// An entry of sample files only: nothing for a generated lattice.
std::function<std::optional<Summary::Value>(const R&)> file_only(
    Summary::Value (*value)(const R&)) {
  return [value](const R& r) -> std::optional<Summary::Value> {
    if (!r.from_file()) return std::nullopt;
    return value(r);
  };
}

const SummaryTable<R>& tension_table() {
  static const SummaryTable<R> table = {
      {"nodes", "", "nodes of the lattice",
       [](const R& r) { return summary_count(r.setup.sample.stats.nodes); }},
      {"bonds", "", "bonds of the lattice",
       [](const R& r) { return summary_count(r.setup.sample.stats.bonds); }},
      {"active_bonds", "", "bonds in the system",
       [](const R& r) { return summary_count(r.setup.active_bonds); }},
      {"pruned_bonds", "",
       "bonds that can carry no force, left out (at nodes with fewer bonds than free "
       "degrees of freedom, or in pieces too weakly held)",
       [](const R& r) { return summary_count(r.setup.pruned_bonds); }},
      {"pinned_nodes", "", "nodes that carry no bond, pinned",
       [](const R& r) { return summary_count(r.setup.pinned_nodes); }},
      {"mean_bond_length", "length", "a, the mean bond length",
       [](const R& r) { return r.mean_bond_length; }},
      {"bond_length_std", "length", "standard deviation of the bond lengths",
       [](const R& r) { return r.setup.sample.stats.std_length; }},
      {"mean_coordination", "", "mean bonds per node",
       [](const R& r) { return r.setup.sample.stats.mean_coordination; }},
      {"mesh_density_Ln", "", "L_n = M^(−1/3) of the M bonds",
       [](const R& r) { return r.setup.sample.stats.mesh_density; }},
      {"inclusion_fraction", "", "volume fraction of the inclusions (0 without)",
       [](const R& r) { return r.setup.sample.inclusion_fraction; }},
      {"inclusion_node_fraction", "", "share of the nodes inside inclusions (0 without)",
       [](const R& r) { return r.setup.sample.inclusion_node_fraction; }},
      {"top_displacement", "length", "Δ, the displacement of the top face",
       [](const R& r) { return r.response.top_displacement; }},
      {"reaction", "force", "F, the force on the top face",
       [](const R& r) { return r.response.reaction; }},
      {"stress_zz", "force/length^2", "σ_zz = F over the cross-section",
       [](const R& r) { return r.response.stress_zz; }},
      {"strain_zz", "", "ε_zz = Δ over the height",
       [](const R& r) { return r.response.strain_zz; }},
      {"E_eff", "k/a",
       "the effective modulus σ_zz/ε_zz (with a sample file k = E^φ a, so in E^φ units)",
       [](const R& r) { return r.unit.of(r.response.young_modulus); }},
      {"nu", "",
       "the Poisson ratio, from the lateral faces without the rigid rotation about z that "
       "the anchoring constraints leave ([theory](../model/theory.md), \"Lateral strains "
       "without the rigid rotation\")",
       [](const R& r) { return r.response.poisson_ratio; }},
      {"E_affine", "k/a", "the affine (Voigt) estimate of E_eff",
       [](const R& r) { return r.unit.of(r.setup.sample.affine.young_z); }},
      {"nu_affine", "", "the affine estimate of ν",
       [](const R& r) { return r.setup.sample.affine.poisson_z; }},
      {"E_appendixB", "k/a", "the appendix-B value 3√2/5",
       [](const R&) { return 3.0 * std::sqrt(2.0) / 5.0; }},
      {"stored_energy", "force*length", "½ u·Ku",
       [](const R& r) { return r.response.stored_energy; }},
      {"external_work", "force*length", "½ F Δ",
       [](const R& r) { return r.response.external_work; }},
      {"energy_relative_gap", "", "\\|½ u·Ku − ½ F Δ\\| / ½ F Δ",
       [](const R& r) {
         return std::fabs(r.response.stored_energy - r.response.external_work) /
                std::max(std::fabs(r.response.external_work), 1e-300);
       }},
      {"ksp_iterations", "", "CG iterations of the solve",
       [](const R& r) { return summary_count(r.solve.iterations); }},
      {"ksp_residual_norm", "", "the final residual norm",
       [](const R& r) { return r.solve.residual_norm; }},
      {"pc_setup_seconds", "s", "preconditioner set-up",
       [](const R& r) { return r.solve.setup_seconds; }},
      {"solve_seconds", "s", "the solve", [](const R& r) { return r.solve.solve_seconds; }},
      {"build_seconds", "s", "building or reading the sample",
       [](const R& r) { return r.setup.seconds_build; }},
      {"partition_seconds", "s", "the partition",
       [](const R& r) { return r.setup.seconds_partition; }},
      {"constraints_seconds", "s", "the boundary conditions and rigidity pruning",
       [](const R& r) { return r.setup.seconds_constraints; }},
      {"distribute_seconds", "s", "the scatter to the ranks",
       [](const R& r) { return r.setup.seconds_distribute; }},
      {"edge_cut", "", "bonds joining two ranks",
       [](const R& r) { return summary_count(r.setup.edge_cut); }},
      {"mpi_ranks", "", "MPI ranks", [](const R& r) { return summary_count(r.ranks); }},
      {"sample_file", "", "sample files only: the file",
       file_only([](const R& r) -> Summary::Value { return r.sample.sample_file; })},
      {"rho_p", "", "sample files only: ρ^p of the sample",
       file_only([](const R& r) -> Summary::Value { return r.setup.sample.cemented.rho_p; })},
      {"rho_m", "", "sample files only: ρ^m",
       file_only([](const R& r) -> Summary::Value { return r.setup.sample.cemented.rho_m; })},
      {"rho_v", "", "sample files only: ρ^v",
       file_only([](const R& r) -> Summary::Value { return r.setup.sample.cemented.rho_v; })},
      {"E_p", "stress", "sample files only: E^p of the phase table (`-phase_E_p`)",
       file_only([](const R& r) -> Summary::Value { return r.e_p(); })},
      {"E_eff_over_E_p", "", "sample files only: E_eff / E^p",
       file_only([](const R& r) -> Summary::Value {
         return r.unit.of(r.response.young_modulus) / r.e_p();
       })},
      {"peak_memory_mb", "MB", "the largest peak resident memory of a rank",
       [](const R& r) { return r.memory.max_mb; }},
      {"peak_memory_mean_mb", "MB", "the mean over the ranks of their peak resident memory",
       [](const R& r) { return r.memory.mean_mb; }},
  };
  return table;
}

}  // namespace

const std::vector<SummaryField>& tension_summary_fields() {
  static const std::vector<SummaryField> fields = described_fields(tension_table());
  return fields;
}

Summary tension_summary(const SampleOptions& sample, const SetupReport& setup,
                        double mean_bond_length, const TensionResponse& r, const SolveReport& solve,
                        int ranks, const PeakMemory& memory) {
  Summary sum;
  sum.add_from(tension_table(), R{sample, setup, mean_bond_length, r, solve, ranks, memory,
                                  stress_unit(sample, mean_bond_length)});
  return sum;
}

}  // namespace lem
