// The entries of lem_fracture's summary.json and summary.csv, in their
// order, each with its unit and meaning (those of the break rules and
// relaxation schemes from their registry entries): the summary is written from this
// table (an entry out of order is a bug caught by every run) and
// docs/reference/fracture-outputs.md lists it (test_fracture_summary checks both
// agree).  The provenance entries that follow are common to every program.
#pragma once

#include "lem/base/summary.hpp"

#include <vector>

namespace lem {

/// `unit` is the CSV header's name[unit] ("stress": E^phase units for sample
/// files, k/a for generated lattices; "lattice": k a^2); empty for plain
/// numbers and words.  After "relaxation" come the fields that the entries
/// of the registered break rules and relaxation schemes declare
/// (registry.hpp); std::invalid_argument when one of them has the name of
/// an entry of the run.
std::vector<SummaryField> fracture_summary_fields();

}  // namespace lem
