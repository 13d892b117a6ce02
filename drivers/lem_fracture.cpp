// Quasi-static tensile test to complete failure (paper sect. 2.3, 3, 6):
// stress-strain curve, E_eff, sigma_eff, broken bonds by phase, fields.
//
//   mpirun -n 2 lem_fracture -sample_file meshes/demo.h5 -output_dir results/fracture
//   mpirun -n 2 lem_fracture -lattice_bonds 200000 -lattice_break_strain 1e-3
#include "lem/calibration.hpp"
#include "lem/driver.hpp"
#include "lem/error.hpp"
#include "lem/files.hpp"
#include "lem/fracture.hpp"
#include "lem/protocol/checkpoint.hpp"
#include "lem/options.hpp"
#include "lem/phase.hpp"
#include "lem/setup.hpp"
#include "lem/stop.hpp"
#include "lem/tension_output.hpp"
#include "lem/write_watch.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>

static const char help[] =
    "Quasi-static uniaxial tension to complete failure of an elastic-brittle spring lattice\n"
    "(Affes et al., EPJE 35, 2012).  The sample is a cemented sample file (-sample_file,\n"
    "phases -phase_*) or a generated lattice (-lattice_*, thresholds -lattice_break_strain).\n"
    "Stresses are normalised by sigma^[p], the strength of the homogeneous lattice of the\n"
    "same geometry made of particle bonds, calibrated first (-fracture_calibrate).\n";

namespace {

// The calibration ends within the step whose stress falls below this
// fraction of its peak: the homogeneous lattice fails in one avalanche, and
// its cycles after the first tenth of the drop cannot change sigma^[p].
constexpr double kCalibrationStopFraction = 0.9;

// A sample set up for fracture: thresholds of generated lattices, disorder.
struct Prepared {
  lem::DistributedLattice lattice;
  lem::SetupReport setup;
  double stress_unit = 1;  // sigma_raw * stress_unit = sigma in E^phase (or k/a) units
};

struct Case {
  lem::FractureResult result;
  lem::SetupReport setup;
  double stress_unit = 1;
};

Prepared prepare(MPI_Comm comm, const lem::SampleOptions& sample, double break_strain,
                 const lem::FractureOptions& options) {
  Prepared p;
  p.lattice = lem::setup_sample_lattice(comm, sample, p.setup);
  lem::DistributedLattice& lattice = p.lattice;
  // Stress unit: a sample file's bonds have k = E^phase a_s and f =
  // sigma^phase a_s^2, so its stresses are already in E^phase units; a
  // generated lattice's are given in units of k/a (k = -lattice_k).
  const bool from_file = !sample.sample_file.empty();
  p.stress_unit = from_file ? 1.0 : lattice.mean_bond_length / sample.random.stiffness;
  if (lattice.bond_strength.empty()) {  // generated lattice: f = k a eps_b
    lattice.bond_strength.resize(lattice.bond_stiffness.size());
    for (int b = 0; b < lattice.local_bonds(); ++b)
      lattice.bond_strength[b] =
          lattice.bond_stiffness[b] * lattice.mean_bond_length * break_strain;
  }
  lem::apply_strength_disorder(lattice, options);
  return p;
}

// Run the protocol on a prepared sample, write the fields.
Case run_case(Prepared p, const lem::SolverOptions& solver, lem::FractureOptions options,
              const lem::Provenance& provenance, bool write_fields) {
  Case c;
  c.setup = p.setup;
  c.stress_unit = options.stress_unit = p.stress_unit;
  lem::DistributedLattice& lattice = p.lattice;
  lem::say("lattice: %lld nodes, %lld bonds in the system, a = %.4g; output %s/\n",
           (long long)c.setup.sample.stats.nodes, (long long)c.setup.active_bonds,
           lattice.mean_bond_length, options.output_dir.c_str());
  lem::ElasticSystem system(lattice, solver);
  lem::check_unused_options(lem::SolverStage::created);
  system.assemble();
  c.result = lem::run_fracture(lattice, system, options, provenance);
  if (write_fields) {
    lem::fault_pause(lattice.comm, "fields", "before the final fields");
    lem::Summary s;
    s.add("steps", static_cast<long long>(c.result.steps));
    lem::write_tension_fields(options.output_dir + "/fields", lattice, system, provenance, s);
  }
  return c;
}

// A checkpoint that the protocol will resume from (rank 0 decides).
bool resumable(MPI_Comm comm, const lem::FractureOptions& options) {
  int found = 0;
  lem::run_on_root(comm, [&] {
    found = options.resume && std::filesystem::exists(lem::checkpoint_path(options.output_dir));
  });
  MPI_Bcast(&found, 1, MPI_INT, 0, comm);
  return found != 0;
}

// What the result of this run depends on, recorded in its manifest: the
// checkpoint's fingerprint (sample, thresholds, protocol options), where the
// run ends, and how it is normalised and written.
std::string result_fingerprint(const lem::DistributedLattice& lattice,
                               const lem::FractureOptions& o, bool calibrating, double sigma_unit,
                               double modulus_unit, bool fields) {
  std::ostringstream s;
  s.precision(17);
  s << lem::fracture_fingerprint(lattice, o) << "stop_fraction=" << o.stop_fraction
    << "\nmax_strain_ratio=" << o.max_strain_ratio << "\nmax_steps=" << o.max_steps
    << "\ncalibrate=" << calibrating << "\nsigma_unit=" << sigma_unit
    << "\nmodulus_unit=" << modulus_unit << "\nfields=" << fields
    << "\nsnapshot_steps=" << o.snapshot_steps << "\n";
  return s.str();
}

// Rank 0: why the finished result `m` is not that of this run ("" if it is;
// the rank count may differ).
std::string other_run(const lem::Manifest& m, const std::string& fingerprint) {
  if (m.program != "lem_fracture") return "\n  written by " + m.program;
  int other_ranks = 0;
  return lem::fingerprint_differences(m.fingerprint, fingerprint, other_ranks, "finished");
}

// Rank 0 of a locked output directory: true if it holds the finished result
// of this very run (then there is nothing to do); InputError if it holds
// another one and -output_overwrite was not given.
bool already_finished(const std::string& dir, const std::string& fingerprint, bool overwrite) {
  if (overwrite) return false;  // a damaged manifest too
  const auto manifest = lem::read_manifest(dir);
  if (!manifest) return false;
  const std::string differs = other_run(*manifest, fingerprint);
  if (!differs.empty())
    throw lem::InputError("output directory '" + dir + "' holds the finished result of "
                          "another run:" + differs + "\npass -output_overwrite to replace it, "
                          "or choose another -output_dir");
  const std::string changed = lem::manifest_mismatch(dir, *manifest);
  if (!changed.empty())
    throw lem::InputError("output directory '" + dir + "' holds a finished result changed "
                          "since it was written:" + changed + "\npass -output_overwrite to "
                          "compute it again");
  return true;
}

// The warnings listed in the summary of a finished result ("" for none, or
// for a summary written before warnings were recorded).
std::string finished_warnings(const std::string& dir) {
  std::ifstream in(dir + "/summary.json");
  const std::string key = "\"warnings\": [";
  for (std::string line; std::getline(in, line);) {
    const auto at = line.find(key);
    if (at == std::string::npos) continue;
    const auto from = at + key.size(), to = line.find(']', from);
    std::string list = line.substr(from, to == std::string::npos ? to : to - from);
    list.erase(std::remove(list.begin(), list.end(), '"'), list.end());
    return list;
  }
  return {};
}

// Rank 0: the warning options are not part of the fingerprint, so a result
// finished with warnings is refused here under -fracture_strict.
void refuse_if_strict(const std::string& dir, const lem::FractureOptions& options) {
  if (options.strict && !finished_warnings(dir).empty())
    throw lem::NumericalError("output directory '" + dir + "' holds a finished result with "
                              "warnings (" + finished_warnings(dir) + "), an error under "
                              "-fracture_strict; pass -output_overwrite to compute it again");
}

// The entries lem_fracture writes in its output folder, or the tools draw
// from its result (tools/plot_fracture.py, plot_stress.py).  The others
// belong to whoever put them there (a study's run.json and log) and stay
// when -output_overwrite replaces the result.
bool part_of_result(const std::string& name) {
  static const std::set<std::string> names = {"curve.csv",      "curve.json",  "broken.csv",  "summary.csv",
                                              "summary.json",   "calibration", "checkpoint.bin",
                                              "fracture.png",   "stress.png",  "stress.json"};
  const std::string ext = std::filesystem::path(name).extension().string();
  return names.count(name) > 0 || ext == ".part" || ext == ".tmp" ||
         name.rfind("fields", 0) == 0 || name.rfind("elastic", 0) == 0 ||
         name.rfind("snapshot", 0) == 0;
}

// Whether the staging folder of -output_overwrite (<dir>.overwrite) is one
// of ours (rank 0 decides).
bool staging_is_ours(MPI_Comm comm, const std::string& dir) {
  int ours = 0;
  lem::run_on_root(comm, [&] { ours = lem::staging_state(dir) == lem::StagingState::ours; });
  MPI_Bcast(&ours, 1, MPI_INT, 0, comm);
  return ours != 0;
}

// Rank 0, -output_overwrite: what the staging folder of `dir` holds for this
// run.  True if it is this run's complete result, to be put in place (a run
// stopped while doing so); false if the run is to be computed there: resumed
// from its checkpoint, or started over once the folder is emptied.
bool staged_result(const std::string& dir, const std::string& fingerprint,
                   const lem::FractureOptions& options) {
  const std::string staging = lem::staging_dir(dir);
  if (!options.resume) {
    if (lem::clear_staging(dir))
      lem::say("-output_overwrite: %s/ emptied (-checkpoint_resume false)\n", staging.c_str());
    return false;
  }
  if (const auto manifest = lem::read_manifest(staging)) {
    const std::string differs =
        other_run(*manifest, fingerprint) + lem::manifest_mismatch(staging, *manifest);
    if (!differs.empty())
      throw lem::InputError("'" + staging + "' holds the finished result of another "
                            "-output_overwrite run of '" + dir + "', not yet in place:" +
                            differs + "\nrun that command again to put it in place, or pass "
                            "-checkpoint_resume false to discard it");
    refuse_if_strict(staging, options);
    lem::remove_checkpoint(staging);
    lem::say("-output_overwrite: %s/ holds the complete result of this run, not yet in place "
             "(the run was stopped while it put it there): putting it in place\n",
             staging.c_str());
    return true;
  }
  namespace fs = std::filesystem;
  if (fs::exists(lem::checkpoint_path(staging)) ||
      fs::exists(lem::checkpoint_path(staging + "/calibration"))) {
    lem::say("-output_overwrite: resuming the run stopped in %s/\n", staging.c_str());
    return false;
  }
  if (lem::clear_staging(dir))
    lem::say("-output_overwrite: %s/ held a run stopped before its first checkpoint: "
             "starting over\n", staging.c_str());
  return false;
}

// sigma^[p] and E^[p]: from the calibration file of this lattice if there is
// one, else by breaking the homogeneous lattice (and stored for next time);
// the warnings of a calibration run go to `warnings`.
lem::Calibration calibrate(MPI_Comm comm, const lem::SampleOptions& sample,
                           const lem::SolverOptions& solver, double break_strain,
                           const lem::FractureOptions& options, std::string path,
                           const lem::Provenance& provenance,
                           std::vector<lem::RunWarning>& warnings) {
  lem::SampleOptions hom = sample;
  hom.homogeneous = true;
  lem::FractureOptions hom_options = options;
  hom_options.output_dir = options.output_dir + "/calibration";
  hom_options.strength_unit = sample.phases.strength[0];
  // Only the peak is needed: stop once the avalanche that follows it has
  // taken a tenth of the stress (docs/model/fracture.md, "Normalisation and the calibration").
  hom_options.stop_fraction = std::max(options.stop_fraction, kCalibrationStopFraction);
  hom_options.stop_within_step = true;
  // -fracture_max_steps bounds the sample run, not its calibration.
  hom_options.max_steps = lem::FractureOptions{}.max_steps;
  hom_options.checkpoint_seconds = 0;
  hom_options.snapshot_steps = 0;
  hom_options.elastic_fields = false;
  Prepared p = prepare(comm, hom, break_strain, hom_options);
  const std::string fingerprint = lem::fracture_fingerprint(p.lattice, hom_options);
  const bool chosen = !path.empty();
  if (!chosen)
    path = std::filesystem::path(sample.sample_file).replace_extension().string() +
           ".calibration-" + lem::calibration_key(fingerprint) + ".txt";
  if (const auto stored = lem::read_calibration(comm, path, fingerprint)) {
    lem::say("calibration: sigma^[p] = %.6g, E^[p] = %.6g (E^phase units) from %s\n",
             stored->sigma_hom, stored->e_hom, path.c_str());
    return *stored;
  }
  // A calibration stopped by a signal resumes from its checkpoint, whose
  // logs may already carry their final names.
  lem::prepare_output_dir(comm, hom_options.output_dir,
                          resumable(comm, hom_options) ? std::vector<std::string>{}
                                                       : std::vector<std::string>{"curve.csv",
                                                                                  "curve.json",
                                                                                  "broken.csv"});
  lem::say("calibration: the homogeneous lattice (every bond E^p = %g, sigma^p = %g)\n",
           sample.phases.modulus[0], sample.phases.strength[0]);
  Case hom_case;
  try {
    hom_case = run_case(std::move(p), solver, hom_options, provenance, false);
  } catch (const lem::Interrupted& e) {
    throw lem::Interrupted(std::string("calibration ") + e.what());
  }
  warnings = hom_case.result.warnings;
  lem::run_on_root(comm, [&] { lem::remove_checkpoint(hom_options.output_dir); });
  // A calibration is the peak of the homogeneous lattice: bonds broke and
  // the stress fell after it.  Anything else is not sigma^[p] and is never
  // stored (a later run would reuse it).
  const lem::FractureResult& r = hom_case.result;
  if (!r.past_peak()) {
    std::ostringstream why;
    why << "the calibration of sigma^[p] reached no peak: it ended at load step " << r.steps
        << " (" << r.end_reason << ") with " << r.broken_total() << " bonds broken and the "
        << "stress " << (r.final_stress < r.peak_stress ? "below" : "at") << " its largest value, "
        << r.peak_stress * hom_case.stress_unit << " E^phase; load steps of -fracture_increment "
        << "= " << options.increment << " a do not reach the strength of the homogeneous lattice "
        << "(-phase_sigma_p = " << sample.phases.strength[0] << ") within "
        << hom_options.max_steps << " steps: raise -fracture_increment (the paper's is "
        << "3e-4), or check -phase_sigma_p. Nothing was stored";
    throw lem::InputError(why.str());
  }
  lem::Calibration c;
  c.sigma_hom = hom_case.result.peak_stress * hom_case.stress_unit;
  c.e_hom = hom_case.result.young_modulus * hom_case.stress_unit;
  lem::say("calibration: sigma^[p] = %.6g, E^[p] = %.6g (E^phase units)\n", c.sigma_hom,
           c.e_hom);
  std::string stored = "stored in " + path;
  try {
    lem::write_calibration(comm, path, fingerprint, c, provenance);
    lem::say("calibration: stored in %s\n", path.c_str());
  } catch (const lem::IoError& e) {
    if (chosen) throw;
    lem::say("calibration: not stored (%s)\n", e.what());  // e.g. a read-only sample folder
    stored = "not stored (" + std::string(e.what()) + "), so the next run calibrates again";
  }
  // A request that came while the calibration ended: stop before the sample.
  if (const int signal = lem::stop_requested(comm, "calibration_done"))
    throw lem::Interrupted("stopped by " + lem::signal_name(signal) + " after the calibration: "
                           "sigma^[p] and E^[p] " + stored + "; run the same command again "
                           "to break the sample");
  return c;
}

}  // namespace

int main(int argc, char** argv) {
  return lem::run_driver(argc, argv, help, [](MPI_Comm comm) {
    lem::SampleOptions sample = lem::read_sample_options(comm);
    lem::FractureOptions options = lem::read_fracture_options(comm);
    double break_strain = 1e-3, sigma_unit = 0, modulus_unit = 0;
    bool calibrate_first = true, fields = true, overwrite = false;
    std::string calibration_file;
    {
      lem::OptionGroup g(comm, "Fracture run and output");
      break_strain = g.real("-lattice_break_strain", "Generated lattices: a bond breaks when "
                            "stretched by this fraction of the mean bond length (f = k a eps)",
                            1e-3, 0.0, 1.0, true);
      calibrate_first = g.flag("-fracture_calibrate", "Sample files: first break the homogeneous "
                         "lattice of particle bonds to measure sigma^[p] and E^[p] (paper "
                         "sect. 3), written to <output_dir>/calibration/", true);
      calibration_file = g.string("-fracture_calibration_file", "Sample files: where sigma^[p] "
                                  "and E^[p] are kept (read if it exists and belongs to this "
                                  "lattice and these options; written after calibrating); "
                                  "default: beside the sample file, named by a hash of both",
                                  "");
      sigma_unit = g.real("-fracture_sigma_unit", "Normalise stresses by this value instead "
                          "(E^phase units; e.g. sigma^[p] from an earlier calibration; 0: "
                          "calibrate or use sigma^p)", 0.0, 0.0, 1e12);
      modulus_unit = g.real("-fracture_modulus_unit", "Normalise moduli by this value instead "
                            "(E^phase units; e.g. E^[p] from an earlier calibration; 0: "
                            "calibrate or use E^p)", 0.0, 0.0, 1e12);
      options.output_dir = g.string("-output_dir", "Directory of the results", "results/fracture");
      overwrite = g.flag("-output_overwrite", "Compute the result again even if -output_dir "
                         "holds a finished one (its manifest.txt), in <output_dir>.overwrite/: "
                         "it replaces the old one only when complete; without it a finished "
                         "run of the same sample and options is left as it is (exit 0)", false);
      fields = g.flag("-output_fields", "Write the final displacements and bond states to "
                      "HDF5/XDMF (fields.h5), and those of the first equilibrium with the node "
                      "stresses of eq. 1 (elastic.h5)", true);
      options.elastic_fields = fields;
      lem::set_write_stop_grace(g.real(
          "-output_write_grace", "Seconds a write that every rank waits for (fields, "
          "snapshots, a checkpoint, also the one that answers the request) may go on after a "
          "stop request (SIGTERM/SIGUSR1) before the job is ended without it (exit 4; the "
          "same command resumes from the last checkpoint on disk); a write that failed on "
          "some rank ends the job after 3 s (exit 3)", lem::write_stop_grace(), 1.0, 86400.0));
      options.snapshot_steps = g.integer("-output_snapshot_steps", "Also write them (as "
                                         "snapshot_<step>.h5/.xmf) once in every this many "
                                         "load steps (0: never)", 0, 0, 1'000'000'000);
    }
    const lem::SolverOptions solver = lem::read_solver_options(comm);
    lem::check_option_names(comm);
    const bool from_file = !sample.sample_file.empty();
    const bool calibrating = from_file && calibrate_first && sigma_unit == 0 && modulus_unit == 0;
    const auto provenance = lem::collect_provenance(comm, "lem_fracture");
    if (calibrating && !calibration_file.empty())  // before a calibration that could not be stored
      lem::run_on_root(comm, [&] {
        const auto folder = std::filesystem::path(calibration_file).parent_path();
        if (!folder.empty() && !std::filesystem::is_directory(folder))
          throw lem::InputError("option -fracture_calibration_file: the folder of '" +
                                calibration_file + "' does not exist");
      });
    // The sample is read and checked before -output_dir is touched: bad input
    // must not cost an earlier result.
    Prepared prepared = prepare(comm, sample, break_strain, options);
    if (const int signal = lem::stop_requested(comm, "sample_read"))
      throw lem::Interrupted("stopped by " + lem::signal_name(signal) + " before anything was "
                             "written; run the same command again");
    const std::string fingerprint = result_fingerprint(prepared.lattice, options, calibrating,
                                                       sigma_unit, modulus_unit, fields);

    const std::string dir = options.output_dir;
    const lem::OutputLock lock(comm, dir);
    // A replacement of the result stopped halfway is finished first (the
    // new result put in place, or the replaced one removed).
    std::optional<lem::OutputLock> staging_lock;
    if (staging_is_ours(comm, dir)) staging_lock.emplace(comm, lem::staging_dir(dir));
    lem::run_on_root(comm, [&] {
      const std::string done = lem::finish_replacement(dir, part_of_result);
      if (!done.empty()) lem::say("%s/: %s\n", dir.c_str(), done.c_str());
    });
    // Still there: an -output_overwrite run that did not end.
    const bool staged = staging_is_ours(comm, dir);
    if (staged && !overwrite)
      lem::say("note: %s/ holds an -output_overwrite run of %s/ that did not end, left as it "
               "is: run with -output_overwrite to finish it, or remove %s/\n",
               lem::staging_dir(dir).c_str(), dir.c_str(), lem::staging_dir(dir).c_str());
    int finished = 0;
    lem::run_on_root(comm, [&] {
      finished = already_finished(dir, fingerprint, overwrite);
      if (finished) refuse_if_strict(dir, options);
      // A run killed between its commit and the checkpoint's removal.
      if (finished) lem::remove_checkpoint(dir);
    });
    MPI_Bcast(&finished, 1, MPI_INT, 0, comm);
    if (finished) {
      lem::say("the result in %s/ is complete (manifest.txt): nothing to do; pass "
               "-output_overwrite to compute it again\n", dir.c_str());
      return;
    }
    // -output_overwrite on a finished result: the new one is computed in the
    // staging folder and takes the old one's place only when complete.
    int staging = 0, exchange = 0, pending = 0;
    lem::run_on_root(comm, [&] { staging = overwrite && (staged || lem::has_manifest(dir)); });
    MPI_Bcast(&staging, 1, MPI_INT, 0, comm);
    if (!staging) {
      staging_lock.reset();  // held only to finish or report what it holds
    } else {
      lem::run_on_root(comm, [&] {
        lem::check_replaceable(dir);
        if (lem::staging_state(dir) == lem::StagingState::foreign)
          throw lem::InputError("-output_overwrite computes the new result of '" + dir + "' in '" +
                                lem::staging_dir(dir) + "', which holds something else: move "
                                "or remove it");
      });
      if (!staged) {  // made (again)
        staging_lock.reset();
        staging_lock.emplace(comm, lem::staging_dir(dir));
      }
      lem::run_on_root(comm, [&] {
        exchange = lem::prepare_staging(dir);
        pending = staged_result(dir, fingerprint, options);
      });
      MPI_Bcast(&exchange, 1, MPI_INT, 0, comm);
      MPI_Bcast(&pending, 1, MPI_INT, 0, comm);
      options.output_dir = lem::staging_dir(dir);
      if (!pending)
        lem::say("-output_overwrite: the new result is computed in %s/; the one in %s/ stays "
                 "until it is complete\n", options.output_dir.c_str(), dir.c_str());
      if (!exchange)
        lem::say("-output_overwrite: this filesystem cannot swap two folders in one rename: "
                 "the new result will take the old one's place by two, between which %s/ "
                 "does not exist\n", dir.c_str());
    }
    // The result in place (a staged one put there), and a stop request
    // that came while it was written.
    const auto finish = [&] {
      if (staging)
        lem::run_on_root(comm, [&] { lem::install_result(dir, exchange, part_of_result); });
      lem::say("results in %s/\n", dir.c_str());
      if (const int signal = lem::stop_requested(comm, "committed"))
        throw lem::Interrupted("stopped by " + lem::signal_name(signal) + " while the results "
                               "were written; they are complete in " + dir + "/ (manifest.txt), "
                               "so running the same command again does nothing");
    };
    if (pending) return finish();
    // Withdraw what an earlier run left (manifest first).  A run that will
    // resume keeps its logs (maybe already renamed by a run killed while
    // committing) and the first-equilibrium fields written before its
    // checkpoint.
    const std::string work = options.output_dir;  // dir, or its staging folder
    std::vector<std::string> stale = {"summary.json", "summary.csv", "fields.h5", "fields.xmf",
                                      "fracture.png", "stress.png", "stress.json"};
    if (!resumable(comm, options))
      stale.insert(stale.end(), {"curve.csv", "curve.json", "broken.csv", "elastic.h5", "elastic.xmf"});
    lem::run_on_root(comm, [&] { lem::withdraw_results(work, stale); });

    const double e_p = sample.phases.modulus[0], s_p = sample.phases.strength[0];
    double sigma_hom = 0, e_hom = 0;
    std::vector<lem::RunWarning> calibration_warnings;
    if (calibrating) {
      const lem::Calibration c = calibrate(comm, sample, solver, break_strain, options,
                                           calibration_file, provenance, calibration_warnings);
      sigma_hom = c.sigma_hom;
      e_hom = c.e_hom;
    }
    options.strength_unit = sigma_unit > 0 ? sigma_unit : sigma_hom > 0 ? sigma_hom
                                                      : from_file ? s_p : 1.0;
    options.modulus_unit = modulus_unit > 0 ? modulus_unit : e_hom > 0 ? e_hom
                                                      : from_file ? e_p : 1.0;
    const Case c = run_case(std::move(prepared), solver, options, provenance, fields);

    const lem::FractureResult& r = c.result;
    const double e_eff = r.young_modulus * c.stress_unit, s_eff = r.peak_stress * c.stress_unit;
    lem::Summary s;
    s.add("sample_file", sample.sample_file);
    s.add("nodes", static_cast<long long>(c.setup.sample.stats.nodes));
    s.add("active_bonds", static_cast<long long>(c.setup.active_bonds));
    s.add("increment_over_a", options.increment);
    s.add("break_rule", std::string(lem::name_of(options.break_rule)));
    s.add("sigma_unit", options.strength_unit, "stress");
    s.add("E_unit", options.modulus_unit, "stress");
    s.add("sigma_hom", sigma_hom, "stress");
    s.add("E_hom", e_hom, "stress");
    s.add("E_eff", e_eff, "stress");
    s.add("E_eff_over_E_unit", e_eff / options.modulus_unit);
    s.add("sigma_eff", s_eff, "stress");
    s.add("sigma_eff_over_sigma_unit", s_eff / options.strength_unit);
    s.add("strain_at_peak", r.strain_at_peak);
    s.add("peak_step", static_cast<long long>(std::llround(r.peak_step)));
    s.add("final_strain", r.final_strain);
    s.add("final_stress_over_sigma_unit", r.final_stress * c.stress_unit / options.strength_unit);
    s.add("broken", static_cast<long long>(r.broken_total()));
    for (int k = 0; k < lem::kPhaseCount; ++k)
      if (static_cast<lem::Phase>(k) != lem::Phase::v)
        s.add(std::string("broken_") + lem::kPhaseNames[k], static_cast<long long>(r.broken[k]));
    s.add("n_b", r.particle_damage());
    s.add("detached_bonds", static_cast<long long>(r.detached_bonds));
    s.add("pinned_nodes", static_cast<long long>(r.pinned_nodes));
    s.add("steps", static_cast<long long>(r.steps));
    s.add("visited_steps", static_cast<long long>(r.visited_steps));
    s.add("rupture_steps", static_cast<long long>(r.rupture_steps));
    s.add("relaxation_cycles", static_cast<long long>(r.relaxation_cycles));
    s.add("solves", static_cast<long long>(r.solves));
    s.add("early_stops", static_cast<long long>(r.early_stops));
    s.add("decided_steps", static_cast<long long>(r.decided_steps));
    s.add("tie_solves", static_cast<long long>(r.tie_solves));
    s.add("ksp_iterations", static_cast<long long>(r.iterations));
    s.add("pc_builds", static_cast<long long>(r.preconditioner_builds));
    s.add("fallback_solves", static_cast<long long>(r.fallback_solves));
    s.add("relaxation", std::string(lem::name_of(options.relaxation)));
    s.add("patch_solves", static_cast<long long>(r.patch_solves));
    s.add("patch_iterations", static_cast<long long>(r.patch_iterations));
    s.add("patch_nodes_mean", r.patch_solves > 0 ? static_cast<double>(r.patch_nodes) /
                                                       static_cast<double>(r.patch_solves)
                                                 : 0.0);
    s.add("patch_overflows", static_cast<long long>(r.patch_overflows));
    s.add("patch_error_max", r.patch_error_max);
    s.add("patch_disabled_step", static_cast<long long>(r.patch_disabled_step));
    // A plain run solves at every step plus every relaxation cycle.
    s.add("solves_stepping_estimate", static_cast<long long>(r.steps + r.relaxation_cycles));
    s.add("work", r.work, "lattice");
    s.add("stored_energy", r.stored_energy, "lattice");
    s.add("released_energy", r.released_energy, "lattice");
    s.add("energy_balance_error", r.energy_balance_error);
    s.add("end_reason", r.end_reason);
    // Degradations (docs/model/fracture.md, "Warnings"): "code:count", the
    // calibration's prefixed; an empty list for a sound run.
    std::vector<std::string> warnings = lem::warning_words(calibration_warnings, "calibration_");
    for (const auto& w : lem::warning_words(r.warnings)) warnings.push_back(w);
    s.add("warnings", warnings);
    s.add("resumed", static_cast<long long>(r.resumed));
    s.add("seconds", r.seconds, "s");
    // Of this process: a resumed run reports its own part.
    const lem::PeakMemory memory = lem::peak_memory(comm);
    s.add("peak_memory_mb", memory.max_mb, "MB");
    s.add("peak_memory_mean_mb", memory.mean_mb, "MB");
    int ranks = 1;
    MPI_Comm_size(comm, &ranks);
    s.add("mpi_ranks", static_cast<long long>(ranks));
    lem::say("end: %s at step %lld\n", r.end_reason.c_str(), (long long)r.steps);
    lem::say("E_eff = %.6g (%.4f E_unit)   sigma_eff = %.6g (%.4f sigma_unit) at strain %.4e\n",
             e_eff, e_eff / options.modulus_unit, s_eff, s_eff / options.strength_unit,
             r.strain_at_peak);
    lem::say("broken %lld bonds (n_b = %.4f), %lld solves (%lld iterations, %lld PC builds) over "
             "%lld steps; energy balance error %.2e; %.1f s\n",
             (long long)r.broken_total(), r.particle_damage(), (long long)r.solves,
             (long long)r.iterations, (long long)r.preconditioner_builds, (long long)r.steps,
             r.energy_balance_error, r.seconds);
    // Commit: every file in place and synced, then the manifest, then the
    // checkpoint goes (docs/reference/outputs.md, "manifest.txt and the commit"); then a staged result
    // takes the old one's place.
    s.add_provenance(provenance);
    lem::run_on_root(comm, [&] {
      s.write(work + "/summary");
      std::vector<std::string> files = {"curve.csv", "broken.csv", "summary.csv",
                                        "summary.json"};
      for (const auto& entry : std::filesystem::directory_iterator(work)) {
        const std::string name = entry.path().filename().string();
        const std::string ext = entry.path().extension().string();
        // (curve.json is missing only in a run resumed from an older version's checkpoint.)
        if (((name.rfind("snapshot", 0) == 0 || name.rfind("elastic", 0) == 0 ||
              name.rfind("fields", 0) == 0) &&
             (ext == ".h5" || ext == ".xmf")) ||
            name == "curve.json")
          files.push_back(name);
      }
      std::sort(files.begin() + 4, files.end());
      lem::fault_point("before_manifest");
      lem::commit_results(work, "lem_fracture", fingerprint, files);
      lem::fault_point("after_manifest");
      lem::remove_checkpoint(work);
    });
    finish();
  }, lem::StopHandling::save_and_exit);
}
