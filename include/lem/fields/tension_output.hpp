// Field files of a lattice under load: displacements, bond forces and, when
// the lattice has Voronoi volumes, node stresses.  Used by the protocol, so
// it sits below it.
#pragma once

#include "lem/system/elastic_system.hpp"
#include "lem/io/hdf5_writer.hpp"
#include "lem/system/node_stress.hpp"
#include "lem/base/summary.hpp"

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace lem {

/// <stem>.h5 / <stem>.xmf: displacements, bond forces and stiffnesses, and
/// when the lattice has Voronoi volumes (sample files) the node stresses
/// (`stress`, Tensor6; `stress_zz`) and the volumes; it then returns their
/// volume average (also stored as the attribute mean_node_stress_zz).
/// Collective.
std::optional<SymTensor> write_tension_fields(const std::string& stem,
                                              const DistributedLattice& lattice,
                                              const ElasticSystem& system,
                                              const Provenance& provenance, const Summary& summary);

}  // namespace lem
