#include "lem/report/tension_summary.hpp"

#include "lem/base/phase.hpp"
#include "lem/setup/units.hpp"

#include <algorithm>
#include <cmath>

namespace lem {

const std::vector<SummaryField>& tension_summary_fields() {
  static const std::vector<SummaryField> fields = {
      {"nodes", "", "nodes of the lattice"},
      {"bonds", "", "bonds of the lattice"},
      {"active_bonds", "", "bonds in the system"},
      {"pruned_bonds", "",
       "bonds that can carry no force, left out (at nodes with fewer bonds than free "
       "degrees of freedom, or in pieces too weakly held)"},
      {"pinned_nodes", "", "nodes that carry no bond, pinned"},
      {"mean_bond_length", "length", "a, the mean bond length"},
      {"bond_length_std", "length", "standard deviation of the bond lengths"},
      {"mean_coordination", "", "mean bonds per node"},
      {"mesh_density_Ln", "", "L_n = M^(−1/3) of the M bonds"},
      {"inclusion_fraction", "", "volume fraction of the inclusions (0 without)"},
      {"inclusion_node_fraction", "", "share of the nodes inside inclusions (0 without)"},
      {"top_displacement", "length", "Δ, the displacement of the top face"},
      {"reaction", "force", "F, the force on the top face"},
      {"stress_zz", "force/length^2", "σ_zz = F over the cross-section"},
      {"strain_zz", "", "ε_zz = Δ over the height"},
      {"E_eff", "k/a",
       "the effective modulus σ_zz/ε_zz (with a sample file k = E^φ a, so in E^φ units)"},
      {"nu", "",
       "the Poisson ratio, from the lateral faces without the rigid rotation about z that "
       "the anchoring constraints leave ([theory](../model/theory.md), \"Lateral strains "
       "without the rigid rotation\")"},
      {"E_affine", "k/a", "the affine (Voigt) estimate of E_eff"},
      {"nu_affine", "", "the affine estimate of ν"},
      {"E_appendixB", "k/a", "the appendix-B value 3√2/5"},
      {"stored_energy", "force*length", "½ u·Ku"},
      {"external_work", "force*length", "½ F Δ"},
      {"energy_relative_gap", "", "\\|½ u·Ku − ½ F Δ\\| / ½ F Δ"},
      {"ksp_iterations", "", "CG iterations of the solve"},
      {"ksp_residual_norm", "", "the final residual norm"},
      {"pc_setup_seconds", "s", "preconditioner set-up"},
      {"solve_seconds", "s", "the solve"},
      {"build_seconds", "s", "building or reading the sample"},
      {"partition_seconds", "s", "the partition"},
      {"constraints_seconds", "s", "the boundary conditions and rigidity pruning"},
      {"distribute_seconds", "s", "the scatter to the ranks"},
      {"edge_cut", "", "bonds joining two ranks"},
      {"mpi_ranks", "", "MPI ranks"},
      {"sample_file", "", "sample files only: the file"},
      {"rho_p", "", "sample files only: ρ^p of the sample"},
      {"rho_m", "", "sample files only: ρ^m"},
      {"rho_v", "", "sample files only: ρ^v"},
      {"E_p", "stress", "sample files only: E^p of the phase table (`-phase_E_p`)"},
      {"E_eff_over_E_p", "", "sample files only: E_eff / E^p"},
      {"peak_memory_mb", "MB", "the largest peak resident memory of a rank"},
      {"peak_memory_mean_mb", "MB", "the mean over the ranks of their peak resident memory"},
  };
  return fields;
}

Summary tension_summary(const SampleOptions& sample, const SetupReport& setup,
                        double mean_bond_length, const TensionResponse& r, const SolveReport& solve,
                        int ranks, const PeakMemory& memory) {
  const StressUnit unit = stress_unit(sample, mean_bond_length);
  const auto& s = setup.sample;
  Summary sum;
  Summary::Described d(sum, tension_summary_fields());
  const auto count = [&](const char* name, std::int64_t n) {
    d.put(name, static_cast<long long>(n));
  };
  count("nodes", s.stats.nodes);
  count("bonds", s.stats.bonds);
  count("active_bonds", setup.active_bonds);
  count("pruned_bonds", setup.pruned_bonds);
  count("pinned_nodes", setup.pinned_nodes);
  d.put("mean_bond_length", mean_bond_length);
  d.put("bond_length_std", s.stats.std_length);
  d.put("mean_coordination", s.stats.mean_coordination);
  d.put("mesh_density_Ln", s.stats.mesh_density);
  d.put("inclusion_fraction", s.inclusion_fraction);
  d.put("inclusion_node_fraction", s.inclusion_node_fraction);
  d.put("top_displacement", r.top_displacement);
  d.put("reaction", r.reaction);
  d.put("stress_zz", r.stress_zz);
  d.put("strain_zz", r.strain_zz);
  d.put("E_eff", unit.of(r.young_modulus));
  d.put("nu", r.poisson_ratio);
  d.put("E_affine", unit.of(s.affine.young_z));
  d.put("nu_affine", s.affine.poisson_z);
  d.put("E_appendixB", 3.0 * std::sqrt(2.0) / 5.0);
  d.put("stored_energy", r.stored_energy);
  d.put("external_work", r.external_work);
  d.put("energy_relative_gap", std::fabs(r.stored_energy - r.external_work) /
                                   std::max(std::fabs(r.external_work), 1e-300));
  count("ksp_iterations", solve.iterations);
  d.put("ksp_residual_norm", solve.residual_norm);
  d.put("pc_setup_seconds", solve.setup_seconds);
  d.put("solve_seconds", solve.solve_seconds);
  d.put("build_seconds", setup.seconds_build);
  d.put("partition_seconds", setup.seconds_partition);
  d.put("constraints_seconds", setup.seconds_constraints);
  d.put("distribute_seconds", setup.seconds_distribute);
  count("edge_cut", setup.edge_cut);
  count("mpi_ranks", ranks);
  const bool from_file = !sample.sample_file.empty();
  const double e_p = sample.phases.modulus[static_cast<int>(Phase::p)];
  const auto file_only = [&](const char* name, Summary::Value value) {
    from_file ? d.put(name, std::move(value)) : d.skip(name);
  };
  file_only("sample_file", sample.sample_file);
  file_only("rho_p", s.cemented.rho_p);
  file_only("rho_m", s.cemented.rho_m);
  file_only("rho_v", s.cemented.rho_v);
  file_only("E_p", e_p);
  file_only("E_eff_over_E_p", unit.of(r.young_modulus) / e_p);
  d.put("peak_memory_mb", memory.max_mb);
  d.put("peak_memory_mean_mb", memory.mean_mb);
  d.done();
  return sum;
}

}  // namespace lem
