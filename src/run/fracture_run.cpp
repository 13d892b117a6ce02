#include "lem/solver/levers.hpp"
#include "lem/run/fracture_run.hpp"

#include "lem/report/calibration.hpp"
#include "lem/base/collective.hpp"
#include "lem/base/driver.hpp"
#include "lem/base/files.hpp"
#include "lem/base/error.hpp"
#include "lem/run/fracture_summary.hpp"
#include "lem/base/log.hpp"
#include "lem/base/options.hpp"
#include "lem/base/phase.hpp"
#include "lem/protocol/checkpoint.hpp"
#include "lem/protocol/registry.hpp"
#include "lem/run/result_folder.hpp"
#include "lem/setup/setup.hpp"
#include "lem/setup/units.hpp"
#include "lem/base/stop.hpp"
#include "lem/fields/tension_output.hpp"
#include "lem/io/write_watch.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <stdexcept>

namespace lem {

namespace {

// The calibration ends within the step whose stress falls below this
// fraction of its peak: the homogeneous lattice fails in one avalanche, and
// its cycles after the first tenth of the drop cannot change sigma^[p].
constexpr double kCalibrationStopFraction = 0.9;

// A sample set up for fracture: thresholds of generated lattices, disorder.
struct Prepared {
  DistributedLattice lattice;
  SetupReport setup;
  double stress_unit = 1;  // sigma_raw * stress_unit = sigma in E^phase (or k/a) units (units.hpp)
};

struct Case {
  FractureResult result;
  SetupReport setup;
  double stress_unit = 1;
  double lattice_a = 0;  // a (DistributedLattice::mean_bond_length)
};

Prepared prepare(MPI_Comm comm, const SampleOptions& sample, double break_strain,
                 const FractureOptions& options) {
  Prepared p;
  p.lattice = setup_sample_lattice(comm, sample, p.setup);
  DistributedLattice& lattice = p.lattice;
  p.stress_unit = stress_unit(sample, lattice.mean_bond_length).per_lattice_stress;
  if (lattice.bond_strength.empty()) {  // generated lattice: f = k a eps_b
    lattice.bond_strength.resize(lattice.bond_stiffness.size());
    for (int b = 0; b < lattice.local_bonds(); ++b)
      lattice.bond_strength[b] =
          lattice.bond_stiffness[b] * lattice.mean_bond_length * break_strain;
  }
  apply_strength_disorder(lattice, options);
  return p;
}

// Run the protocol on a prepared sample, write the fields.
// (`output` without the stress unit, which is the sample's.)
Case run_case(Prepared p, const SolverOptions& solver, const FractureOptions& options,
              FractureOutput output, const Provenance& provenance, bool write_fields,
              bool registered_outputs) {
  Case c;
  c.setup = p.setup;
  c.lattice_a = p.lattice.mean_bond_length;
  c.stress_unit = output.stress_unit = p.stress_unit;
  DistributedLattice& lattice = p.lattice;
  say("lattice: %lld nodes, %lld bonds in the system, a = %.4g; output %s/\n",
      (long long)c.setup.sample.stats.nodes, (long long)c.setup.active_bonds,
      lattice.mean_bond_length, output.dir.c_str());
  ElasticSystem system(lattice, solver);
  check_unused_options(SolverStage::created);
  system.assemble();
  c.result = run_fracture(lattice, system, options, output, provenance);
  // What each lever spent, by stage (the single cycle: how much of it
  // goes to following K as it changes).
  for (const SolverLever* lever : system.levers())
    if (const std::string line = lever->work_line(); !line.empty()) say("%s\n", line.c_str());
  if (write_fields) {
    fault_pause(lattice.comm, "fields", "before the final fields");
    Summary s;
    s.add("steps", static_cast<long long>(c.result.steps));
    write_tension_fields(output.dir + "/fields", lattice, system, provenance, s);
  }
  if (registered_outputs)
    for (const FractureOutputEntry& e : fracture_outputs())
      e.write(lattice, c.result, output.dir + "/" + e.file);
  return c;
}

// A checkpoint that the protocol will resume from (rank 0 decides).
bool resumable(MPI_Comm comm, const FractureOptions& options, const std::string& dir) {
  bool found = false;
  run_on_root(comm,
              [&] { found = options.resume && std::filesystem::exists(checkpoint_path(dir)); });
  broadcast_value(comm, found);
  return found;
}

// What the result of this run depends on, recorded in its manifest
// (protocol/fingerprint.hpp): the sample by content, the protocol, and every
// option that changes what is computed or written.
std::string result_fingerprint(const DistributedLattice& lattice, const FractureOptions& o) {
  return fracture_fingerprint(lattice, o, FingerprintScope::result);
}

// The warnings a stored calibration carries, as if its run had just raised
// them: in the summary and the manifest, and an error under -fracture_strict.
void keep_stored_warnings(const Calibration& stored, const std::string& path, bool strict,
                          std::vector<RunWarning>& warnings) {
  if (stored.warnings.empty()) return;
  std::string words;
  for (const auto& w : stored.warnings) words += (words.empty() ? "" : ", ") + w;
  if (strict)
    throw NumericalError("the calibration in '" + path + "' was made by a run with warnings (" +
                         words +
                         "), an error under -fracture_strict; remove it to calibrate "
                         "again under -fracture_strict");
  say_warning("warning [calibration] %s carries the warnings of the run that made it: %s\n",
              path.c_str(), words.c_str());
  for (const auto& w : stored.warnings) {
    const std::size_t colon = w.rfind(':');
    warnings.push_back(
        {w.substr(0, colon), colon == std::string::npos ? 1 : std::atoll(w.c_str() + colon + 1)});
  }
}

// sigma^[p] and E^[p]: from the calibration file of this lattice if there is
// one, else by breaking the homogeneous lattice (and stored for next time);
// the warnings of a calibration run go to `warnings`.
Calibration calibrate(MPI_Comm comm, const SampleOptions& sample, const SolverOptions& solver,
                      double break_strain, const FractureOptions& options, const std::string& dir,
                      std::string path, const Provenance& provenance,
                      std::vector<RunWarning>& warnings) {
  SampleOptions hom = sample;
  hom.homogeneous = true;
  FractureOptions hom_options = options;
  FractureOutput hom_output;  // no fields, no snapshots
  hom_output.dir = dir + "/calibration";
  hom_output.strength_unit = sample.phases.strength[0];
  // Only the peak is needed: stop once the avalanche that follows it has
  // taken a tenth of the stress (docs/model/fracture-calibration.md).
  hom_options.stop_fraction = std::max(options.stop_fraction, kCalibrationStopFraction);
  hom_options.stop_within_step = true;
  // -fracture_max_steps bounds the sample run, not its calibration; the
  // run's checkpoints (-checkpoint_seconds, -checkpoint_steps) cover both: a
  // calibration of 10^7 bonds takes hours.
  hom_options.max_steps = FractureOptions{}.max_steps;
  Prepared p = prepare(comm, hom, break_strain, hom_options);
  const std::string fingerprint =
      fracture_fingerprint(p.lattice, hom_options, FingerprintScope::calibration);
  const bool chosen = !path.empty();
  if (!chosen)
    path = std::filesystem::path(sample.sample_file).replace_extension().string() +
           ".calibration-" + calibration_key(fingerprint) + ".txt";
  if (const auto stored = read_calibration(comm, path, fingerprint)) {
    say("calibration: sigma^[p] = %.6g, E^[p] = %.6g (E^phase units) from %s\n", stored->sigma_hom,
        stored->e_hom, path.c_str());
    keep_stored_warnings(*stored, path, options.strict, warnings);
    return *stored;
  }
  // A calibration that could not be stored where it was asked for is
  // refused before it runs, not after.
  if (chosen)
    run_on_root(comm, [&] {
      if (const std::string why = unwritable_file(path); !why.empty())
        throw InputError("option -fracture_calibration_file: '" + path + "' cannot be written (" +
                         why + "), so the calibration would be lost; choose a writable path");
    });
  // A calibration stopped by a signal resumes from its checkpoint, whose
  // logs may already carry their final names.
  prepare_output_dir(comm, hom_output.dir,
                     resumable(comm, hom_options, hom_output.dir)
                         ? std::vector<std::string>{}
                         : std::vector<std::string>{"curve.csv", "curve.json", "broken.csv"});
  say("calibration: the homogeneous lattice (every bond E^p = %g, sigma^p = %g)\n",
      sample.phases.modulus[0], sample.phases.strength[0]);
  Case hom_case;
  try {
    hom_case = run_case(std::move(p), solver, hom_options, hom_output, provenance, false, false);
  } catch (const Interrupted& e) {
    throw Interrupted(std::string("calibration ") + e.what());
  }
  warnings = hom_case.result.warnings;
  run_on_root(comm, [&] { remove_checkpoint(hom_output.dir); });
  // A calibration is the peak of the homogeneous lattice: bonds broke and
  // the stress fell after it.  Anything else is not sigma^[p] and is never
  // stored (a later run would reuse it).
  const FractureResult& r = hom_case.result;
  if (!r.past_peak()) {
    std::ostringstream why;
    why << "the calibration of sigma^[p] reached no peak: it ended at load step " << r.steps << " ("
        << r.end_reason << ") with " << r.broken_total() << " bonds broken and the "
        << "stress " << (r.final_stress < r.peak_stress ? "below" : "at") << " its largest value, "
        << r.peak_stress * hom_case.stress_unit << " E^phase; load steps of -fracture_increment "
        << "= " << options.increment << " a do not reach the strength of the homogeneous lattice "
        << "(-phase_sigma_p = " << sample.phases.strength[0] << ") within " << hom_options.max_steps
        << " steps: raise -fracture_increment (the paper's is "
        << "3e-4), or check -phase_sigma_p. Nothing was stored";
    throw InputError(why.str());
  }
  Calibration c;
  c.sigma_hom = hom_case.result.peak_stress * hom_case.stress_unit;
  c.e_hom = hom_case.result.young_modulus * hom_case.stress_unit;
  c.warnings = warning_words(warnings);
  say("calibration: sigma^[p] = %.6g, E^[p] = %.6g (E^phase units)\n", c.sigma_hom, c.e_hom);
  std::string stored = "stored in " + path;
  try {
    write_calibration(comm, path, fingerprint, c, provenance);
    say("calibration: stored in %s\n", path.c_str());
  } catch (const IoError& e) {
    if (chosen) throw;
    say("calibration: not stored (%s)\n", e.what());  // e.g. a read-only sample folder
    stored = "not stored (" + std::string(e.what()) + "), so the next run calibrates again";
  }
  // A request that came while the calibration ended: stop before the sample.
  if (const int signal = stop_requested(comm, "calibration_done"))
    throw Interrupted("stopped by " + signal_name(signal) +
                      " after the calibration: "
                      "sigma^[p] and E^[p] " +
                      stored +
                      "; run the same command again "
                      "to break the sample");
  return c;
}


// The units of the curve and the summary (paper sect. 3): given, else the
// calibration's sigma^[p] and E^[p], else the particle phase's own values
// (sample files) or 1 (generated lattices, k/a units).
void normalise(FractureOutput& o, const FractureRunOptions& run, const Calibration& c,
               const SampleOptions& sample) {
  const bool from_file = !sample.sample_file.empty();
  const double e_p = sample.phases.modulus[0], s_p = sample.phases.strength[0];
  o.strength_unit = run.sigma_unit > 0 ? run.sigma_unit
                    : c.sigma_hom > 0  ? c.sigma_hom
                    : from_file        ? s_p
                                       : 1.0;
  o.modulus_unit = run.modulus_unit > 0 ? run.modulus_unit
                   : c.e_hom > 0        ? c.e_hom
                   : from_file          ? e_p
                                        : 1.0;
}

// summary.json / summary.csv of a finished run.
Summary fracture_summary(MPI_Comm comm, const SampleOptions& sample, const FractureOptions& o,
                         const FractureOutput& units, const Calibration& calibration, const Case& c,
                         const std::vector<std::string>& warnings) {
  const FractureResult& r = c.result;
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  const FractureRecord record{sample,        o,           units,    calibration,       c.setup, r,
                              c.stress_unit, c.lattice_a, warnings, peak_memory(comm), ranks};
  const double e_eff = record.e_eff(), s_eff = record.sigma_eff();
  Summary s;
  s.add_from(fracture_summary_table(), record);
  say("end: %s at step %lld\n", r.end_reason.c_str(), (long long)r.steps);
  say("E_eff = %.6g (%.4f E_unit)   sigma_eff = %.6g (%.4f sigma_unit) at strain %.4e\n", e_eff,
      e_eff / units.modulus_unit, s_eff, s_eff / units.strength_unit, r.strain_at_peak);
  say("broken %lld bonds (n_b = %.4f), %lld solves (%lld iterations, %lld PC builds) over "
      "%lld steps; energy balance error %.2e; %.1f s\n",
      (long long)r.broken_total(), r.particle_damage(), (long long)r.solves,
      (long long)r.iterations, (long long)r.preconditioner_builds, (long long)r.steps,
      r.energy_balance_error, r.seconds);
  return s;
}

}  // namespace

FractureRunOptions read_fracture_run_options(MPI_Comm comm) {
  FractureRunOptions o;
  OptionGroup g(comm, "Fracture run and output");
  o.break_strain = g.real("-lattice_break_strain",
                          "Generated lattices: a bond breaks when "
                          "stretched by this fraction of the mean bond length (f = k a eps)",
                          1e-3, 0.0, 1.0, true);
  o.calibrate = g.flag("-fracture_calibrate",
                       "Sample files: first break the homogeneous "
                       "lattice of particle bonds to measure sigma^[p] and E^[p] (paper "
                       "sect. 3), written to <output_dir>/calibration/",
                       true);
  o.calibration_file = g.string("-fracture_calibration_file",
                                "Sample files: where sigma^[p] "
                                "and E^[p] are kept (read if it exists and belongs to this "
                                "lattice and these options; written after calibrating); "
                                "default: beside the sample file, named by a hash of both",
                                "");
  o.sigma_unit = g.real("-fracture_sigma_unit",
                        "Normalise stresses by this value instead "
                        "(E^phase units; e.g. sigma^[p] from an earlier calibration; 0: "
                        "calibrate or use sigma^p)",
                        0.0, 0.0, 1e12);
  o.modulus_unit = g.real("-fracture_modulus_unit",
                          "Normalise moduli by this value instead "
                          "(E^phase units; e.g. E^[p] from an earlier calibration; 0: "
                          "calibrate or use E^p)",
                          0.0, 0.0, 1e12);
  const ResultFolder::Request folder = ResultFolder::read_request(g, "results/fracture");
  o.output_dir = folder.dir;
  o.overwrite = folder.overwrite;
  o.fields = g.flag("-output_fields",
                    "Write the final displacements and bond states to "
                    "HDF5/XDMF (fields.h5), and those of the first equilibrium with the node "
                    "stresses of eq. 1 (elastic.h5)",
                    true);
  set_write_stop_grace(
      g.real("-output_write_grace",
             "Seconds a write that every rank waits for (fields, "
             "snapshots, a checkpoint, also the one that answers the request) may go on after a "
             "stop request (SIGTERM/SIGUSR1) before the job is ended without it (exit 4; the "
             "same command resumes from the last checkpoint on disk); a write that failed on "
             "some rank ends the job after 3 s (exit 3)",
             write_stop_grace(), 1.0, 86400.0));
  o.snapshot_steps = g.integer("-output_snapshot_steps",
                               "Also write them (as "
                               "snapshot_<step>.h5/.xmf) once in every this many "
                               "load steps (0: never)",
                               0, 0, 1'000'000'000);
  return o;
}

void run_fracture_job(MPI_Comm comm, const SampleOptions& sample, const FractureOptions& protocol,
                      const FractureRunOptions& run, const SolverOptions& solver,
                      const Provenance& provenance) {
  const FractureOptions& options = protocol;
  fracture_summary_table();  // a plug-in's field of a taken name: refused before any work
  const bool from_file = !sample.sample_file.empty();
  const bool calibrating =
      from_file && run.calibrate && run.sigma_unit == 0 && run.modulus_unit == 0;
  if (calibrating &&
      !run.calibration_file.empty())  // before a calibration that could not be stored
    run_on_root(comm, [&] {
      const auto folder = std::filesystem::path(run.calibration_file).parent_path();
      if (!folder.empty() && !std::filesystem::is_directory(folder))
        throw InputError("option -fracture_calibration_file: the folder of '" +
                         run.calibration_file + "' does not exist");
    });
  // The sample is read and checked before -output_dir is touched: bad input
  // must not cost an earlier result.
  Prepared prepared = prepare(comm, sample, run.break_strain, options);
  if (const int signal = stop_requested(comm, "sample_read"))
    throw Interrupted("stopped by " + signal_name(signal) +
                      " before anything was "
                      "written; run the same command again");
  ResultFolder::Request request;
  request.dir = run.output_dir;
  request.fingerprint = result_fingerprint(prepared.lattice, options);
  request.overwrite = run.overwrite;
  request.resume = options.resume;
  request.strict = options.strict;
  // Files of registered outputs are part of every finished result.
  ResultLayout layout = fracture_layout();
  for (const FractureOutputEntry& e : fracture_outputs()) layout.required.push_back(e.file);
  const ResultFolder folder(comm, layout, request);
  if (!folder.begin()) return;

  Calibration calibration;
  std::vector<RunWarning> calibration_warnings;
  if (calibrating)
    calibration = calibrate(comm, sample, solver, run.break_strain, options, folder.work_dir(),
                            run.calibration_file, provenance, calibration_warnings);
  // Where the run writes and its units: decided here, read-only below.
  FractureOutput output;
  output.dir = folder.work_dir();
  output.elastic_fields = run.fields;
  output.snapshot_steps = run.snapshot_steps;
  normalise(output, run, calibration, sample);
  const Case c =
      run_case(std::move(prepared), solver, options, output, provenance, run.fields, true);
  // Degradations (docs/model/fracture.md, "Warnings"): "code:count", the
  // calibration's prefixed; an empty list for a sound run.
  std::vector<std::string> warnings = warning_words(calibration_warnings, "calibration_");
  for (const auto& w : warning_words(c.result.warnings)) warnings.push_back(w);
  Summary summary = fracture_summary(comm, sample, options, output, calibration, c, warnings);
  summary.add_provenance(provenance);
  folder.commit(summary, warnings);
  folder.install();
}

namespace {
std::vector<FractureOutputEntry>& output_registry() {
  static std::vector<FractureOutputEntry> entries;
  return entries;
}
}  // namespace

void register_fracture_output(FractureOutputEntry entry) {
  if (entry.file.empty() || entry.file.find('/') != std::string::npos || !entry.write)
    throw std::invalid_argument("a registered output needs a file name without '/' and a writer");
  if (fracture_layout().owns(entry.file))
    throw std::invalid_argument("output '" + entry.file + "' is a file lem_fracture writes");
  for (const FractureOutputEntry& e : output_registry())
    if (e.file == entry.file)
      throw std::invalid_argument("output '" + entry.file + "' is registered twice");
  output_registry().push_back(std::move(entry));
}

const std::vector<FractureOutputEntry>& fracture_outputs() { return output_registry(); }

int fracture_program(int argc, char** argv, const char* help) {
  return run_driver(
      argc, argv, help,
      [](MPI_Comm comm) {
        const SampleOptions sample = read_sample_options(comm);
        const FractureOptions protocol = read_fracture_options(comm);
        const FractureRunOptions run = read_fracture_run_options(comm);
        register_solver_levers();
        const SolverOptions solver = read_solver_options(comm);
        check_option_names(comm);
        const auto provenance = collect_provenance(comm, "lem_fracture");
        run_fracture_job(comm, sample, protocol, run, solver, provenance);
      },
      StopHandling::save_and_exit);
}

}  // namespace lem
