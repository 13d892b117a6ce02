// lem_fracture with a break rule, a relaxation scheme and an output added
// from outside the library, in this one file, as docs/developer/extending.md
// walks through: each is a class or a function and one registration before
// the options are read.  A solver lever is in a file of its own
// (counted_lever.cpp), registered here by one line.  The break rule and the scheme bring their options,
// their fingerprint lines and their summary fields in their registry
// entries.
#include "lem/base/error.hpp"
#include "lem/base/files.hpp"
#include "lem/run/fracture_run.hpp"
#include "lem/base/log.hpp"
#include "lem/protocol/registry.hpp"
#include "lem/solver/levers.hpp"
#include "lem/system/solver_lever.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace {

// Break rule: of the critical bonds, the `count` of smallest threshold
// (then smallest id) break first.  All it adds to a run is in its entry
// (weakest_first_entry): its option, the line that identifies its results
// and its summary field.
class WeakestFirst final : public lem::BreakRule {
 public:
  explicit WeakestFirst(std::int64_t count) : count_(count) {}
  std::vector<lem::Rupture> batch(std::vector<lem::Rupture> critical) const override {
    const auto weaker = [](const lem::Rupture& a, const lem::Rupture& b) {
      return a.threshold != b.threshold ? a.threshold < b.threshold : a.id < b.id;
    };
    const auto kept = std::min<std::size_t>(critical.size(), static_cast<std::size_t>(count_));
    std::partial_sort(critical.begin(), critical.begin() + kept, critical.end(), weaker);
    critical.resize(kept);
    return critical;
  }
  // The thresholds are known without a solve, but which bonds are critical
  // is not: the batch follows from the critical set alone.
  bool set_decides_batch() const override { return true; }
  // From the run's tally: a resumed run reports what an uninterrupted one does.
  std::vector<std::pair<std::string, double>> report(const lem::FractureTally& run) const override {
    const double cycles = static_cast<double>(run.relaxation_cycles);
    return {{"weakest_bonds_per_cycle",
             cycles > 0 ? static_cast<double>(run.broken_total()) / cycles : 0.0}};
  }

 private:
  std::int64_t count_;
};

lem::BreakRuleEntry weakest_first_entry() {
  auto count = std::make_shared<std::int64_t>(1);  // read with the options, used by `make`
  lem::BreakRuleEntry e;
  e.name = "weakest_first";
  e.help = "the -fracture_weakest_count critical bonds of smallest threshold";
  e.make = [count] { return std::make_unique<WeakestFirst>(*count); };
  e.read_options = [count](lem::OptionGroup& g) {
    *count = g.integer("-fracture_weakest_count",
                       "weakest_first: the critical bonds that break in one relaxation cycle, "
                       "those of smallest threshold",
                       1, 1, 1'000'000'000);
  };
  e.fingerprint = [count] { return "weakest_count=" + std::to_string(*count) + "\n"; };
  e.summary = {{"weakest_bonds_per_cycle", "",
                "weakest_first: bonds broken per relaxation cycle (at most "
                "-fracture_weakest_count; 0 with other rules)"}};
  return e;
}

// Relaxation scheme: the global one, counting the load steps it relaxed,
// with an option of its own (the word its report starts with), its count in
// the summary and carried over a checkpoint.
class CountedGlobal final : public lem::GlobalRelaxation {
 public:
  CountedGlobal(const lem::RelaxationParts& parts, std::string label)
      : GlobalRelaxation(parts), label_(std::move(label)) {}
  ~CountedGlobal() override { lem::say("%s: %lld load steps relaxed\n", label_.c_str(), steps_); }
  lem::RelaxationOutcome relax(std::int64_t step, double top_displacement, double strain,
                               double stress_before) override {
    ++steps_;
    return GlobalRelaxation::relax(step, top_displacement, strain, stress_before);
  }
  std::string saved_state() const override { return std::to_string(steps_); }
  void restore_state(const std::string& bytes) override {
    if (bytes.empty() || bytes.find_first_not_of("0123456789") != std::string::npos)
      throw std::runtime_error("'" + bytes + "' is no count of load steps");
    steps_ = std::stoll(bytes);
  }
  std::vector<std::pair<std::string, double>> report() const override {
    return {{"counted_steps", static_cast<double>(steps_)}};
  }

 private:
  std::string label_;
  long long steps_ = 0;
};

// Output: broken bonds (ruptures and bonds of loose pieces: stiffness 0) in
// ten slabs of equal height, by the bond's midpoint; each rank counts the
// bonds it reports, rank 0 writes the sums.
void write_damage_profile(const lem::DistributedLattice& l, const lem::FractureResult&,
                          const std::string& path) {
  constexpr int kSlabs = 10;
  double z_range[2] = {std::numeric_limits<double>::max(), std::numeric_limits<double>::max()};
  for (const lem::Point& x : l.coords) {
    z_range[0] = std::min(z_range[0], x[2]);
    z_range[1] = std::min(z_range[1], -x[2]);
  }
  MPI_Allreduce(MPI_IN_PLACE, z_range, 2, MPI_DOUBLE, MPI_MIN, l.comm);
  const double bottom = z_range[0], height = -z_range[1] - z_range[0];
  std::array<long long, kSlabs> broken{};
  for (int b = 0; b < l.local_bonds(); ++b) {
    if (!l.bond_reported[b] || l.bond_stiffness[b] != 0) continue;
    const double z = 0.5 * (l.coords[l.bond_ends[b][0]][2] + l.coords[l.bond_ends[b][1]][2]);
    broken[std::clamp(static_cast<int>((z - bottom) / height * kSlabs), 0, kSlabs - 1)] += 1;
  }
  MPI_Allreduce(MPI_IN_PLACE, broken.data(), kSlabs, MPI_LONG_LONG, MPI_SUM, l.comm);
  lem::run_on_root(l.comm, [&] {
    std::string text = "z_low,z_high,broken\n";
    for (int k = 0; k < kSlabs; ++k)
      text += std::to_string(bottom + height * k / kSlabs) + "," +
              std::to_string(bottom + height * (k + 1) / kSlabs) + "," + std::to_string(broken[k]) +
              "\n";
    lem::write_text_file_atomically(path, text);
  });
}

}  // namespace

lem::SolverLeverEntry counted_lever_entry();  // counted_lever.cpp

int main(int argc, char** argv) {
  // The built-in levers first, so that this one goes around them: the
  // single-precision cycle (the default) copies the multigrid's own levels
  // and must wrap the multigrid itself (registered after a lever of one's
  // own, it would step aside).
  lem::register_solver_levers();
  lem::register_solver_lever(counted_lever_entry());
  lem::register_break_rule(weakest_first_entry());
  // The scheme's option lives beside its factory, which reads it.
  auto label = std::make_shared<std::string>();
  lem::register_relaxation(
      {"counted_global",
       "the global scheme, counting the load steps it relaxes",
       [label](const lem::RelaxationParts& parts) -> std::unique_ptr<lem::Relaxation> {
         return std::make_unique<CountedGlobal>(parts, *label);
       },
       [label](lem::OptionGroup& g) {
         *label = g.string("-fracture_counted_label",
                           "counted_global: the first word of its "
                           "report",
                           "counted_global");
       },
       {},
       {{"counted_steps", "", "counted_global: load steps relaxed (0 with other schemes)"}}});
  lem::register_fracture_output({"damage_profile.csv", write_damage_profile});
  return lem::fracture_program(argc, argv, "lem_fracture with example extensions\n");
}
