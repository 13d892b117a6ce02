// lem_fracture with one break rule and one relaxation scheme added from
// outside the library, as docs/developer/extending.md walks through: each is
// a class and one registration before the options are read.
#include "lem/fracture_run.hpp"
#include "lem/log.hpp"
#include "lem/protocol/registry.hpp"

#include <algorithm>

namespace {

// Break rule: of the critical bonds, the one of smallest threshold (then
// smallest id) breaks first.
class WeakestFirst final : public lem::BreakRule {
 public:
  std::vector<lem::Rupture> batch(std::vector<lem::Rupture> critical) const override {
    if (critical.empty()) return critical;
    return {*std::min_element(critical.begin(), critical.end(),
                              [](const lem::Rupture& a, const lem::Rupture& b) {
                                return a.threshold != b.threshold ? a.threshold < b.threshold
                                                                  : a.id < b.id;
                              })};
  }
  // The thresholds are known without a solve, but which bonds are critical
  // is not: the batch follows from the critical set alone.
  bool set_decides_batch() const override { return true; }
};

// Relaxation scheme: the global one, counting the load steps it relaxed.
class CountedGlobal final : public lem::GlobalRelaxation {
 public:
  using GlobalRelaxation::GlobalRelaxation;
  ~CountedGlobal() override { lem::say("counted_global: %lld load steps relaxed\n", steps_); }
  lem::RelaxationOutcome relax(std::int64_t step, double top_displacement, double strain,
                               double stress_before) override {
    ++steps_;
    return GlobalRelaxation::relax(step, top_displacement, strain, stress_before);
  }

 private:
  long long steps_ = 0;
};

}  // namespace

int main(int argc, char** argv) {
  lem::register_break_rule({"weakest_first", "the critical bond of smallest threshold",
                            [] { return std::make_unique<WeakestFirst>(); }});
  lem::register_relaxation(
      {"counted_global", "the global scheme, counting the load steps it relaxes",
       [](const lem::RelaxationParts& parts) -> std::unique_ptr<lem::Relaxation> {
         return std::make_unique<CountedGlobal>(parts);
       }});
  return lem::fracture_program(argc, argv, "lem_fracture with example extensions\n");
}
