// The summary record of an elastic tension test (lem_tension's
// summary.json/.csv): sample facts, solver figures and moduli, written from
// its table of fields (name, unit, meaning), which docs/reference/outputs.md
// lists; assembled above the protocol, from the set-up report.
#pragma once

#include "lem/base/driver.hpp"
#include "lem/base/summary.hpp"
#include "lem/setup/setup.hpp"
#include "lem/system/elastic_system.hpp"

#include <vector>

namespace lem {

/// lem_tension's entries, in their order; those marked "sample files
/// only" are left out for a generated lattice.
const std::vector<SummaryField>& tension_summary_fields();

/// The summary of a tension run of `sample` (its moduli in the unit of
/// setup/units.hpp), before the provenance; `ranks` the rank count.
Summary tension_summary(const SampleOptions& sample, const SetupReport& setup,
                        double mean_bond_length, const TensionResponse& response,
                        const SolveReport& solve, int ranks, const PeakMemory& memory);

}  // namespace lem
