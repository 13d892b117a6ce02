// The entries of lem_fracture's summary.json and summary.csv, in their
// order, each with its unit and meaning: the summary is written from this
// table (an entry out of order is a bug caught by every run) and
// docs/reference/outputs.md lists it (test_fracture_summary checks both
// agree).  The provenance entries that follow are common to every program.
#pragma once

#include "lem/base/summary.hpp"

#include <vector>

namespace lem {

/// `unit` is the CSV header's name[unit] ("stress": E^phase units for sample
/// files, k/a for generated lattices; "lattice": k a^2); empty for plain
/// numbers and words.
const std::vector<SummaryField>& fracture_summary_fields();

}  // namespace lem
