#include "lem/protocol/relaxation.hpp"

#include "lem/base/collective.hpp"
#include "lem/base/error.hpp"
#include "lem/base/log.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <utility>
#include <stdexcept>

namespace lem {

Relaxation::Relaxation(const RelaxationParts& parts) : p_(parts), pieces_(parts.lattice) {
  // A solve that meets -ksp_rtol with a bond in doubt goes on, in its own
  // Krylov space, to -fracture_tie_rtol; with decided solves, only until
  // the certificate puts every bond in doubt beyond its error.  next_batch
  // solves again the fields that did neither.
  Tightening t{p_.options.tie_rtol, [this] {
                 tie_check_.clear();  // the tail starts again with each solve
                 tie_tail_.restart();
                 return p_.critical.in_doubt(p_.system.bond_tensions());
               }};
  if (decides_early()) {
    t.interval = p_.options.decision_interval;
    t.settled = [this] { return ties_settled(); };
  }
  p_.system.set_tightening(std::move(t));
}

Relaxation::~Relaxation() { p_.system.set_tightening({}); }

bool Relaxation::ties_settled() {
  std::vector<double> now = p_.system.bond_tensions();
  bool settled = false;
  if (!tie_check_.empty()) {  // the first check only records the field
    const double change = p_.critical.force_error(now, tie_check_, 1.0);
    const double tail = tie_tail_.next(change);
    settled =
        tail > 0 && p_.critical.doubts_decided(now, p_.options.decision_safety * tail * change);
  }
  tie_check_ = std::move(now);
  return settled;
}

bool Relaxation::break_batch(const std::vector<Rupture>& batch, std::int64_t step, int cycle,
                             double strain) {
  LogStageScope stage("Ruptures");
  p_.ledger.open_batch();
  std::vector<std::int64_t> ids;
  ids.reserve(batch.size());
  for (const Rupture& x : batch) {
    ids.push_back(x.id);
    p_.tally.broken[x.phase] += 1;
    p_.recorder.rupture(step, cycle, strain, x);
  }
  p_.ledger.break_bonds(ids);
  // Pieces cut loose: pin them.  Pinned rows trade their bonds for a
  // diagonal of the same size, so the kept preconditioner stays usable (a
  // failure would retry with a new one).
  LogStageScope piece_stage("Pieces");
  const PieceReport pieces = pieces_.find();
  // Every rank must list the same nodes: gather the owned ones.
  std::vector<std::int64_t> owned_loose;
  for (int n : pieces.loose_nodes)
    if (n < p_.lattice.owned) owned_loose.push_back(p_.lattice.node_id[n]);
  std::vector<std::int64_t> loose = allgather(p_.lattice.comm, owned_loose);
  std::sort(loose.begin(), loose.end());
  if (!loose.empty()) {
    p_.tally.detached_bonds += p_.ledger.pin_nodes(loose);
    p_.tally.pinned_nodes += static_cast<std::int64_t>(loose.size());
  }
  p_.tally.pieces = pieces.pieces;
  piece_stage.pop();
  p_.system.finish_updates();
  stage.pop();
  p_.solver.note_ruptures(static_cast<std::int64_t>(batch.size()));
  return pieces.faces_joined;
}

void Relaxation::note_batch(std::int64_t step, const std::vector<Rupture>& batch,
                            RelaxationOutcome& out) {
  out.broken += static_cast<std::int64_t>(batch.size());
  out.cycles += 1;
  p_.progress.relaxing(step, out.cycles, out.broken, p_.clock.elapsed());
}

bool Relaxation::decides_early() const {
  return p_.options.decision_safety > 0 && p_.critical.rule().set_decides_batch();
}

bool Relaxation::decision_stands(FieldDecision decision, const std::vector<double>& now,
                                 const std::vector<double>& earlier) const {
  if (decision == FieldDecision::breaks) return true;
  if (decision != FieldDecision::holds || !p_.options.decided_closing) return false;
  // A step that ends here writes this field's stress to the curve: its
  // error, estimated like the forces', must be below 1e-6 of the peak; and
  // a field that will be kept goes on to -ksp_rtol in this solve (a CG
  // restarted from it would lose its Krylov space).
  const double peak = p_.tally.peak_stress, stress = p_.system.stress_of(now);
  const double change = std::abs(stress - p_.system.stress_of(earlier));
  return peak > 0 && p_.options.decision_safety * change <= kClosingStressTolerance * peak &&
         !(p_.needs_equilibrium && p_.needs_equilibrium(stress));
}

SolveReport Relaxation::solve_for_decision(double top_displacement) {
  if (!decides_early()) return p_.solver.solve(top_displacement, true);
  // Every `interval` iterations: the largest change of any force since the
  // last check, E.  While E shrinks by a factor rho < 1 per interval, what
  // is left of any force's error is at most the rest of the series,
  // E rho / (1 - rho) (each later change is at most the largest); it is
  // taken as `safety` times E max(1, rho / (1 - rho)).  The check field kept
  // beside the field is stretched to that tail (u + g (u_check - u)), so the
  // certificate scales with the field and is read back the same way
  // (CriticalBonds::force_error).  A bond's own change is no measure of its
  // error: the slow, smooth part of the error moves forces that hardly
  // change over an interval (docs/notes/fracture-certificate.md).
  std::vector<double> earlier;
  ErrorTail series;
  EarlyStop early;
  early.interval = p_.options.decision_interval;
  std::vector<double> decided;
  early.restart = [&] {
    earlier.clear();
    series.restart();
  };
  early.decided = [&] {
    LogStageScope stage("Decisions");
    std::vector<double> now = p_.system.bond_tensions();
    if (!earlier.empty()) {
      const double tail = series.next(p_.critical.force_error(now, earlier, 1.0));
      if (tail > 0) {
        std::vector<double> stretched(now.size());
        for (std::size_t b = 0; b < now.size(); ++b)
          stretched[b] = now[b] + tail * (earlier[b] - now[b]);
        if (decision_stands(p_.critical.decide(now, stretched, p_.options.decision_safety), now,
                            stretched)) {
          p_.system.stretch_check(tail);
          decided = std::move(now);
          return true;
        }
      }
    }
    earlier = std::move(now);
    p_.system.mark_check();
    return false;
  };
  const SolveReport report = p_.solver.solve(top_displacement, true, &early);
  // The next batch reads the forces the stop was decided on.
  if (report.stopped_early) {
    check_decision(decided);
    decided_ = {std::move(decided), p_.tally.solves};
  }
  return report;
}

std::vector<Rupture> Relaxation::next_batch(double top_displacement) {
  LogStageScope stage("Decisions");  // a solve logs under its own stage
  // Taken once: after this call the field may be scaled to another load.
  const DecidedForces last = std::exchange(decided_, DecidedForces{});
  if (!p_.system.at_equilibrium() && last.solves == p_.tally.solves)
    return p_.critical.find(last.tensions);  // the field the last solve stopped on: decided
  std::vector<double> tensions = p_.system.bond_tensions();
  if (!p_.system.at_equilibrium()) {
    // A field a decided solve left (scaled since, perhaps): its certificate
    // scaled with it.  What it does not decide, CG decides from there.
    const std::vector<double> earlier = p_.system.check_tensions();
    const FieldDecision d = p_.critical.decide(tensions, earlier, p_.options.decision_safety);
    if (decision_stands(d, tensions, earlier)) {
      check_decision(tensions);
    } else {
      solve_for_decision(top_displacement);
      decided_ = {};  // its forces are read here
      tensions = p_.system.bond_tensions();
    }
  }
  // Solves normally go on to the tie tolerance themselves (the Protocol's
  // Tightening); a field they did not take there (the fallback solver's, a
  // restored one) is solved again from where it is.
  if (p_.system.at_equilibrium() && p_.options.tie_rtol < p_.system.field_rtol() &&
      !p_.system.ties_settled() && p_.critical.in_doubt(tensions)) {
    const SolveReport again = p_.solver.solve_to(p_.options.tie_rtol, top_displacement);
    p_.tally.tie_solves += 1;
    p_.tally.tie_iterations += again.iterations;
    tensions = p_.system.bond_tensions();
  } else if (p_.system.ties_settled()) {
    check_decision(tensions);
  }
  return p_.critical.find(tensions);
}

void Relaxation::check_decision(const std::vector<double>& tensions) {
  static const bool wanted = std::getenv("LEM_CHECK_DECISIONS") != nullptr;
  if (!wanted) return;
  // The field solved on to 1e-12 from where it is, then put back as it was.
  ElasticSystem& system = p_.system;
  const std::vector<double> owned = system.solution(), check = system.check_solution();
  const double top = system.top_displacement();
  system.solve_to(1e-12, top);
  const std::vector<Rupture> converged = p_.critical.find(system.bond_tensions());
  system.set_state(owned, top, check);
  const std::vector<Rupture> decided = p_.critical.find(tensions);
  auto ids = [](const std::vector<Rupture>& batch) {
    std::string s;
    for (const Rupture& r : batch) {
      s += ' ';
      s += std::to_string(r.id);
    }
    return s.empty() ? std::string(" none") : s;
  };
  int rank = 0;
  MPI_Comm_rank(p_.lattice.comm, &rank);
  if (rank == 0) std::fprintf(stderr, "decision checked:%s\n", ids(decided).c_str());
  if (ids(decided) != ids(converged))
    throw std::logic_error("LEM_CHECK_DECISIONS: a decided field breaks" + ids(decided) +
                           " where the converged field breaks" + ids(converged));
}

void Relaxation::restore_state(const std::string& bytes) {
  if (!bytes.empty())
    throw std::runtime_error("a relaxation state of " + std::to_string(bytes.size()) +
                             " bytes where the scheme keeps none");
}

bool Relaxation::stress_fell() const {
  // The level at which the run ends (Protocol::end_reason): the fraction of
  // the curve's peak, that is of the equilibria of the steps before this one
  // (a step whose stress falls is no peak).  Not of the stress before the
  // step's ruptures, which is no equilibrium of the curve: a step stopped
  // below that level but above the run's would end with bonds still over
  // their thresholds, broken at the next step.
  return p_.options.stop_within_step && p_.tally.peak_stress > 0 &&
         p_.system.response().stress_zz < p_.options.stop_fraction * p_.tally.peak_stress;
}

void Relaxation::next_cycle(std::int64_t step, const RelaxationOutcome& out) const {
  if (out.cycles > 0 && p_.between_cycles) p_.between_cycles(step, out.cycles);
}

RelaxationOutcome Relaxation::relax(std::int64_t step, double top_displacement, double strain,
                                    double /*stress_before*/) {
  RelaxationOutcome out;
  for (;;) {
    next_cycle(step, out);
    const std::vector<Rupture> batch = next_batch(top_displacement);
    // An equilibrium, or a decided field that may end the step (decision_stands).
    if (batch.empty()) break;
    const bool joined = break_batch(batch, step, out.cycles, strain);
    const CycleEnd end = cycle(step, top_displacement, strain, batch, joined, out);
    if (!end.joined) {
      out.disconnected = true;
      break;
    }
    if (stress_fell()) {  // the run ends after this step, on an equilibrium
      if (end.stopped_early) p_.solver.solve(top_displacement, true);
      if (stress_fell()) break;
    }
  }
  if (out.broken > 0) {
    LogStageScope stage("Recording");
    p_.recorder.flush_ruptures();
  }
  return out;
}

CycleEnd GlobalRelaxation::cycle(std::int64_t step, double top_displacement, double /*strain*/,
                                 const std::vector<Rupture>& batch, bool joined,
                                 RelaxationOutcome& out) {
  // The run ends after a disconnecting batch: solve it to -ksp_rtol.
  const SolveReport solved =
      joined ? solve_for_decision(top_displacement) : p_.solver.solve(top_displacement, true);
  note_batch(step, batch, out);
  return {joined, solved.stopped_early};
}

}  // namespace lem
