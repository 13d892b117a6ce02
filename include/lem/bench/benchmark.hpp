// A benchmark of the tension pipeline at one size and rank count (lem_bench):
// set-up stages, assembly, preconditioner set-up, CG solve, peak memory, the
// fine-level MatMult and a STREAM triad measured in the same run, then the
// bond operator (-solver_operator bonds) beside the assembled K: product and
// CG iteration, then the multigrid cycle level by level in double and single
// precision (-solver_cycle_precision).  It prints figures, not a verdict
// (docs/benchmarks-solver.md).
//
// Solves measured:
//   first  - ElasticSystem::solve(d) as lem_tension does it: KSPSetUp (PC built
//            from scratch) then CG from the affine initial guess;
//   repeat - `repeat` times: assemble() again (same values), KSPSetUp +
//            PCSetUp (PC rebuilt; GAMG may reuse its interpolation), then CG from a zero
//            initial guess on b = K u_first, i.e. the same problem.  The PC set
//            up in one repeat is the one kept for the solve of that repeat.
#pragma once

#include "lem/system/elastic_system.hpp"
#include "lem/setup/setup.hpp"

#include <mpi.h>

#include <cstdint>

namespace lem {

struct BenchOptions {
  std::int64_t bonds = 1300000;    // generated lattices: about this many bonds
  std::int64_t repeat = 3;         // repeated assembly + PC set-up + solve
  std::int64_t cycle_repeat = 3;   // alternating solves of each cycle precision
  bool morton = true;              // Morton order inside each part (serial set-up)
  std::int64_t matmults = 20;      // fine-level products timed
  double stream_mb = 80;           // STREAM array size per rank (MB, x3 arrays)
  std::int64_t voronoi_nodes = 0;  // > 0: time voronoi_volumes() on this many nodes instead
  std::int64_t block_columns = 0;  // > 0: the preconditioner applied to this many columns at once
};

/// The tension benchmark of `sample` (a generated lattice of bench.bonds,
/// or a sample file).  Collective; prints its figures on rank 0.
void run_tension_benchmark(MPI_Comm comm, SampleOptions sample, const BenchOptions& bench,
                           const SolverOptions& solver);

/// voronoi_volumes() (serial, on rank 0) on a random lattice of
/// bench.voronoi_nodes nodes, bench.repeat times: the median.
void run_voronoi_benchmark(MPI_Comm comm, SampleOptions sample, const BenchOptions& bench);

}  // namespace lem
