// Build a cemented granular sample and write it to a sample file that
// lem_tension (-sample_file) and the other mechanical drivers load
// (src/run/sample_run.cpp).
//
//   lem_sample -sample_particles 516 -lattice_bonds 1300000 -matrix_fraction 0.13
//   lem_sample -sample_particles 64 -output_dir meshes -output_stem tiny
#include "lem/run/programs.hpp"

static const char help[] =
    "Cemented granular sample (Affes et al., EPJE 35, 2012, sect. 2.2-2.3):\n"
    "  1. a jammed periodic packing of polydisperse spheres (-pack_*),\n"
    "  2. a cube holding -sample_particles sphere centres (spheres reaching in are kept),\n"
    "  3. a random Delaunay lattice in the cube (-lattice_*) and its clipped Voronoi volumes\n"
    "     (-lattice_generator cells: every rank builds and writes its share of steps 3-5),\n"
    "  4. matrix bridges between near particles (-matrix_*), calibrated so that the matrix\n"
    "     volume measured on the lattice is -matrix_fraction,\n"
    "  5. node phases (particle/matrix/void) and bond phases (p, m, v, pp, pm).\n"
    "Writes <output_dir>/<output_stem>.h5 and .xmf (open in ParaView) and a summary.\n";

int main(int argc, char** argv) { return lem::sample_program(argc, argv, help); }
