#include "lem/protocol/local_relaxation.hpp"

#include "lem/protocol/registry.hpp"

#include "lem/base/log.hpp"
#include "lem/base/error.hpp"
#include "lem/system/tension.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace lem {

RelaxationEntry local_relaxation_entry() {
  // One set of options, read with the protocol's, shared by the factory and
  // the fingerprint; the summary fields are the counts of report().
  auto options = std::make_shared<LocalRelaxationOptions>();
  RelaxationEntry e;
  e.name = "local";
  e.help = "(experimental) relax patches around the new ruptures first, break the bonds they "
           "certify, and solve globally to confirm";
  e.make = [options](const RelaxationParts& parts) -> std::unique_ptr<Relaxation> {
    return std::make_unique<LocalRelaxation>(parts, *options);
  };
  e.read_options = [options](OptionGroup& g) {
    LocalRelaxationOptions& o = *options;
    o.radius = g.real("-fracture_patch_radius",
                      "local: a patch holds the nodes within this "
                      "many mean bond lengths a of the ruptures since the last global "
                      "equilibrium",
                      o.radius, 1.0, 100.0);
    o.margin = g.real("-fracture_patch_margin",
                      "local: a patch field breaks a bond only when "
                      "its force exceeds (1 + margin) times its threshold (margin: a bound on "
                      "the patch error); nearer bonds wait for the global solve",
                      o.margin, 0.0, 10.0, true);
    o.max_fraction = g.real("-fracture_patch_max_fraction",
                            "local: a patch with more than "
                            "this fraction of the free nodes is solved globally",
                            o.max_fraction, 0.0, 1.0, true);
    o.rtol = g.real("-fracture_patch_rtol",
                    "local: relative tolerance of the patch solves "
                    "(CG, options prefix -patch_)",
                    o.rtol, 0.0, 0.1, true);
  };
  e.fingerprint = [options] {
    std::ostringstream s;
    s.precision(17);
    s << "patch_radius=" << options->radius << "\npatch_margin=" << options->margin
      << "\npatch_max_fraction=" << options->max_fraction << "\npatch_rtol=" << options->rtol
      << "\n";
    return s.str();
  };
  // The counts report() gives (0 in runs of other schemes).
  e.summary = {{"patch_solves", "", "local scheme: patch solves (0 with `global`)"},
               {"patch_iterations", "", "local scheme: CG iterations of the patch solves"},
               {"patch_nodes_mean", "", "local scheme: mean free nodes of a patch"},
               {"patch_overflows", "", "local scheme: patches too large, solved globally"},
               {"patch_error_max", "",
                "local scheme: largest patch force error against the confirming "
                "global field, of max(f, mean f)"},
               {"patch_disabled_step", "",
                "local scheme: step at which patches were given up (0: never)"}};
  return e;
}

LocalRelaxation::LocalRelaxation(const RelaxationParts& parts,
                                 const LocalRelaxationOptions& options)
    : Relaxation(parts),
      o_(options),
      radius_(options.radius * parts.lattice.mean_bond_length),
      grid_(parts.lattice.box, radius_),
      cells_(grid_.cell_count()) {
  const DistributedLattice& l = p_.lattice;
  std::int64_t free = 0;
  for (int n = 0; n < l.owned; ++n) {
    cells_[grid_.cell_of(l.coords[n])].push_back(n);
    free += (l.dof_flags[n] & (kFixX | kFixY | kFixZ)) != (kFixX | kFixY | kFixZ);
  }
  MPI_Allreduce(&free, &free_nodes_, 1, MPI_INT64_T, MPI_SUM, l.comm);
  // Read the -patch_ options now: a misspelt one is then reported after the
  // first solve, not ignored until the first patch.
  KSP ksp = create_patch_solver(l.comm, o_.rtol);
  LEM_PETSC(KSPDestroy(&ksp));
}

std::vector<int> LocalRelaxation::patch_nodes(const std::vector<Rupture>& ruptures) const {
  const DistributedLattice& l = p_.lattice;
  const double r2 = radius_ * radius_;
  std::vector<char> in(l.owned, 0);
  for (const Rupture& x : ruptures) {
    const Point c{x.x, x.y, x.z};
    grid_.for_each_cell_near(c, [&](std::size_t cell) {
      for (int n : cells_[cell]) {
        double d2 = 0;
        for (int a = 0; a < 3; ++a) d2 += (l.coords[n][a] - c[a]) * (l.coords[n][a] - c[a]);
        if (d2 <= r2) in[n] = 1;
      }
      return true;
    });
  }
  std::vector<int> nodes;
  for (int n = 0; n < l.owned; ++n)
    if (in[n]) nodes.push_back(n);
  return nodes;
}

std::vector<Rupture> LocalRelaxation::certain(const std::vector<Rupture>& critical) const {
  // A zero threshold (bare contact) needs a tension clearly above the
  // patch error too: margin times the mean threshold.
  const double margin = o_.margin;
  std::vector<Rupture> sure;
  for (const Rupture& x : critical)
    if (x.force > (1 + margin) * x.threshold && x.force > margin * p_.critical.mean_threshold())
      sure.push_back(x);
  return sure;
}

double LocalRelaxation::patch_error(const std::vector<double>& patch,
                                    const std::vector<double>& global) const {
  const DistributedLattice& l = p_.lattice;
  double worst = 0, all = 0;
  for (int b = 0; b < l.local_bonds(); ++b) {
    if (!l.bond_reported[b] || l.bond_stiffness[b] <= 0) continue;
    worst = std::max(worst, std::fabs(global[b] - patch[b]) /
                                std::max(l.bond_strength[b], p_.critical.mean_threshold()));
  }
  MPI_Allreduce(&worst, &all, 1, MPI_DOUBLE, MPI_MAX, l.comm);
  return all;
}

bool LocalRelaxation::local_phase(std::int64_t step, double strain, std::vector<Rupture> batch,
                                  RelaxationOutcome& out, std::vector<double>& patch_tensions) {
  // Patches around every batch since the last global solve (so the last
  // one is as accurate as a single patch around all of them), as long as
  // they certify ruptures.
  std::vector<Rupture> phase = batch;
  for (;;) {
    const std::vector<int> nodes = patch_nodes(phase);
    std::int64_t size = static_cast<std::int64_t>(nodes.size()), total = 0;
    MPI_Allreduce(&size, &total, 1, MPI_INT64_T, MPI_SUM, p_.lattice.comm);
    if (static_cast<double>(total) > o_.max_fraction * static_cast<double>(free_nodes_)) {
      counters_.overflows += 1;
      return true;
    }
    const SolveReport r = p_.system.relax_patch(nodes, o_.rtol);
    counters_.solves += 1;
    counters_.iterations += r.iterations;
    counters_.nodes += total;
    if (r.reason < 0) return true;  // leave it to the global solve
    std::vector<double> tensions = p_.system.bond_tensions();
    batch = certain(p_.critical.find(tensions));
    if (batch.empty()) {
      patch_tensions = std::move(tensions);  // the field the global solve will check
      return true;
    }
    phase.insert(phase.end(), batch.begin(), batch.end());
    const bool joined = break_batch(batch, step, out.cycles, strain);
    note_batch(step, batch, out);
    if (!joined) return false;
  }
}

void LocalRelaxation::check_patch_error(std::int64_t step,
                                        const std::vector<double>& patch_tensions) {
  const double e = patch_error(patch_tensions, p_.system.bond_tensions());
  counters_.error_max = std::max(counters_.error_max, e);
  if (e > o_.margin && counters_.disabled_step == 0) {
    // The margin did not bound the patch error: decisions of this phase
    // may differ from the reference's; take none on patches again.
    counters_.disabled_step = step;
    say("step %lld: a patch field erred by %.3g of a threshold, above -fracture_patch_margin "
        "%.3g; the rest of the run relaxes globally\n",
        static_cast<long long>(step), e, o_.margin);
  }
}

CycleEnd LocalRelaxation::cycle(std::int64_t step, double top_displacement, double strain,
                                const std::vector<Rupture>& batch, bool joined,
                                RelaxationOutcome& out) {
  // `batch` came from a global equilibrium: its decisions are exact.
  note_batch(step, batch, out);
  std::vector<double> patch_tensions;
  if (joined && counters_.disabled_step == 0)
    joined = local_phase(step, strain, batch, out, patch_tensions);
  p_.solver.solve(top_displacement, true);
  if (joined && !patch_tensions.empty()) check_patch_error(step, patch_tensions);
  return {joined, false};
}

std::string LocalRelaxation::saved_state() const {
  static_assert(std::is_trivially_copyable_v<Counters>);
  return std::string(reinterpret_cast<const char*>(&counters_), sizeof(counters_));
}

void LocalRelaxation::restore_state(const std::string& bytes) {
  if (bytes.size() != sizeof(counters_))
    throw std::runtime_error("a local relaxation state of " + std::to_string(bytes.size()) +
                             " bytes, not " + std::to_string(sizeof(counters_)));
  std::memcpy(&counters_, bytes.data(), sizeof(counters_));
}

std::vector<std::pair<std::string, double>> LocalRelaxation::report() const {
  const auto real = [](std::int64_t n) { return static_cast<double>(n); };
  return {{"patch_solves", real(counters_.solves)},
          {"patch_iterations", real(counters_.iterations)},
          {"patch_nodes_mean",
           counters_.solves > 0 ? real(counters_.nodes) / real(counters_.solves) : 0.0},
          {"patch_overflows", real(counters_.overflows)},
          {"patch_error_max", counters_.error_max},
          {"patch_disabled_step", real(counters_.disabled_step)}};
}

}  // namespace lem
