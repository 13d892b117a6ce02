// Benchmark of the tension pipeline at one size and rank count (lem/bench/benchmark.hpp):
// set-up stages, assembly, preconditioner set-up, CG solve, peak memory, the
// fine-level MatMult and a STREAM triad measured in the same run, then the bond
// operator beside the assembled K.  Prints figures, not a verdict.
//
//   mpirun -n 2 lem_bench -bench_bonds 1300000 -options_file jobs/solver-gamg.opts
//   lem_bench -bench_voronoi 200000 -lattice_seed 3      # voronoi_volumes() alone
#include "lem/bench/benchmark.hpp"
#include "lem/base/driver.hpp"
#include "lem/base/error.hpp"
#include "lem/base/options.hpp"

#include <string>

static const char help[] = "Benchmark of lattice set-up, assembly and the CG + AMG solve.\n";

int main(int argc, char** argv) {
  return lem::run_driver(argc, argv, help, [](MPI_Comm comm) {
    const lem::SampleOptions sample = lem::read_sample_options(comm);
    lem::BenchOptions bench;
    {
      lem::OptionGroup g(comm, "Benchmark");
      bench.bonds =
          g.integer("-bench_bonds", "Approximate number of bonds", bench.bonds, 100, 2'000'000'000);
      bench.repeat =
          g.integer("-bench_repeat", "Repeated assembly + PC set-up + solve", bench.repeat, 0, 100);
      bench.cycle_repeat = g.integer("-bench_cycle_repeat",
                                     "Alternating solves of each "
                                     "multigrid cycle precision (double, single) on the same "
                                     "preconditioner",
                                     bench.cycle_repeat, 1, 100);
      bench.morton = g.flag("-bench_morton", "Morton order inside each part (false: METIS order)",
                            bench.morton);
      bench.matmults =
          g.integer("-bench_matmult", "Fine-level MatMults timed", bench.matmults, 1, 10000);
      bench.stream_mb = g.real("-bench_stream_mb", "STREAM array size per rank (MB, x3 arrays)",
                               bench.stream_mb, 1.0, 1e5);
      bench.voronoi_nodes = g.integer("-bench_voronoi",
                                      "Time voronoi_volumes() on a random "
                                      "lattice of this many nodes instead (0: the tension "
                                      "benchmark)",
                                      0, 0, 2'000'000'000);
      for (const char* o : {"-lattice_nodes", "-lattice_bonds", "-lattice_Ln", "-lattice_type"})
        if (g.given(o))
          throw lem::InputError(std::string(o) + ": lem_bench sets the size with "
                                                 "-bench_bonds (random lattices) or reads "
                                                 "-sample_file");
      if (!sample.sample_file.empty() && g.given("-bench_bonds"))
        throw lem::InputError("-bench_bonds sizes generated lattices: the sample file "
                              "-sample_file fixes its lattice");
    }
    const lem::SolverOptions solver = lem::read_solver_options(comm);
    lem::check_option_names(comm);
    if (bench.voronoi_nodes > 0) {
      lem::check_unused_options();
      lem::run_voronoi_benchmark(comm, sample, bench);
    } else {
      lem::run_tension_benchmark(comm, sample, bench, solver);
    }
  });
}
