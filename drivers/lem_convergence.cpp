// Convergence of the effective Young's modulus with the mesh density
// L_n = M^(-1/3) (paper sect. 3, fig. 6): a matrix with 20% stiff spherical
// inclusions (10x) and with 20% spherical pores, each normalised by the
// homogeneous lattice of the same nodes, fitted linearly in L_n
// (lem/run/convergence_study.hpp).
//
//   mpirun -n 2 lem_convergence -convergence_Ln 0.05,0.04,0.03,0.02 -output_dir results/convergence
//   /usr/bin/python3 tools/plot_convergence.py results/convergence
#include "lem/run/programs.hpp"

static const char help[] =
    "Mesh-density convergence of E_eff for stiff inclusions and pores (paper fig. 6).\n";

int main(int argc, char** argv) { return lem::convergence_program(argc, argv, help); }
