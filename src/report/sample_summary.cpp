#include "lem/report/sample_summary.hpp"

#include "lem/base/log.hpp"
#include "lem/base/phase.hpp"

namespace lem {

const std::vector<SummaryField>& sample_summary_fields() {
  // The statistics are defined in docs/model/cemented-samples.md, "What a
  // sample reports".
  static const std::vector<SummaryField> fields = {
      {"sample_file", "", "the sample file written"},
      {"particles", "", "spheres of the sample, those reaching in included"},
      {"sample_particles", "", "sphere centres in the cube (`-sample_particles`)"},
      {"side", "d_min", "the cube's side"},
      {"nodes", "", "nodes of the lattice"},
      {"bonds", "", "bonds of the lattice"},
      {"nodes_per_particle", "", "nodes / centres in the cube"},
      {"rho_p_geometric", "",
       "ρ^p: the spheres' exact volume clipped to the cube, over its volume"},
      {"rho_p", "", "ρ^p on the lattice: Voronoi volume of the particle nodes over the cube's"},
      {"rho_m_requested", "", "ρ^m asked for (`-matrix_fraction`)"},
      {"rho_m", "", "ρ^m on the lattice"},
      {"rho_v", "", "ρ^v on the lattice"},
      {"bonds_p", "", "particle bonds"},
      {"bonds_m", "", "matrix bonds"},
      {"bonds_v", "", "void bonds"},
      {"bonds_pp", "", "particle–particle contact bonds"},
      {"bonds_pm", "", "particle–matrix interface bonds"},
      {"bonds_per_particle", "", "p bonds per particle (paper: ≈1550)"},
      {"eligible_pairs", "", "pairs of particles near enough for a bridge"},
      {"eligible_per_particle", "", "eligible bridge ends per particle"},
      {"bridges", "", "bridges holding matrix"},
      {"bridges_per_particle", "", "bridge ends holding matrix per particle"},
      {"interface_ratio_Spm_Sp", "",
       "S^pm/S^p: the share of the resolved particle surface covered by matrix"},
      {"packing_seed", "", "`-pack_seed`"},
      {"packing_particles", "", "spheres of the periodic packing"},
      {"lattice_seed", "", "`-lattice_seed`"},
      {"lattice_generator", "", "`serial` or `cells` (`-lattice_generator`)"},
      {"matrix_max_gap", "d_min", "the largest gap a bridge spans"},
      {"void_bonds", "", "the rule that makes void bonds (`any_end` or `both_ends`)"},
      {"seconds_packing", "s", "the packing"},
      {"seconds_lattice", "s", "the lattice"},
      {"seconds_voronoi", "s", "the Voronoi volumes"},
      {"seconds_phases", "s", "the matrix and the phases"},
      {"peak_memory_mb", "MB", "the largest peak resident memory of a rank"},
      {"peak_memory_mean_mb", "MB", "the mean over the ranks of their peak resident memory"},
  };
  return fields;
}

Summary sample_summary(const CementedSampleStats& st, const CementedSampleSpec& spec,
                       const std::string& file, const PeakMemory& memory) {
  Summary sum;
  Summary::Described d(sum, sample_summary_fields());
  const auto count = [&](const std::string& name, std::int64_t n) {
    d.put(name, static_cast<long long>(n));
  };
  d.put("sample_file", file);
  count("particles", st.particles);
  count("sample_particles", spec.sample_particles);
  d.put("side", st.side);
  count("nodes", st.nodes);
  count("bonds", st.bonds);
  d.put("nodes_per_particle", st.nodes_per_particle);
  d.put("rho_p_geometric", st.rho_p_geometric);
  d.put("rho_p", st.rho_p);
  d.put("rho_m_requested", spec.bridges.matrix_fraction);
  d.put("rho_m", st.rho_m);
  d.put("rho_v", st.rho_v);
  for (int k = 0; k < kPhaseCount; ++k)
    count(std::string("bonds_") + phase_name(static_cast<Phase>(k)), st.bonds_per_phase[k]);
  d.put("bonds_per_particle", st.bonds_per_particle);
  count("eligible_pairs", st.eligible_pairs);
  d.put("eligible_per_particle", st.eligible_per_particle);
  count("bridges", st.bridges);
  d.put("bridges_per_particle", st.bridges_per_particle);
  d.put("interface_ratio_Spm_Sp", st.interface_ratio);
  count("packing_seed", static_cast<std::int64_t>(spec.packing.seed));
  count("packing_particles", spec.packing.count);
  count("lattice_seed", static_cast<std::int64_t>(spec.lattice.seed));
  d.put("lattice_generator",
        std::string(spec.generator == LatticeGenerator::cells ? "cells" : "serial"));
  d.put("matrix_max_gap", spec.bridges.max_gap / spec.packing.d_min);
  d.put("void_bonds", std::string(void_rule_name(spec.bridges.void_bonds)));
  d.put("seconds_packing", st.packing_seconds);
  d.put("seconds_lattice", st.lattice_seconds);
  d.put("seconds_voronoi", st.voronoi_seconds);
  d.put("seconds_phases", st.phases_seconds);
  d.put("peak_memory_mb", memory.max_mb);
  d.put("peak_memory_mean_mb", memory.mean_mb);
  d.done();
  return sum;
}

void say_sample_report(const CementedSampleStats& st, const CementedSampleSpec& spec) {
  say("sample: %lld spheres (%lld centres inside), side %.5g d_min; %lld "
      "nodes, %lld bonds "
      "(%.0f nodes per particle)\n",
      (long long)st.particles, (long long)spec.sample_particles, st.side, (long long)st.nodes,
      (long long)st.bonds, st.nodes_per_particle);
  say("rho_p %.4f geometric, %.4f on the lattice; rho_m %.4f requested, %.4f "
      "on the "
      "lattice; rho_v %.4f\n",
      st.rho_p_geometric, st.rho_p, spec.bridges.matrix_fraction, st.rho_m, st.rho_v);
  say("bonds per phase (void rule %s):", void_rule_name(spec.bridges.void_bonds));
  for (int k = 0; k < kPhaseCount; ++k)
    say("  %s %lld", phase_name(static_cast<Phase>(k)), (long long)st.bonds_per_phase[k]);
  say("\n");
  say("p bonds per particle %.0f (paper ~1550); %lld eligible pairs (%.1f per "
      "particle), "
      "%lld bridges holding matrix, %.1f per particle (paper ~9); S^pm/S^p "
      "%.3f\n",
      st.bonds_per_particle, (long long)st.eligible_pairs, st.eligible_per_particle,
      (long long)st.bridges, st.bridges_per_particle, st.interface_ratio);
  say("time: packing %.2f s, lattice %.2f s, Voronoi %.2f s, matrix and phases "
      "%.2f s\n",
      st.packing_seconds, st.lattice_seconds, st.voronoi_seconds, st.phases_seconds);
}

}  // namespace lem
