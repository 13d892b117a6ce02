// The convergence of E_eff with the mesh density L_n = M^(-1/3) (paper
// sect. 3, fig. 6), the work of lem_convergence: a matrix with stiff
// spherical inclusions and with spherical pores, each normalised by the
// homogeneous lattice of the same nodes, fitted linearly in L_n.
#pragma once

#include "lem/base/summary.hpp"
#include "lem/setup/setup.hpp"

#include <vector>

namespace lem {

/// lem_convergence's summary entries, in their order.
const std::vector<SummaryField>& convergence_summary_fields();
/// Its summary (the inclusions of `sample`), before the provenance.
Summary convergence_summary(const SampleOptions& sample);

}  // namespace lem
