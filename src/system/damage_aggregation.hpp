// Finer aggregates near broken bonds (-solver_damage_aggregates).
//
// GAMG aggregates the finest level on the squared graph of K (aggregates
// two bonds across), which keeps its coarse levels small; on a damaged
// lattice those aggregates reach across weak necks and crack tips, and the
// coarse space misses the slow modes there (docs/notes/slow-modes.md: the
// plain graph everywhere saves a third of the iterations after the peak,
// for three times the bytes per iteration).  This keeps GAMG's aggregates
// where the lattice is intact and splits, after GAMG's own coarsening of
// the finest level, each aggregate that holds a node of a broken bond into
// pieces one bond across, so the coarse level grows only near the damage.
#pragma once

#include "lem/system/distributed_lattice.hpp"

#include <petscksp.h>

namespace lem {

/// Before a build of the KSP's preconditioner, which must be GAMG's own
/// aggregation (an InputError otherwise, or with another PETSc than 3.18):
/// mark the owned nodes that end a broken bond (stiffness 0, a strength
/// above 0), and with `layers` > 1 those up to layers - 1 intact bonds from
/// them, and make GAMG's coarsening of its finest level split the
/// aggregates holding a marked node.
void prepare_damage_aggregation(KSP ksp, const DistributedLattice& lattice, int layers);

}  // namespace lem
