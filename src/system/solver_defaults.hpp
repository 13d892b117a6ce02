// The solver defaults of ElasticSystem, shared by its files
// (elastic_system.cpp, solver_defaults.cpp); not part of the public API.
#pragma once

#include "lem/system/solver_lever.hpp"

#include <petscksp.h>

namespace lem {

/// CG, rtol 1e-8, GAMG with plain aggregation and a 1000-row coarse grid,
/// and a pre-solve hook that sets the W cycle and one sweep per level
/// unless options do.  Call before KSPSetFromOptions.
void apply_solver_defaults(KSP ksp);
/// The fallback solver (-fallback_* options): CG + Jacobi from the current
/// iterate.  Call before KSPSetFromOptions.
void apply_fallback_defaults(KSP ksp);
/// KSPSetFromOptions as an input check: a value PETSc cannot take is an
/// InputError naming the option, and so is a Krylov method that cannot
/// start from the previous solution (every solve here does).
void set_from_options(KSP ksp);
/// Put -mat_no_inode in the options database unless given (see the .cpp).
void default_no_inodes();

}  // namespace lem
