// Dense packing of polydisperse spheres and the cubic sample cut out of it
// (src/run/packing_run.cpp).
//
//   lem_pack -pack_particles 4000 -pack_sample_particles 516 -output_dir results/packing
//
// -pack_particles defaults to "auto" (twice the cube's count, rounded to a
// hundred: 1000 for the default 516).  The packing is serial: rank 0 builds it.
#include "lem/run/programs.hpp"

static const char help[] =
    "Jammed packing of polydisperse frictionless spheres (isotropic compaction in a periodic\n"
    "box) and a cubic sample of it, as in Affes et al., EPJE 35 (2012), sect. 2.2-2.3.\n";

int main(int argc, char** argv) { return lem::pack_program(argc, argv, help); }
