// The soft directions of single nodes: a node left with a few nearly
// coplanar bonds moves normal to their plane at almost no cost, and the
// point-Jacobi smoother does not see that direction.  Read from the node's
// own 3x3 block B with D its diagonal: an eigenvector y of D^-1/2 B D^-1/2
// whose eigenvalue mu lies below a threshold gives the direction D^-1/2 y
// (mu is the Rayleigh quotient the smoother sees).  Used by the soft-node
// deflation (-solver_soft_node_deflation, src/system/soft_node_deflation.hpp).
#pragma once

#include "lem/system/distributed_lattice.hpp"

#include <array>
#include <vector>

namespace lem {

/// A soft direction of one node: the node (local index) and the unit
/// vector (zero on its fixed dofs).
struct SoftDirection {
  int node = 0;
  std::array<double, 3> vector{};
};

/// The soft directions of the owned nodes: for every owned node with a free
/// dof, the eigenvectors of its diagonal-scaled 3x3 block (intact bonds,
/// `ground` on free dofs) whose eigenvalue is below `threshold`.
std::vector<SoftDirection> find_soft_directions(const DistributedLattice& lattice, double ground,
                                                double threshold);

}  // namespace lem
