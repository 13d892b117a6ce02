// Quasi-static tensile fracture (paper sect. 2.1, 2.3 and appendix A).
//
// The top face is raised by increments Delta; a bond whose tensile force
// exceeds its threshold breaks irreversibly (never in compression).  Under the
// paper's rule every critical bond breaks at once and the system is relaxed at
// the same load until none is critical; the other rule breaks only the most
// critical bond per relaxation cycle.  Ties are broken by the global bond id,
// so results do not depend on the number of ranks.
//
// Between two ruptures the system is linear: the solution at load step m is
// the last solution scaled by m/n.  The protocol therefore computes the first
// step at which some bond will exceed its threshold and jumps there without
// solving (-fracture_skip_idle); the curve and the broken-bond sequence are
// those of stepping through every increment.
//
// The protocol is put together from parts with one job each (lem/protocol/):
//   options.hpp               the options, read once
//   disorder.hpp              seeded threshold factors
//   break_rule.hpp            which bonds are critical, when the next one will be
//   damage_ledger.hpp         numbered batches of ruptures and pinnings: apply, record, replay
//   preconditioner_policy.hpp when the kept preconditioner is rebuilt; every solve counted
//   relaxation.hpp            break-pin-solve cycles at a fixed load
//   checkpoint.hpp            checkpoint file, fingerprint, stop signals
//   recorder.hpp              curve.csv, broken.csv, snapshots, elastic fields
//   progress.hpp              progress lines and the time-left estimate
//   warnings.hpp              degraded results: said, recorded, errors under -fracture_strict
// and run_fracture() (src/protocol/fracture.cpp) strings them together.
#pragma once

#include "lem/system/distributed_lattice.hpp"
#include "lem/system/elastic_system.hpp"
#include "lem/protocol/disorder.hpp"
#include "lem/protocol/options.hpp"
#include "lem/protocol/state.hpp"
#include "lem/protocol/warnings.hpp"
#include "lem/io/hdf5_writer.hpp"

#include <string>
#include <utility>
#include <vector>

namespace lem {

struct FractureResult : FractureTally {
  double final_stress = 0, final_strain = 0;
  double stored_energy = 0;         // E: the bonds'
  double ground_energy = 0;         // G: the ground springs' (-lattice_ground_stiffness)
  double energy_balance_error = 0;  // |W - E - G - R| / W
  double peak_step = 0;             // load step of the peak stress (strain / step strain)
  std::string end_reason;
  double seconds = 0;
  bool resumed = false;
  std::vector<RunWarning> warnings;  // degradations seen (docs/model/fracture.md, "Warnings")
  /// The values of the summary fields of the break rule and the relaxation
  /// scheme (BreakRule::report, Relaxation::report), by name.
  std::vector<std::pair<std::string, double>> plugin_report;
  /// The value of `name` in plugin_report, 0 when neither has one.
  double plugin_value(const std::string& name) const;
  /// Bonds broke and the stress fell after its peak: the peak is the
  /// lattice's strength, not the last load reached.
  bool past_peak() const { return broken_total() > 0 && final_stress < peak_stress; }
};

/// Runs the protocol on an assembled system.  Writes <output.dir>/curve.csv,
/// broken.csv (complete only at the end: *.part while running), snapshots
/// and checkpoint.bin (which records a hash of the sample and the options
/// that change the results, so that a resume with others is refused).  The
/// checkpoint stays when the run completes: the caller removes it
/// (remove_checkpoint) once it has committed the results, so that a kill
/// before the commit resumes instead of starting over.  Checks the options
/// database for unused options after the first solve, when PETSc has read
/// its own (a misspelt option stops the run there).
FractureResult run_fracture(DistributedLattice& lattice, ElasticSystem& system,
                            const FractureOptions& options, const FractureOutput& output,
                            const Provenance& provenance);

}  // namespace lem
