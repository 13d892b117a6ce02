// Step 5 of the parallel set-up (lem/setup/parallel_setup.hpp): the constraints of
// make_tension_constraints found on the distributed lattice -- nodes with
// fewer bonds than free degrees of freedom and pieces with fewer than three
// nodes on the loaded faces pinned, each other piece anchored on a face
// (the node nearest its centroid holds x and y, the farthest from it one
// component) -- with the piece finder of the fracture protocol and per-piece
// sums and picks gathered over the ranks (O(pieces x ranks)).
#pragma once

#include "lem/system/distributed_lattice.hpp"
#include "lem/setup/setup.hpp"

#include <vector>

namespace lem {

/// Sets every node's flags (ghosts from their owners, `ghost_owner` per
/// ghost); keeps only the bonds in the system and the ghosts they reach;
/// counts into `report` (bonds in the system, pruned, pinned, face nodes,
/// edge cut).  Throws InputError when no piece joins the two loaded faces.
/// Collective.
void constrain(DistributedLattice& lattice, const std::vector<int>& ghost_owner,
               SetupReport& report);

}  // namespace lem
