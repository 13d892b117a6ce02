// Effective Young's modulus of cemented samples against the matrix volume
// fraction (Affes et al. 2012, sect. 3, figs. 5 and 11, appendix D;
// lem/run/stiffness_study.hpp).
//
//   mpirun -n 2 lem_stiffness -output_dir results/stiffness
//   /usr/bin/python3 tools/plot_stiffness.py results/stiffness
#include "lem/run/programs.hpp"

static const char help[] =
    "E_eff/E^[p] of cemented samples against the matrix fraction, bare and adhesive\n"
    "contacts, with the Hashin-Shtrikman estimates of appendix D (paper figs. 5, 11).\n";

int main(int argc, char** argv) { return lem::stiffness_program(argc, argv, help); }
