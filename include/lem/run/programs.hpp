// Every program of lem3d is one call: its driver (drivers/lem_<name>.cpp)
// holds its help text and calls <name>_program, which reads the options,
// runs the work inside the driver frame (run_driver: errors and stop
// requests become exit statuses) and writes the results.  lem_fracture's
// is fracture_program (fracture_run.hpp), which programs that register
// their own parts call too.
//
// A program's summary.json/.csv (lem_pack's packing.json) is written from
// its table of entries, each declared once with its name, unit, meaning and
// value (base/summary.hpp, SummaryEntry); program_summaries() lists their
// descriptions, and docs/reference/outputs.md shows each, lem_fracture's on
// docs/reference/fracture-outputs.md (test_fracture_summary keeps them
// equal).
#pragma once

#include "lem/base/summary.hpp"

#include <vector>

namespace lem {

int pack_program(int argc, char** argv, const char* help);
int sample_program(int argc, char** argv, const char* help);
int tension_program(int argc, char** argv, const char* help);
int stiffness_program(int argc, char** argv, const char* help);
int convergence_program(int argc, char** argv, const char* help);
int bench_program(int argc, char** argv, const char* help);

/// A program's summary table.
struct ProgramSummary {
  const char* program;
  std::vector<SummaryField> fields;  // a copy: lem_fracture's table is built per call
};
/// Every program that writes a summary, in the order of the outputs page.
std::vector<ProgramSummary> program_summaries();

}  // namespace lem
