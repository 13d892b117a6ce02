// The solver defaults of ElasticSystem, shared by its files
// (elastic_system.cpp, solver_defaults.cpp); not part of the public API.
#pragma once

#include <petscksp.h>

namespace lem {

/// CG, rtol 1e-8, GAMG with plain aggregation and a 1000-row coarse grid,
/// and a pre-solve hook that sets the W cycle and one sweep per level
/// unless options do.  Call before KSPSetFromOptions.
void apply_solver_defaults(KSP ksp);
/// Put -mat_no_inode in the options database unless given (see the .cpp).
void default_no_inodes();

}  // namespace lem
