// Fracture options, read once per run into plain values.
#pragma once

#include "lem/base/phase.hpp"

#include <mpi.h>

#include <array>
#include <cstdint>
#include <string>

namespace lem {

/// Random factor on the breaking thresholds.
enum class ThresholdDisorder { none, uniform, weibull };

struct FractureOptions {
  double increment = 3e-4;  // top displacement per step, units of a
  // Which critical bonds break in one relaxation cycle, and how a load step
  // is relaxed after ruptures: names of the registry (registry.hpp).
  std::string break_rule = "all";     // the paper's rule
  std::string relaxation = "global";  // every cycle a global solve
  bool skip_idle = true;              // jump over increments without rupture
  double stop_fraction = 0.05;        // end when sigma < this * peak after the peak
  double max_strain_ratio = 10;       // ... or when the strain exceeds this * peak strain
  bool stop_within_step = false;      // test the stop fraction after every relaxation
                                      // cycle (calibration: only the peak matters)
  std::int64_t max_steps = 1000000;
  // Relaxation solves end as soon as they decide the next batch (the error
  // of a force taken as decision_safety times its change over the last
  // decision_interval CG iterations); 0: every solve to -ksp_rtol.
  double decision_safety = 1;
  int decision_interval = 4;
  // With decided solves, a load step may also end on a field that decides
  // that nothing more breaks (kept equilibria are still solved to -ksp_rtol).
  bool decided_closing = true;
  // A bond whose force is within tie_band * -ksp_rtol * (mean positive
  // threshold) of its level is decided on a re-solve to tie_rtol: solver
  // noise, which differs with the rank count, must not decide it.  0: off.
  double tie_band = 1000;
  double tie_rtol = 1e-10;
  std::int64_t rebuild_after_ruptures = 2000;  // 0: never by count
  double rebuild_iteration_growth = 1.5;       // 0: never by iterations
  // Threshold disorder: f *= factor(seed, bond id) for the phases listed.
  ThresholdDisorder disorder = ThresholdDisorder::none;
  double disorder_width = 0.0;   // uniform: factor in [1 - w, 1 + w]
  double weibull_modulus = 6.0;  // weibull: mean-one Weibull factor
  std::uint64_t disorder_seed = 1;
  std::array<bool, kPhaseCount> disorder_phases{true, true, false, true, true};
  // Warnings of a degraded result (docs/model/fracture.md, "Warnings"): an energy
  // balance error above warn_energy_error, a peak reached before load step
  // warn_peak_steps (0: either check off); strict makes every warning,
  // the fallback solver's included, an error (exit 2).
  double warn_energy_error = 1e-5;
  std::int64_t warn_peak_steps = 10;
  bool strict = false;
  // Checkpoints (0: never by that criterion); also on SIGTERM / SIGUSR1.
  std::int64_t checkpoint_steps = 0;
  double checkpoint_seconds = 600;
  bool resume = true;  // resume from <output dir>/checkpoint.bin
};

/// Where a run writes and in which units, decided by the run around the
/// protocol (fracture_run.hpp) and read-only for the protocol.
struct FractureOutput {
  std::string dir = "results/fracture";
  std::int64_t snapshot_steps = 0;  // fields every this many load steps (0: none)
  bool elastic_fields = false;      // <dir>/elastic.h5: the first equilibrium,
                                    // with node stresses when the lattice has volumes
  double strength_unit = 1.0;       // sigma^[p] for the normalised columns
  double modulus_unit = 1.0;        // E^[p]
  double stress_unit = 1.0;         // raw stress * this = stress in the units of the
                                    // phase moduli (sample files: 1; lattices: a/k)
};

/// Read the -fracture_*, -strength_* and -checkpoint_* options.
FractureOptions read_fracture_options(MPI_Comm comm);

}  // namespace lem
