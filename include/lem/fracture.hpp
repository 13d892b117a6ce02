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
// The matrix is changed in place; the preconditioner is kept across steps
// and rebuilt by a policy (ruptures since the last build, growth of the
// iteration count).  Pieces cut loose are pinned (pieces.hpp).  The run ends
// when the stress has fallen below a fraction of the peak or no piece joins
// the bottom to the top face.
//
// Every change of the matrix is a numbered batch of events (bonds broken,
// nodes pinned).  A checkpoint stores the events, the step, the counters and
// the displacements; a restart replays the events and every preconditioner
// build in the same order as the interrupted run, so the resumed run
// continues bit for bit as the uninterrupted one.
#pragma once

#include "lem/distributed_lattice.hpp"
#include "lem/elastic_system.hpp"
#include "lem/hdf5_writer.hpp"

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace lem {

inline constexpr int kBondPhases = 5;  // p, m, v, pp, pm (lem::Phase order)

struct FractureOptions {
  double increment = 3e-4;           // top displacement per step, units of a
  bool break_all = true;             // paper's rule; false: most critical only
  bool skip_idle = true;             // jump over increments without rupture
  double stop_fraction = 0.05;       // end when sigma < this * peak after the peak
  double max_strain_ratio = 10;      // ... or when the strain exceeds this * peak strain
  bool stop_within_step = false;     // test the stop fraction after every relaxation
                                     // cycle (calibration: only the peak matters)
  std::int64_t max_steps = 1000000;
  std::int64_t rebuild_after_ruptures = 2000;  // 0: never by count
  double rebuild_iteration_growth = 2.5;       // 0: never by iterations
  // Threshold disorder: f *= factor(seed, bond id) for the phases listed.
  std::string disorder = "none";     // none | uniform | weibull
  double disorder_width = 0.0;       // uniform: factor in [1 - w, 1 + w]
  double weibull_modulus = 6.0;      // weibull: mean-one Weibull factor
  std::uint64_t disorder_seed = 1;
  std::array<bool, kBondPhases> disorder_phases{true, true, false, true, true};
  // Checkpoints (0: never by that criterion); also on SIGTERM / SIGUSR1.
  std::int64_t checkpoint_steps = 0;
  double checkpoint_seconds = 600;
  bool resume = true;                // resume from <output_dir>/checkpoint.bin
  // Results.
  std::string output_dir = "results/fracture";
  std::int64_t snapshot_steps = 0;   // fields every this many load steps (0: none)
  bool elastic_fields = false;       // <output_dir>/elastic.h5: the first equilibrium,
                                     // with node stresses when the lattice has volumes
  double strength_unit = 1.0;        // sigma^[p] for the normalised columns
  double modulus_unit = 1.0;         // E^[p]
  double stress_unit = 1.0;          // raw stress * this = stress in the units of the
                                     // phase moduli (sample files: 1; lattices: a/k)
  /// Called once after the first solve (drivers check the options there).
  std::function<void()> after_first_solve;
};

/// Read the -fracture_*, -strength_* and -checkpoint_* options.
FractureOptions read_fracture_options(MPI_Comm comm);

/// Multiply the thresholds of the chosen phases by a seeded random factor
/// that depends only on (seed, bond id): the same on every rank count.
void apply_strength_disorder(DistributedLattice& lattice, const FractureOptions& options);

struct FractureResult {
  double young_modulus = 0;       // E_eff: sigma/eps of the first equilibrium (raw units)
  double peak_stress = 0;         // sigma_eff (raw units)
  double strain_at_peak = 0;
  double final_stress = 0, final_strain = 0;
  std::int64_t steps = 0;         // last load step reached
  std::int64_t visited_steps = 0; // steps at which the state was evaluated
  std::int64_t solves = 0, iterations = 0, preconditioner_builds = 0;
  std::int64_t fallback_solves = 0;  // multigrid failed, Jacobi-CG solved (ElasticSystem)
  std::int64_t rupture_steps = 0; // steps with at least one rupture
  std::int64_t relaxation_cycles = 0;
  std::array<std::int64_t, kBondPhases> broken{};  // per phase
  std::int64_t detached_bonds = 0, pinned_nodes = 0;
  double work = 0, stored_energy = 0, released_energy = 0;
  double energy_balance_error = 0;  // |W - E - R| / W
  std::string end_reason;
  double seconds = 0;
  bool resumed = false;
  std::int64_t broken_total() const;
  double particle_damage() const;   // n_b: broken p bonds / broken bonds
};

/// Runs the protocol on an assembled system.  Writes <output_dir>/curve.csv,
/// broken.csv (complete only at the end: *.part while running), snapshots
/// and checkpoint.bin (which records a hash of the sample and the options
/// that change the results, so that a resume with others is refused).
FractureResult run_fracture(DistributedLattice& lattice, ElasticSystem& system,
                            const FractureOptions& options, const Provenance& provenance);

}  // namespace lem
