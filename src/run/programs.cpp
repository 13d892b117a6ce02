#include "lem/run/programs.hpp"

#include "lem/packing/packing_file.hpp"
#include "lem/report/sample_summary.hpp"
#include "lem/report/tension_summary.hpp"
#include "lem/run/convergence_study.hpp"
#include "lem/run/fracture_summary.hpp"
#include "lem/run/stiffness_study.hpp"

namespace lem {

std::vector<ProgramSummary> program_summaries() {
  return {{"lem_pack", packing_summary_fields()},
          {"lem_sample", sample_summary_fields()},
          {"lem_tension", tension_summary_fields()},
          {"lem_stiffness", stiffness_summary_fields()},
          {"lem_convergence", convergence_summary_fields()},
          {"lem_fracture", fracture_summary_fields()}};
}

}  // namespace lem
