// The summary record of an elastic tension test (sample facts, solver
// figures, moduli); assembled above the protocol, from the set-up report.
#pragma once

#include "lem/system/distributed_lattice.hpp"
#include "lem/system/elastic_system.hpp"
#include "lem/setup/setup.hpp"
#include "lem/base/summary.hpp"

namespace lem {

/// Sample facts, solver figures and moduli; E in units of k/a (k of the
/// lattice option -lattice_k, a the mean bond length).
Summary tension_summary(const SetupReport& setup, const DistributedLattice& lattice, double bond_k,
                        const TensionResponse& response, const SolveReport& solve);

}  // namespace lem
