#include "lem/report/tension_summary.hpp"

#include <algorithm>
#include <cmath>

namespace lem {

Summary tension_summary(const SetupReport& setup, const DistributedLattice& lattice, double bond_k,
                        const TensionResponse& r, const SolveReport& solve) {
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
  sum.add("constraints_seconds", setup.seconds_constraints, "s");
  sum.add("distribute_seconds", setup.seconds_distribute, "s");
  sum.add("edge_cut", static_cast<long long>(setup.edge_cut));
  int ranks = 1;
  MPI_Comm_size(lattice.comm, &ranks);
  sum.add("mpi_ranks", static_cast<long long>(ranks));
  return sum;
}

}  // namespace lem
