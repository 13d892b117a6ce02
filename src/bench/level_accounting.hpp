// Per-level accounting of the multigrid cycle in lem_bench, and the double-
// and single-precision cycles (-solver_cycle_precision) side by side.
#pragma once

#include "lem/system/elastic_system.hpp"

#include <cstdint>

namespace lem {

/// The operator of a multigrid level (`level` counted from the coarsest,
/// as PCMG does) as its smoother has it (assembled even with -pc_use_amat),
/// its global rows and its nonzeros.  Collective.
struct LevelOperator {
  Mat A = nullptr;
  PetscInt rows = 0;
  double nonzeros = 0;
};
LevelOperator level_operator(PC mg, PetscInt level);

/// With `b` the right-hand side of the benchmark: one logged CG solve per
/// cycle precision, printed as a table per level (rows, nonzeros, visits,
/// products and transfers, bytes by the model, ms measured, per CG
/// iteration), then `repeat` (≥ 1) alternating unlogged solves of each and the
/// system's E_eff with each.  Needs -pc_mg_log set before the multigrid was
/// built (for the double cycle's level events).  Collective.
void account_levels(MPI_Comm comm, ElasticSystem& sys, DistributedLattice& lattice,
                    const SolverOptions& solver, Vec b, double delta, std::int64_t repeat);

}  // namespace lem
