// Results of an elastic tension test: the summary record and the field files.
#pragma once

#include "lem/elastic_system.hpp"
#include "lem/hdf5_writer.hpp"
#include "lem/node_stress.hpp"
#include "lem/setup.hpp"
#include "lem/summary.hpp"

#include <optional>
#include <string>

namespace lem {

/// Sample facts, solver figures and moduli; E in units of k/a (k of the
/// lattice option -lattice_k, a the mean bond length).
Summary tension_summary(const SetupReport& setup, const DistributedLattice& lattice,
                        double bond_k, const TensionResponse& response,
                        const SolveReport& solve);

/// <stem>.h5 / <stem>.xmf: displacements, bond forces and stiffnesses, and
/// when the lattice has Voronoi volumes (sample files) the node stresses
/// (`stress`, Tensor6; `stress_zz`) and the volumes; it then returns their
/// volume average (also stored as the attribute mean_node_stress_zz).
/// Collective.
std::optional<SymTensor> write_tension_fields(const std::string& stem,
                                              const DistributedLattice& lattice,
                                              const ElasticSystem& system,
                                              const Provenance& provenance,
                                              const Summary& summary);

/// Create `dir` (rank 0) and remove results of an earlier run in it, so that
/// a failed run cannot leave an older summary looking like its own.
void prepare_output_dir(MPI_Comm comm, const std::string& dir,
                        const std::vector<std::string>& result_files);

}  // namespace lem
