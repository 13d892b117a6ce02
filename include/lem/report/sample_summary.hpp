// What lem_sample reports of a cemented sample: its summary record
// (summary.json/.csv beside the sample file), written from its table of
// fields (name, unit, meaning) that docs/reference/outputs.md lists, and
// the lines it prints.
#pragma once

#include "lem/base/driver.hpp"
#include "lem/base/summary.hpp"
#include "lem/sample/cemented_sample.hpp"

#include <string>
#include <vector>

namespace lem {

/// lem_sample's summary entries, in their order.
const std::vector<SummaryField>& sample_summary_fields();

/// The summary of the sample written to `file`, from its statistics, and
/// the peak memory of the ranks that made it (before the provenance).
Summary sample_summary(const CementedSampleStats& stats, const CementedSampleSpec& spec,
                       const std::string& file, const PeakMemory& memory);

/// Rank 0 prints the sample's statistics (counts, fractions, bonds per
/// phase, bridges, stage times).
void say_sample_report(const CementedSampleStats& stats, const CementedSampleSpec& spec);

}  // namespace lem
