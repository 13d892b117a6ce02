#include "lem/fields/tension_output.hpp"


namespace lem {

std::optional<SymTensor> write_tension_fields(const std::string& stem,
                                              const DistributedLattice& lattice,
                                              const ElasticSystem& system,
                                              const Provenance& provenance,
                                              const Summary& summary) {
  NodeSlice nodes;
  nodes.coords.assign(lattice.coords.begin(), lattice.coords.begin() + lattice.owned);
  nodes.ids.assign(lattice.node_id.begin(), lattice.node_id.begin() + lattice.owned);
  Field displacement{"displacement", 3, {}};
  for (const auto& d : system.owned_displacements())
    displacement.values.insert(displacement.values.end(), d.begin(), d.end());
  Field flags{"dof_flags", 1, {}, true};
  for (int n = 0; n < lattice.owned; ++n) flags.values.push_back(lattice.dof_flags[n]);
  nodes.fields = {displacement, flags};
  const auto tension = system.bond_tensions();
  auto scalars = summary.numbers();
  std::optional<SymTensor> mean;
  if (!lattice.node_volume.empty()) {
    const std::vector<SymTensor> node_stress = node_stresses(lattice, tension);
    Field stress{"stress", 6, {}}, stress_zz{"stress_zz", 1, {}}, volume{"volume", 1, {}};
    for (const SymTensor& t : node_stress) {
      stress.values.insert(stress.values.end(), t.begin(), t.end());
      stress_zz.values.push_back(t[kZZ]);
    }
    volume.values.assign(lattice.node_volume.begin(), lattice.node_volume.begin() + lattice.owned);
    nodes.fields.insert(nodes.fields.end(), {stress, stress_zz, volume});
    // The identity of appendix C (= the applied stress at equilibrium).
    mean = volume_average(lattice, node_stress);
    scalars.emplace_back("mean_node_stress_zz", (*mean)[kZZ]);
  }

  BondSlice bonds;
  Field force{"force", 1, {}}, stiffness{"stiffness", 1, {}}, phase{"phase", 1, {}, true};
  for (int b = 0; b < lattice.local_bonds(); ++b) {
    if (!lattice.bond_reported[b]) continue;
    const auto [p, q] = lattice.bond_ends[b];
    bonds.ends.push_back({lattice.global_index[p], lattice.global_index[q]});
    bonds.ids.push_back(lattice.bond_id[b]);
    force.values.push_back(tension[b]);
    stiffness.values.push_back(lattice.bond_stiffness[b]);
    if (!lattice.bond_tag.empty()) phase.values.push_back(lattice.bond_tag[b]);
  }
  // Broken (or detached) bonds keep their place with stiffness 0.
  bonds.fields = {force, stiffness};
  if (!lattice.bond_tag.empty()) bonds.fields.push_back(phase);
  write_lattice_fields(lattice.comm, stem, nodes, bonds, provenance, scalars);
  return mean;
}

}  // namespace lem
