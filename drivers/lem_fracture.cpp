// Quasi-static tensile test to complete failure (paper sect. 2.3, 3, 6):
// stress-strain curve, E_eff, sigma_eff, broken bonds by phase, fields.
//
//   mpirun -n 2 lem_fracture -sample_file meshes/demo.h5 -output_dir results/fracture
//   mpirun -n 2 lem_fracture -lattice_bonds 200000 -lattice_break_strain 1e-3
#include "lem/run/fracture_run.hpp"

static const char help[] =
    "Quasi-static uniaxial tension to complete failure of an elastic-brittle spring lattice\n"
    "(Affes et al., EPJE 35, 2012).  The sample is a cemented sample file (-sample_file,\n"
    "phases -phase_*) or a generated lattice (-lattice_*, thresholds -lattice_break_strain).\n"
    "Stresses are normalised by sigma^[p], the strength of the homogeneous lattice of the\n"
    "same geometry made of particle bonds, calibrated first (-fracture_calibrate).\n";

int main(int argc, char** argv) { return lem::fracture_program(argc, argv, help); }
