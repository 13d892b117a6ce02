// The entries of lem_fracture's summary.json and summary.csv, in their
// order, each declared once with its unit, its meaning and how its value is
// taken from the run's record (those of the break rules and relaxation
// schemes from their registry entries).  docs/reference/fracture-outputs.md
// lists the table (test_fracture_summary checks both agree).  The
// provenance entries that follow are common to every program.
#pragma once

#include "lem/base/driver.hpp"
#include "lem/base/summary.hpp"
#include "lem/protocol/fracture.hpp"
#include "lem/protocol/options.hpp"
#include "lem/report/calibration.hpp"
#include "lem/setup/setup.hpp"

#include <string>
#include <vector>

namespace lem {

/// What lem_fracture's summary is written from: the finished run of the
/// sample and what surrounds it.
struct FractureRecord {
  const SampleOptions& sample;
  const FractureOptions& options;
  const FractureOutput& units;  // strength_unit, modulus_unit of the summary
  const Calibration& calibration;
  const SetupReport& setup;
  const FractureResult& result;
  double stress_unit = 1;  // raw stress * this = stress in E^phase (or k/a) units
  double lattice_a = 0;    // mean bond length
  std::vector<std::string> warnings;
  PeakMemory memory;  // of this process: a resumed run reports its own part
  int ranks = 1;
  double e_eff() const { return result.young_modulus * stress_unit; }
  double sigma_eff() const { return result.peak_stress * stress_unit; }
};

/// lem_fracture's table.  `unit` is the CSV header's name[unit] ("stress":
/// E^phase units for sample files, k/a for generated lattices; "lattice":
/// k a^2); empty for plain numbers and words.  After "relaxation" come the
/// fields that the entries of the registered break rules and relaxation
/// schemes declare (registry.hpp), valued by FractureResult::plugin_value
/// (0 for those not chosen: every summary has the same entries);
/// std::invalid_argument when one of them has the name of an entry of the
/// run.
SummaryTable<FractureRecord> fracture_summary_table();

/// The descriptions of its entries (for the documentation).
std::vector<SummaryField> fracture_summary_fields();

}  // namespace lem
