// Elastic uniaxial tension of a lattice sample: prints the effective Young's
// modulus and Poisson ratio and writes a summary and the fields
// (src/run/tension_run.cpp).
//
//   mpirun -n 2 lem_tension -lattice_bonds 1300000 -output_dir results/tension
//   mpirun -n 2 lem_tension -sample_file meshes/demo.h5 -output_dir results/demo
#include "lem/run/programs.hpp"

static const char help[] =
    "Elastic uniaxial tension of a spring lattice (Affes et al., EPJE 35, 2012).\n"
    "Bottom face u_z = 0, top face u_z = Delta, lateral faces free.\n"
    "The sample is a generated lattice (-lattice_*, -inclusion_*) or a cemented sample\n"
    "file from lem_sample (-sample_file, bond moduli -phase_E_*).\n";

int main(int argc, char** argv) { return lem::tension_program(argc, argv, help); }
