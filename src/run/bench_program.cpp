// lem_bench: the benchmark of the tension pipeline at one size and rank
// count (lem/bench/benchmark.hpp), or of voronoi_volumes() alone.
#include "lem/solver/levers.hpp"
#include "lem/base/driver.hpp"
#include "lem/base/error.hpp"
#include "lem/base/options.hpp"
#include "lem/bench/benchmark.hpp"
#include "lem/run/programs.hpp"

#include <string>

namespace lem {

namespace {

BenchOptions read_bench_options(MPI_Comm comm, const SampleOptions& sample) {
  BenchOptions bench;
  OptionGroup g(comm, "Benchmark");
  bench.bonds =
      g.integer("-bench_bonds", "Approximate number of bonds", bench.bonds, 100, 2'000'000'000);
  bench.repeat =
      g.integer("-bench_repeat", "Repeated assembly + PC set-up + solve", bench.repeat, 0, 100);
  bench.cycle_repeat = g.integer("-bench_cycle_repeat",
                                 "Alternating solves of each "
                                 "multigrid cycle precision (double, single) on the same "
                                 "preconditioner",
                                 bench.cycle_repeat, 1, 100);
  bench.morton =
      g.flag("-bench_morton", "Morton order inside each part (false: METIS order)", bench.morton);
  bench.matmults =
      g.integer("-bench_matmult", "Fine-level MatMults timed", bench.matmults, 1, 10000);
  bench.stream_mb = g.real("-bench_stream_mb", "STREAM array size per rank (MB, x3 arrays)",
                           bench.stream_mb, 1.0, 1e5);
  bench.block_columns = g.integer(
      "-bench_block_columns",
      "Also apply the preconditioner to this many random columns at once (PCMatApply: one "
      "MatMatSolve for a factorization) and to one, and print the cost per column: what a "
      "column of a low-rank update to a factorization costs (0: not measured)",
      0, 0, 100000);
  bench.voronoi_nodes = g.integer("-bench_voronoi",
                                  "Time voronoi_volumes() on a random "
                                  "lattice of this many nodes instead (0: the tension "
                                  "benchmark)",
                                  0, 0, 2'000'000'000);
  for (const char* o : {"-lattice_nodes", "-lattice_bonds", "-lattice_Ln", "-lattice_type"})
    if (g.given(o))
      throw InputError(std::string(o) + ": lem_bench sets the size with "
                                        "-bench_bonds (random lattices) or reads "
                                        "-sample_file");
  if (!sample.sample_file.empty() && g.given("-bench_bonds"))
    throw InputError("-bench_bonds sizes generated lattices: the sample file "
                     "-sample_file fixes its lattice");
  return bench;
}

}  // namespace

int bench_program(int argc, char** argv, const char* help) {
  return run_driver(argc, argv, help, [](MPI_Comm comm) {
    const SampleOptions sample = read_sample_options(comm);
    const BenchOptions bench = read_bench_options(comm, sample);
    register_solver_levers();
    const SolverOptions solver = read_solver_options(comm);
    check_option_names(comm);
    if (bench.voronoi_nodes > 0) {
      check_unused_options();
      run_voronoi_benchmark(comm, sample, bench);
    } else {
      run_tension_benchmark(comm, sample, bench, solver);
    }
  });
}

}  // namespace lem
