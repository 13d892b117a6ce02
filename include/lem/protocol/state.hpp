// The scalar state of a fracture run: what it has done so far (the tally,
// which is also the result) and what the parts of the protocol need to
// continue.  Trivially copyable, so a checkpoint stores it as bytes.
#pragma once

#include "lem/protocol/options.hpp"

#include <array>
#include <cstdint>
#include <type_traits>

namespace lem {

/// Counts and extremes of a run, in raw (lattice or E^phase) units.
struct FractureTally {
  double young_modulus = 0;  // E_eff: sigma/eps of the first equilibrium
  double peak_stress = 0;    // sigma_eff
  double strain_at_peak = 0;
  std::int64_t steps = 0;          // last load step reached
  std::int64_t visited_steps = 0;  // steps at which the state was evaluated
  std::int64_t solves = 0, iterations = 0, preconditioner_builds = 0;
  std::int64_t fallback_solves = 0;  // multigrid failed, Jacobi-CG solved (ElasticSystem)
  std::int64_t rupture_steps = 0;    // steps with at least one rupture
  std::int64_t relaxation_cycles = 0;
  std::int64_t early_stops = 0;     // relaxation solves ended once the batch was decided
  std::int64_t decided_steps = 0;   // load steps that ended on a decided field (no equilibrium)
  std::int64_t tie_solves = 0;      // solves taken on to -fracture_tie_rtol for bonds in doubt
  std::int64_t tie_iterations = 0;  // their CG iterations after -ksp_rtol
  std::array<std::int64_t, kPhaseCount> broken{};  // per phase
  std::int64_t detached_bonds = 0, pinned_nodes = 0;
  std::int64_t pieces = 1;     // connected pieces of unpinned nodes
  double work = 0;             // external work, trapezoidal rule over the curve
  double released_energy = 0;  // energy lost in relaxations (bonds and ground springs)
  std::int64_t broken_total() const;
  double particle_damage() const;  // n_b: broken p bonds / broken bonds
};

/// What the preconditioner policy remembers between solves.
struct PreconditionerState {
  std::int64_t ruptures_since_build = 0;
  std::int64_t baseline_iterations = 0;  // first relaxation solve after the last build
  std::int64_t rebuild_pending = 0;      // the next solve builds a new preconditioner
};

/// Lengths of the result files that belong to the state (rows written
/// after it are dropped on resume), and the CRC-32 of those bytes (a log
/// edited since is refused, not sealed into the result).
struct ResultFileMarks {
  std::int64_t curve_bytes = 0, broken_bytes = 0;
  std::uint32_t curve_crc = 0, broken_crc = 0;
};

struct FractureState {
  FractureTally tally;
  PreconditionerState preconditioner;
  ResultFileMarks files;
  std::int64_t batches = 0;  // numbered batches of matrix changes so far
  std::int64_t next_checkpoint_step = 0;
  double reaction = 0;        // top reaction at the current equilibrium
  double seconds_before = 0;  // wall time of earlier sessions
};
static_assert(std::is_trivially_copyable_v<FractureState>);

}  // namespace lem
