// What the solver module needs of PETSc's private structures, behind plain
// functions (petsc318_private.cpp, the only file that includes a private
// PETSc header; it refuses to build against another PETSc than 3.18).
#pragma once

#include <petscksp.h>

#include <vector>

namespace lem {

/// The operations of a PC type of our own.
struct PcOperations {
  PetscErrorCode (*setup)(PC) = nullptr;
  PetscErrorCode (*apply)(PC, Vec, Vec) = nullptr;
  PetscErrorCode (*destroy)(PC) = nullptr;
  PetscErrorCode (*view)(PC, PetscViewer) = nullptr;
};
/// In a type's create function (PCRegister): make `pc` that type, with
/// `data` as its implementation's data.
void define_pc_type(PC pc, void* data, const PcOperations& ops);
/// The data of a PC made by define_pc_type.
void* pc_type_data(PC pc);
/// In the type's destroy operation, once the data is freed.
void clear_pc_type_data(PC pc);

/// The state counter of `object` (PetscObjectStateGet, a public function
/// only from PETSc 3.19): it grows whenever the object's values change.
PetscObjectState object_state(PetscObject object);

/// Whether `pc` is GAMG with its aggregation (-pc_gamg_type agg).
bool is_gamg_aggregation(PC pc);
/// Make the next builds of GAMG `pc` split, after GAMG's own coarsening of
/// its finest level, every aggregate holding an owned node marked in
/// `near_damage` into pieces one bond across.
void split_aggregates_near(PC pc, std::vector<char> near_damage);

}  // namespace lem
