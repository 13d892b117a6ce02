#include "lem/tension_output.hpp"

#include "lem/error.hpp"

#include <cmath>
#include <filesystem>

namespace lem {

Summary tension_summary(const SetupReport& setup, const DistributedLattice& lattice,
                        double bond_k, const TensionResponse& r, const SolveReport& solve) {
  const double a = lattice.mean_bond_length;
  const double unit = bond_k / a;  // modulus unit k/a (paper sect. 2.2)
  const auto& s = setup.sample;
  Summary sum;
  sum.add("nodes", static_cast<long long>(s.stats.nodes));
  sum.add("bonds", static_cast<long long>(s.stats.bonds));
  sum.add("active_bonds", static_cast<long long>(setup.active_bonds));
  sum.add("pruned_bonds", static_cast<long long>(setup.pruned_bonds));
  sum.add("pinned_nodes", static_cast<long long>(setup.pinned_nodes));
  sum.add("mean_bond_length", a, "length");
  sum.add("bond_length_std", s.stats.std_length, "length");
  sum.add("mean_coordination", s.stats.mean_coordination);
  sum.add("mesh_density_Ln", s.stats.mesh_density);
  sum.add("inclusion_fraction", s.inclusion_fraction);
  sum.add("inclusion_node_fraction", s.inclusion_node_fraction);
  sum.add("top_displacement", r.top_displacement, "length");
  sum.add("reaction", r.reaction, "force");
  sum.add("stress_zz", r.stress_zz, "force/length^2");
  sum.add("strain_zz", r.strain_zz);
  sum.add("E_eff", r.young_modulus / unit, "k/a");
  sum.add("nu", r.poisson_ratio);
  sum.add("E_affine", s.affine.young_z / unit, "k/a");
  sum.add("nu_affine", s.affine.poisson_z);
  sum.add("E_appendixB", 3.0 * std::sqrt(2.0) / 5.0, "k/a");
  sum.add("stored_energy", r.stored_energy, "force*length");
  sum.add("external_work", r.external_work, "force*length");
  sum.add("energy_relative_gap", std::fabs(r.stored_energy - r.external_work) /
                                     std::max(std::fabs(r.external_work), 1e-300));
  sum.add("ksp_iterations", static_cast<long long>(solve.iterations));
  sum.add("ksp_residual_norm", solve.residual_norm);
  sum.add("pc_setup_seconds", solve.setup_seconds, "s");
  sum.add("solve_seconds", solve.solve_seconds, "s");
  sum.add("build_seconds", setup.seconds_build, "s");
  sum.add("partition_seconds", setup.seconds_partition, "s");
  int ranks = 1;
  MPI_Comm_size(lattice.comm, &ranks);
  sum.add("mpi_ranks", static_cast<long long>(ranks));
  return sum;
}

std::optional<SymTensor> write_tension_fields(const std::string& stem, const DistributedLattice& lattice,
                                              const ElasticSystem& system,
                                              const Provenance& provenance,
                                              const Summary& summary) {
  NodeSlice nodes;
  nodes.coords.assign(lattice.coords.begin(), lattice.coords.begin() + lattice.owned);
  nodes.ids.assign(lattice.node_id.begin(), lattice.node_id.begin() + lattice.owned);
  Field displacement{"displacement", 3, {}};
  for (const auto& d : system.owned_displacements())
    displacement.values.insert(displacement.values.end(), d.begin(), d.end());
  Field flags{"dof_flags", 1, {}};
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
  Field force{"force", 1, {}}, stiffness{"stiffness", 1, {}}, phase{"phase", 1, {}};
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

void prepare_output_dir(MPI_Comm comm, const std::string& dir,
                        const std::vector<std::string>& result_files) {
  run_on_root(comm, [&] {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec || !std::filesystem::is_directory(dir))
      throw InputError("output directory '" + dir + "' cannot be created: " + ec.message());
    for (const auto& f : result_files) std::filesystem::remove(dir + "/" + f, ec);
  });
}

}  // namespace lem
