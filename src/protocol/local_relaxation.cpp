#include "lem/protocol/local_relaxation.hpp"

#include "lem/driver.hpp"
#include "lem/error.hpp"
#include "lem/tension.hpp"

#include <algorithm>
#include <cmath>

namespace lem {

LocalRelaxation::LocalRelaxation(const RelaxationParts& parts)
    : Relaxation(parts),
      radius_(parts.options.patch_radius * parts.lattice.mean_bond_length),
      grid_(parts.lattice.box, radius_),
      cells_(grid_.cell_count()) {
  const DistributedLattice& l = p_.lattice;
  std::int64_t free = 0;
  for (int n = 0; n < l.owned; ++n) {
    cells_[grid_.cell_of(l.coords[n])].push_back(n);
    free += (l.dof_flags[n] & (kFixX | kFixY | kFixZ)) != (kFixX | kFixY | kFixZ);
  }
  MPI_Allreduce(&free, &free_nodes_, 1, MPI_INT64_T, MPI_SUM, l.comm);
  double sums[2] = {0, 0}, totals[2];
  for (int b = 0; b < l.local_bonds(); ++b)
    if (l.bond_reported[b] && l.bond_strength[b] > 0) sums[0] += l.bond_strength[b], sums[1] += 1;
  MPI_Allreduce(sums, totals, 2, MPI_DOUBLE, MPI_SUM, l.comm);
  mean_threshold_ = totals[1] > 0 ? totals[0] / totals[1] : 1.0;
  // Read the -patch_ options now: a misspelt one is then reported after the
  // first solve, not ignored until the first patch.
  KSP ksp = create_patch_solver(l.comm, p_.options.patch_rtol);
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
  const double margin = p_.options.patch_margin;
  std::vector<Rupture> sure;
  for (const Rupture& x : critical)
    if (x.force > (1 + margin) * x.threshold && x.force > margin * mean_threshold_)
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
                                std::max(l.bond_strength[b], mean_threshold_));
  }
  MPI_Allreduce(&worst, &all, 1, MPI_DOUBLE, MPI_MAX, l.comm);
  return all;
}

RelaxationOutcome LocalRelaxation::relax(std::int64_t step, double top_displacement,
                                         double strain, double stress_before) {
  RelaxationOutcome out;
  const FractureOptions& o = p_.options;
  auto count = [&](const std::vector<Rupture>& batch, bool joined) {
    out.broken += static_cast<std::int64_t>(batch.size());
    out.cycles += 1;
    p_.progress.relaxing(step, out.cycles, out.broken, p_.clock.elapsed());
    if (!joined) out.disconnected = true;
    return joined;
  };
  for (;;) {
    // The field is a global equilibrium here: its decisions are exact.
    std::vector<Rupture> batch = p_.critical.find(p_.system.bond_tensions());
    if (batch.empty()) break;
    if (!count(batch, break_batch(batch, step, out.cycles, strain))) break;
    if (p_.tally.patch_disabled_step > 0) {
      p_.solver.solve(top_displacement, true);
      if (stress_fell(stress_before)) break;
      continue;
    }
    // Local phase: patches around every batch since the last global solve
    // (so the last one is as accurate as a single patch around all of
    // them), as long as they certify ruptures.
    std::vector<double> patch_tensions;
    std::vector<Rupture> phase = batch;
    for (;;) {
      const std::vector<int> nodes = patch_nodes(phase);
      std::int64_t size = static_cast<std::int64_t>(nodes.size()), total = 0;
      MPI_Allreduce(&size, &total, 1, MPI_INT64_T, MPI_SUM, p_.lattice.comm);
      if (static_cast<double>(total) > o.patch_max_fraction * static_cast<double>(free_nodes_)) {
        p_.tally.patch_overflows += 1;
        patch_tensions.clear();
        break;
      }
      const SolveReport r = p_.system.relax_patch(nodes, o.patch_rtol);
      p_.tally.patch_solves += 1;
      p_.tally.patch_iterations += r.iterations;
      p_.tally.patch_nodes += total;
      if (r.reason < 0) {  // leave it to the global solve
        patch_tensions.clear();
        break;
      }
      patch_tensions = p_.system.bond_tensions();
      batch = certain(p_.critical.find(patch_tensions));
      if (batch.empty()) break;
      patch_tensions.clear();
      phase.insert(phase.end(), batch.begin(), batch.end());
      if (!count(batch, break_batch(batch, step, out.cycles, strain))) break;
    }
    if (out.disconnected) {
      p_.solver.solve(top_displacement, true);
      break;
    }
    p_.solver.solve(top_displacement, true);
    if (!patch_tensions.empty()) {
      const double e = patch_error(patch_tensions, p_.system.bond_tensions());
      p_.tally.patch_error_max = std::max(p_.tally.patch_error_max, e);
      if (e > p_.options.patch_margin && p_.tally.patch_disabled_step == 0) {
        // The margin did not bound the patch error: decisions of this
        // phase may differ from the reference's; take none on patches again.
        p_.tally.patch_disabled_step = step;
        say("step %lld: a patch field erred by %.3g of a threshold, above -fracture_patch_margin "
            "%.3g; the rest of the run relaxes globally\n",
            static_cast<long long>(step), e, p_.options.patch_margin);
      }
    }
    if (stress_fell(stress_before)) break;  // the run ends after this step
  }
  if (out.broken > 0) p_.recorder.flush_ruptures();
  return out;
}

}  // namespace lem
