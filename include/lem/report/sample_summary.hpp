// What lem_sample reports of a cemented sample: its summary record
// (summary.json/.csv beside the sample file) and the lines it prints.
#pragma once

#include "lem/sample/cemented_sample.hpp"
#include "lem/base/summary.hpp"

#include <string>

namespace lem {

/// The summary of the sample written to `file`, from its statistics.
Summary sample_summary(const CementedSampleStats& stats, const CementedSampleSpec& spec,
                       const std::string& file);

/// Rank 0 prints the sample's statistics (counts, fractions, bonds per
/// phase, bridges, stage times).
void say_sample_report(const CementedSampleStats& stats, const CementedSampleSpec& spec);

}  // namespace lem
