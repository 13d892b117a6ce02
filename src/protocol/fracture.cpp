// The fracture protocol: strings the parts of fracture/ together.  Each load
// step is either idle (the field is scaled, exact) or evaluated: scaled or
// solved at the new load, then relaxed until no bond is critical.  Between
// steps the run may checkpoint, stop on a signal or end; between relaxation
// cycles it may stop on a signal, saving the equilibrium before the step.
#include "lem/protocol/fracture.hpp"

#include "lem/base/collective.hpp"
#include "lem/base/error.hpp"
#include "lem/base/log.hpp"
#include "lem/protocol/break_rule.hpp"
#include "lem/protocol/checkpoint.hpp"
#include "lem/protocol/damage_ledger.hpp"
#include "lem/protocol/registry.hpp"
#include "lem/protocol/preconditioner_policy.hpp"
#include "lem/protocol/progress.hpp"
#include "lem/protocol/recorder.hpp"
#include "lem/protocol/relaxation.hpp"
#include "lem/protocol/warnings.hpp"
#include "lem/base/options.hpp"
#include "lem/base/stop.hpp"

#include <cmath>
#include <cstdlib>
#include <memory>
#include <stdexcept>

namespace lem {

namespace {

// A stop request seen between relaxation cycles of `step`.
struct StopInRelaxation {
  int signal;
  std::int64_t step;
  int cycles;
};


class Protocol {
 public:
  Protocol(DistributedLattice& l, ElasticSystem& s, const FractureOptions& o,
           const FractureOutput& out, const Provenance& provenance)
      : l_(l),
        system_(s),
        o_(o),
        out_(out),
        rule_(break_rule_named(o.break_rule).make()),
        critical_(l, *rule_, o.tie_band * s.rtol()),
        ledger_(l, s),
        solver_(s, ledger_, {o.rebuild_after_ruptures, o.rebuild_iteration_growth},
                state_.preconditioner, state_.tally),
        recorder_(l, s, out, provenance),
        progress_(o, out),
        relaxation_(relaxation_named(o.relaxation)
                        .make(RelaxationParts{l, s, o, critical_, ledger_, solver_, recorder_,
                                              progress_, clock_, state_.tally,
                                              [this](std::int64_t step, int cycles) {
                                                stop_between_cycles(step, cycles);
                                              },
                                              [this](double stress) {
                                                return needs_equilibrium(stress);
                                              }})),
        checkpoint_(l, checkpoint_path(out.dir),
                    fracture_fingerprint(l, o, FingerprintScope::checkpoint)),
        warnings_(o, out.dir) {}

  FractureResult run();

 private:
  double displacement_of(std::int64_t step) const {
    return static_cast<double>(step) * o_.increment * l_.mean_bond_length;
  }
  double strain_of(std::int64_t step) const { return displacement_of(step) / l_.box.length(2); }
  void resume();
  /// The load steps, until one of the ends (returned, for end_reason).
  std::string load_steps();
  /// The run's result, on the field it ended on; the logs moved into place.
  FractureResult result(const std::string& end, bool resumed);
  void visit_idle(std::int64_t step);
  void visit(std::int64_t step, bool first);
  void note_peak(const TensionResponse& r);
  void hold_equilibrium();
  void save_checkpoint();
  void stop_between_cycles(std::int64_t step, int cycles);
  bool needs_equilibrium(double stress) const;
  std::string end_reason() const;

  DistributedLattice& l_;
  ElasticSystem& system_;
  const FractureOptions& o_;
  const FractureOutput& out_;
  FractureState state_;
  FractureTally& tally_ = state_.tally;
  RunClock clock_;
  std::unique_ptr<BreakRule> rule_;
  CriticalBonds critical_;
  DamageLedger ledger_;
  PreconditionerPolicy solver_;
  FractureRecorder recorder_;
  ProgressReporter progress_;
  std::unique_ptr<Relaxation> relaxation_;
  CheckpointStore checkpoint_;
  RunWarnings warnings_;
  bool disconnected_ = false;
  bool holding_ = false;             // an equilibrium is held (not in the first step)
  std::int64_t last_visit_ = 0;      // step of the previous evaluated step (snapshots)
  std::int64_t visiting_ = 0;        // the step being evaluated
  double last_checkpoint_time_ = 0;  // MPI_Wtime
};

void Protocol::resume() {
  Checkpoint c = checkpoint_.load(system_.learning_option());
  ledger_.replay(std::move(c.damage), c.state.batches);
  system_.set_state(c.displacement, displacement_of(c.state.tally.steps), c.check_displacement);
  system_.restore_learnt_space(c.learnt_space);
  // A rebuild asked for before the checkpoint (iteration growth, fallback).
  if (c.state.preconditioner.rebuild_pending) system_.rebuild_preconditioner();
  state_ = c.state;
  // A checkpoint holds the state of an evaluated step: the one the next
  // snapshot is counted from, as in the uninterrupted run.
  last_visit_ = c.state.tally.steps;
  clock_.seconds_before = c.state.seconds_before;
  try {
    relaxation_->restore_state(c.relaxation_state);
  } catch (const std::runtime_error& e) {
    throw InputError("the checkpoint '" + checkpoint_.path() +
                     "' does not fit the relaxation "
                     "scheme '" +
                     o_.relaxation + "' (" + e.what() +
                     "); remove it or pass "
                     "-checkpoint_resume false");
  }
}

void Protocol::note_peak(const TensionResponse& r) {
  if (r.stress_zz > tally_.peak_stress) {
    tally_.peak_stress = r.stress_zz;
    tally_.strain_at_peak = r.strain_zz;
  }
}

void Protocol::visit_idle(std::int64_t step) {
  LogStageScope stage("Recording");  // a scaled field: the response is all the work
  const double previous = system_.top_displacement();
  system_.rescale(displacement_of(step));
  const TensionResponse r = system_.response();
  tally_.work += 0.5 * (state_.reaction + r.reaction) * (r.top_displacement - previous);
  state_.reaction = r.reaction;
  tally_.steps = step;
  tally_.visited_steps += 1;
  note_peak(r);
  recorder_.curve_row(step, r, r.stress_zz, 0, true, tally_, clock_.elapsed());
}

void Protocol::visit(std::int64_t step, bool first) {
  visiting_ = step;
  const double previous = system_.top_displacement();
  const double delta = displacement_of(step);
  if (first || !o_.skip_idle)
    solver_.solve(delta, false);
  else
    system_.rescale(delta);
  LogStageScope response_stage("Recording");
  TensionResponse r = system_.response();
  response_stage.pop();
  tally_.work += 0.5 * (state_.reaction + r.reaction) * (delta - previous);
  // The energy the relaxation releases: the bonds' and the ground springs'
  // (both fall at a fixed load; the ground's is held apart in the balance).
  const double stress_before = r.stress_zz, energy_before = r.stored_energy + r.ground_energy;
  if (first) {
    LogStageScope stage("Decisions");
    critical_.check_first_increment(system_.bond_tensions(), o_.increment);
  }

  const RelaxationOutcome relaxed = relaxation_->relax(step, delta, r.strain_zz, stress_before);
  if (relaxed.disconnected) disconnected_ = true;
  LogStageScope record_stage("Recording");
  r = system_.response();
  tally_.released_energy += energy_before - r.stored_energy - r.ground_energy;
  state_.reaction = r.reaction;
  tally_.steps = step;
  tally_.visited_steps += 1;
  tally_.relaxation_cycles += relaxed.cycles;
  if (relaxed.broken > 0) tally_.rupture_steps += 1;
  if (!system_.at_equilibrium()) tally_.decided_steps += 1;
  if (first) tally_.young_modulus = r.young_modulus;
  note_peak(r);
  recorder_.curve_row(step, r, stress_before, relaxed.cycles, false, tally_, clock_.elapsed());
  progress_.step_done(step, strain_of(step), r.stress_zz, relaxed.broken, relaxed.cycles, tally_,
                      clock_.elapsed());
  recorder_.snapshot_if_due(step, last_visit_, r);
  last_visit_ = step;
  warnings_.after_step(tally_);
}

void Protocol::hold_equilibrium() {
  LogStageScope stage("Checkpoints");
  state_.files = recorder_.marks();
  state_.preconditioner.rebuild_pending = system_.preconditioner_rebuild_pending();
  state_.batches = ledger_.batches();
  FractureState held = state_;
  held.seconds_before = clock_.elapsed();
  checkpoint_.hold(held, relaxation_->saved_state(), ledger_.mark(), system_.solution(),
                   system_.check_solution(), system_.learnt_space());
  holding_ = true;
}

void Protocol::stop_between_cycles(std::int64_t step, int cycles) {
  // A load step's relaxation can last minutes (avalanches of tens of
  // cycles).  Its intermediate states are not saved: the equilibrium held
  // before the step is, and a resumed run computes the whole step again,
  // exactly as the uninterrupted run does.  The first step holds nothing.
  if (!holding_) return;
  if (const int signal = stop_requested(l_.comm, "relaxation_cycle"))
    throw StopInRelaxation{signal, step, cycles};
}

void Protocol::save_checkpoint() {
  LogStageScope stage("Checkpoints");
  recorder_.sync();
  checkpoint_.save(ledger_);
  last_checkpoint_time_ = MPI_Wtime();
}

bool Protocol::needs_equilibrium(double stress) const {
  // A field is kept when it may be the peak, when a snapshot is due, and
  // when the run ends after the step (end_reason, each bound widened by the
  // stress tolerance of a decided field).
  const double peak = tally_.peak_stress, margin = kClosingStressTolerance * peak;
  if (stress >= peak - margin) return true;
  if (recorder_.snapshot_due(visiting_, last_visit_)) return true;
  if (stress < o_.stop_fraction * peak + margin) return true;
  if (o_.max_strain_ratio > 0 && tally_.strain_at_peak > 0 &&
      strain_of(visiting_) > o_.max_strain_ratio * tally_.strain_at_peak)
    return true;
  return visiting_ >= o_.max_steps;
}

std::string Protocol::end_reason() const {
  const double stop_level = o_.stop_fraction * tally_.peak_stress;
  const bool broken = !ledger_.history().bond_events.empty();
  if (disconnected_) return "no piece joins the bottom to the top face";
  if (broken && state_.reaction / (l_.box.length(0) * l_.box.length(1)) < stop_level)
    return "stress below the stop fraction of the peak";
  if (broken && o_.max_strain_ratio > 0 && tally_.strain_at_peak > 0 &&
      strain_of(tally_.steps) > o_.max_strain_ratio * tally_.strain_at_peak)
    return "strain beyond -fracture_max_strain_ratio times the strain at the peak";
  if (tally_.steps >= o_.max_steps) return "reached -fracture_max_steps";
  return {};
}

FractureResult Protocol::run() {
  clock_.start = last_checkpoint_time_ = MPI_Wtime();
  if (l_.bond_strength.empty())
    throw std::logic_error("run_fracture: the lattice has no breaking thresholds");
  system_.set_reuse_preconditioner(true);
  const bool resumed = checkpoint_.exists() && o_.resume;
  if (resumed) {
    resume();
    recorder_.reopen(state_.files);
    warnings_.resumed(tally_);
    say("resumed from %s at step %lld (%lld bonds broken)\n", checkpoint_.path().c_str(),
        (long long)tally_.steps, (long long)ledger_.history().bond_events.size());
    if (const std::size_t learnt = system_.learnt_space().size(); learnt > 0)
      say("resumed the space of %s: %zu learnt vectors\n", system_.learning_option().c_str(),
          learnt);
  } else {
    recorder_.open_new();
    state_.next_checkpoint_step = o_.checkpoint_steps;
    visit(1, true);
    if (out_.elastic_fields) recorder_.elastic_fields(system_.response());
  }
  // PETSc has read its options by now: a misspelt one stops the run here.
  check_unused_options();
  const std::string end = load_steps();
  fault_pause(l_.comm, "fracture_end", "after the last load step");
  // The end is kept: on an equilibrium (a run that ends on a decided field
  // ran out of load steps).
  if (!system_.at_equilibrium()) solver_.solve(system_.top_displacement(), false);
  return result(end, resumed);
}

std::string Protocol::load_steps() {
  for (;;) {
    if (std::string end = end_reason(); !end.empty()) return end;

    const int signal = stop_requested(l_.comm, "load_step");
    double since = MPI_Wtime() - last_checkpoint_time_;
    MPI_Bcast(&since, 1, MPI_DOUBLE, 0, l_.comm);  // one decision for every rank
    const bool by_steps = o_.checkpoint_steps > 0 && tally_.steps >= state_.next_checkpoint_step;
    if (signal || by_steps || (o_.checkpoint_seconds > 0 && since >= o_.checkpoint_seconds)) {
      while (o_.checkpoint_steps > 0 && state_.next_checkpoint_step <= tally_.steps)
        state_.next_checkpoint_step += o_.checkpoint_steps;
      hold_equilibrium();
      save_checkpoint();
      if (signal)
        throw Interrupted("stopped by " + signal_name(signal) + " at step " +
                          std::to_string(tally_.steps) + "; checkpoint written to " +
                          checkpoint_.path() + "; run the same command again to resume");
    }

    LogStageScope decision_stage("Decisions");
    std::int64_t next = tally_.steps + 1;
    if (o_.skip_idle) {
      // On a decided field, each force at the top of its error estimate.
      const std::vector<double> earlier =
          system_.at_equilibrium() ? std::vector<double>{} : system_.check_tensions();
      next = critical_.next_step(system_.bond_tensions(), tally_.steps, o_.max_steps,
                                 earlier.empty() ? nullptr : &earlier, o_.decision_safety);
    }
    decision_stage.pop();
    if (next > o_.max_steps)
      return next == o_.max_steps + 1 && o_.skip_idle ? "no rupture before -fracture_max_steps"
                                                      : "reached -fracture_max_steps";
    hold_equilibrium();
    try {
      if (next - 1 > tally_.steps) visit_idle(next - 1);
      visit(next, false);
    } catch (const NumericalError& e) {
      save_checkpoint();
      throw NumericalError(std::string(e.what()) + "; the state of step " +
                           std::to_string(checkpoint_.held_state().tally.steps) + " is saved in " +
                           checkpoint_.path() +
                           ": rerun (e.g. with other -ksp_/-pc_ options) "
                           "to resume from it");
    } catch (const StopInRelaxation& stop) {
      save_checkpoint();
      throw Interrupted("stopped by " + signal_name(stop.signal) + " in the relaxation of step " +
                        std::to_string(stop.step) + " after " + std::to_string(stop.cycles) +
                        (stop.cycles == 1 ? " cycle" : " cycles") + "; the equilibrium of step " +
                        std::to_string(checkpoint_.held_state().tally.steps) + " is saved in " +
                        checkpoint_.path() +
                        ": run the same command again "
                        "to resume (step " +
                        std::to_string(stop.step) + " is computed again)");
    }
  }
}

FractureResult Protocol::result(const std::string& end, bool resumed) {
  const TensionResponse r = system_.response();
  FractureResult result;
  static_cast<FractureTally&>(result) = tally_;
  result.final_stress = r.stress_zz;
  result.final_strain = r.strain_zz;
  result.stored_energy = r.stored_energy;
  result.ground_energy = r.ground_energy;
  // W = E + G + R where every solve converged: what is left is the solver's.
  result.energy_balance_error =
      tally_.work > 0
          ? std::fabs(tally_.work - r.stored_energy - r.ground_energy - tally_.released_energy) /
                tally_.work
          : 0.0;
  // Before the logs are renamed: under -fracture_strict a warning leaves no
  // result that looks finished.
  result.peak_step = tally_.strain_at_peak / strain_of(1);
  warnings_.at_end(tally_, result.energy_balance_error, result.peak_step, result.past_peak());
  result.warnings = warnings_.list();

  // Complete: move the logs into place; the caller commits the results and
  // then drops the checkpoint.
  recorder_.finish();
  result.end_reason = end;
  result.seconds = clock_.elapsed();
  result.resumed = resumed;
  result.plugin_report = rule_->report(tally_);
  for (auto& value : relaxation_->report()) result.plugin_report.push_back(std::move(value));
  return result;
}

}  // namespace

double FractureResult::plugin_value(const std::string& name) const {
  for (const auto& [key, value] : plugin_report)
    if (key == name) return value;
  return 0;
}

FractureResult run_fracture(DistributedLattice& lattice, ElasticSystem& system,
                            const FractureOptions& options, const FractureOutput& output,
                            const Provenance& provenance) {
  // Test hook: LEM_COLLECTIVE_LIMIT=<bytes> bounds every allgather and
  // broadcast of the run (checkpoints and resumes included), so that a test
  // shows none of them carries a per-node or per-bond array.
  const char* limit = std::getenv("LEM_COLLECTIVE_LIMIT");
  const CollectiveByteLimit bound(limit ? std::strtoull(limit, nullptr, 10) : 0);
  Protocol protocol(lattice, system, options, output, provenance);
  return protocol.run();
}

}  // namespace lem
