#include "lem/report/sample_summary.hpp"

#include "lem/base/log.hpp"
#include "lem/base/phase.hpp"

namespace lem {

namespace {

// What lem_sample's summary is written from.
struct SampleRecord {
  const CementedSampleStats& stats;
  const CementedSampleSpec& spec;
  const std::string& file;
  const PeakMemory& memory;
};

using R = SampleRecord;

// The bonds of one phase.
std::function<std::optional<Summary::Value>(const R&)> bonds_of(Phase phase) {
  return [phase](const R& r) {
    return summary_count(r.stats.bonds_per_phase[static_cast<int>(phase)]);
  };
}

const SummaryTable<R>& sample_table() {
  // The statistics are defined in docs/model/cemented-samples.md, "What a
  // sample reports".
  static const SummaryTable<R> table = {
      {"sample_file", "", "the sample file written", [](const R& r) { return r.file; }},
      {"particles", "", "spheres of the sample, those reaching in included",
       [](const R& r) { return summary_count(r.stats.particles); }},
      {"sample_particles", "", "sphere centres in the cube (`-sample_particles`)",
       [](const R& r) { return summary_count(r.spec.sample_particles); }},
      {"side", "d_min", "the cube's side", [](const R& r) { return r.stats.side; }},
      {"nodes", "", "nodes of the lattice",
       [](const R& r) { return summary_count(r.stats.nodes); }},
      {"bonds", "", "bonds of the lattice",
       [](const R& r) { return summary_count(r.stats.bonds); }},
      {"nodes_per_particle", "", "nodes / centres in the cube",
       [](const R& r) { return r.stats.nodes_per_particle; }},
      {"rho_p_geometric", "", "ρ^p: the spheres' exact volume clipped to the cube, over its volume",
       [](const R& r) { return r.stats.rho_p_geometric; }},
      {"rho_p", "", "ρ^p on the lattice: Voronoi volume of the particle nodes over the cube's",
       [](const R& r) { return r.stats.rho_p; }},
      {"rho_m_requested", "", "ρ^m asked for (`-matrix_fraction`)",
       [](const R& r) { return r.spec.bridges.matrix_fraction; }},
      {"rho_m", "", "ρ^m on the lattice", [](const R& r) { return r.stats.rho_m; }},
      {"rho_v", "", "ρ^v on the lattice", [](const R& r) { return r.stats.rho_v; }},
      {"bonds_p", "", "particle bonds", bonds_of(Phase::p)},
      {"bonds_m", "", "matrix bonds", bonds_of(Phase::m)},
      {"bonds_v", "", "void bonds", bonds_of(Phase::v)},
      {"bonds_pp", "", "particle–particle contact bonds", bonds_of(Phase::pp)},
      {"bonds_pm", "", "particle–matrix interface bonds", bonds_of(Phase::pm)},
      {"bonds_per_particle", "", "p bonds per particle (paper: ≈1550)",
       [](const R& r) { return r.stats.bonds_per_particle; }},
      {"eligible_pairs", "", "pairs of particles near enough for a bridge",
       [](const R& r) { return summary_count(r.stats.eligible_pairs); }},
      {"eligible_per_particle", "", "eligible bridge ends per particle",
       [](const R& r) { return r.stats.eligible_per_particle; }},
      {"bridges", "", "bridges holding matrix",
       [](const R& r) { return summary_count(r.stats.bridges); }},
      {"bridges_per_particle", "", "bridge ends holding matrix per particle",
       [](const R& r) { return r.stats.bridges_per_particle; }},
      {"interface_ratio_Spm_Sp", "",
       "S^pm/S^p: the share of the resolved particle surface covered by matrix",
       [](const R& r) { return r.stats.interface_ratio; }},
      {"packing_seed", "", "`-pack_seed`",
       [](const R& r) { return summary_count(static_cast<std::int64_t>(r.spec.packing.seed)); }},
      {"packing_particles", "", "spheres of the periodic packing",
       [](const R& r) { return summary_count(r.spec.packing.count); }},
      {"lattice_seed", "", "`-lattice_seed`",
       [](const R& r) { return summary_count(static_cast<std::int64_t>(r.spec.lattice.seed)); }},
      {"lattice_generator", "", "`serial` or `cells` (`-lattice_generator`)",
       [](const R& r) {
         return std::string(r.spec.generator == LatticeGenerator::cells ? "cells" : "serial");
       }},
      {"matrix_max_gap", "d_min", "the largest gap a bridge spans",
       [](const R& r) { return r.spec.bridges.max_gap / r.spec.packing.d_min; }},
      {"void_bonds", "", "the rule that makes void bonds (`any_end` or `both_ends`)",
       [](const R& r) { return std::string(void_rule_name(r.spec.bridges.void_bonds)); }},
      {"seconds_packing", "s", "the packing", [](const R& r) { return r.stats.packing_seconds; }},
      {"seconds_lattice", "s", "the lattice", [](const R& r) { return r.stats.lattice_seconds; }},
      {"seconds_voronoi", "s", "the Voronoi volumes",
       [](const R& r) { return r.stats.voronoi_seconds; }},
      {"seconds_phases", "s", "the matrix and the phases",
       [](const R& r) { return r.stats.phases_seconds; }},
      {"peak_memory_mb", "MB", "the largest peak resident memory of a rank",
       [](const R& r) { return r.memory.max_mb; }},
      {"peak_memory_mean_mb", "MB", "the mean over the ranks of their peak resident memory",
       [](const R& r) { return r.memory.mean_mb; }},
  };
  return table;
}

}  // namespace

const std::vector<SummaryField>& sample_summary_fields() {
  static const std::vector<SummaryField> fields = described_fields(sample_table());
  return fields;
}

Summary sample_summary(const CementedSampleStats& st, const CementedSampleSpec& spec,
                       const std::string& file, const PeakMemory& memory) {
  Summary sum;
  sum.add_from(sample_table(), R{st, spec, file, memory});
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
