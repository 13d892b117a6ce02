#include "lem/report/sample_summary.hpp"

#include "lem/base/log.hpp"
#include "lem/base/phase.hpp"

namespace lem {

Summary sample_summary(const CementedSampleStats& st, const CementedSampleSpec& spec,
                       const std::string& file) {
  Summary sum;
  sum.add("sample_file", file);
  sum.add("particles", static_cast<long long>(st.particles));
  sum.add("sample_particles", static_cast<long long>(spec.sample_particles));
  sum.add("side", st.side, "d_min");
  sum.add("nodes", static_cast<long long>(st.nodes));
  sum.add("bonds", static_cast<long long>(st.bonds));
  sum.add("nodes_per_particle", st.nodes_per_particle);
  sum.add("rho_p_geometric", st.rho_p_geometric);
  sum.add("rho_p", st.rho_p);
  sum.add("rho_m_requested", spec.bridges.matrix_fraction);
  sum.add("rho_m", st.rho_m);
  sum.add("rho_v", st.rho_v);
  for (int k = 0; k < kPhaseCount; ++k)
    sum.add(std::string("bonds_") + phase_name(static_cast<Phase>(k)),
            static_cast<long long>(st.bonds_per_phase[k]));
  sum.add("bonds_per_particle", st.bonds_per_particle);
  sum.add("eligible_pairs", static_cast<long long>(st.eligible_pairs));
  sum.add("eligible_per_particle", st.eligible_per_particle);
  sum.add("bridges", static_cast<long long>(st.bridges));
  sum.add("bridges_per_particle", st.bridges_per_particle);
  sum.add("interface_ratio_Spm_Sp", st.interface_ratio);
  sum.add("packing_seed", static_cast<long long>(spec.packing.seed));
  sum.add("packing_particles", static_cast<long long>(spec.packing.count));
  sum.add("lattice_seed", static_cast<long long>(spec.lattice.seed));
  sum.add("lattice_generator",
          std::string(spec.generator == LatticeGenerator::cells ? "cells" : "serial"));
  sum.add("matrix_max_gap", spec.bridges.max_gap / spec.packing.d_min, "d_min");
  sum.add("void_bonds", std::string(void_rule_name(spec.bridges.void_bonds)));
  sum.add("seconds_packing", st.packing_seconds, "s");
  sum.add("seconds_lattice", st.lattice_seconds, "s");
  sum.add("seconds_voronoi", st.voronoi_seconds, "s");
  sum.add("seconds_phases", st.phases_seconds, "s");
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
