// The built-in solver levers (src/solver/): preconditioners put around the
// multigrid of the elastic system, each a PETSc PC type registered with
// PCRegister and chosen by its option (lem/system/solver_lever.hpp).
//
//   lem_single_cycle        -solver_cycle_precision single  the multigrid cycle in float (default)
//   lem_damage_aggregates   -solver_damage_aggregates N   GAMG's aggregates split near cracks
//   lem_particle_deflation  -solver_particle_deflation    rigid modes of every particle
//   lem_ritz_deflation      -solver_ritz_deflation N      slow Ritz vectors learnt from solves
//   lem_direct_tail         -solver_direct_tail N         a factor of K with low-rank updates, when CG is slow
//
// A lever of one's own is one file with a SolverLever and its entry, and one
// call of register_solver_lever() before the options are read, after
// register_solver_levers() so that it goes around the built-in ones (the
// single-precision cycle, the default, must wrap the multigrid itself;
// tests/extension/extended_fracture.cpp).
#pragma once

namespace lem {

/// Register the built-in levers (once; later calls do nothing).  Every
/// program calls it before it reads the solver's options.
void register_solver_levers();

}  // namespace lem
