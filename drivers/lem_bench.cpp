// Benchmark of the tension pipeline at one size and rank count (lem/bench/benchmark.hpp):
// set-up stages, assembly, preconditioner set-up, CG solve, peak memory, the
// fine-level MatMult and a STREAM triad measured in the same run, then the bond
// operator beside the assembled K.  Prints figures, not a verdict
// (src/run/bench_program.cpp).
//
//   mpirun -n 2 lem_bench -bench_bonds 1300000 -options_file jobs/solver-gamg.opts
//   lem_bench -bench_voronoi 200000 -lattice_seed 3      # voronoi_volumes() alone
#include "lem/run/programs.hpp"

static const char help[] = "Benchmark of lattice set-up, assembly and the CG + AMG solve.\n";

int main(int argc, char** argv) { return lem::bench_program(argc, argv, help); }
