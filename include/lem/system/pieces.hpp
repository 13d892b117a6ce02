// Connected pieces of the bond graph during fracture, found in parallel.
//
// Ruptures can cut nodes or whole clusters loose.  A piece that is not joined
// to both the bottom and the top face carries no load at equilibrium (nothing
// pulls it), but it leaves zero-energy modes that make K singular.  The
// fracture protocol pins such pieces (their bonds are detached, their nodes
// fixed), and ends the run once no piece joins the two faces.
#pragma once

#include "lem/system/distributed_lattice.hpp"

#include <petscvec.h>

#include <cstdint>
#include <vector>

namespace lem {

struct PieceReport {
  std::vector<int> loose_nodes;       // local nodes (owned and ghost) of pieces to pin
  std::int64_t pieces = 0;            // pieces of unpinned nodes, global
  std::int64_t loose_pieces = 0;      // of which carry no load
  std::int64_t loose_node_count = 0;  // owned nodes in them, global
  bool faces_joined = false;          // some piece joins the bottom to the top face
};

/// Labels the pieces of the graph of bonds with k > 0 over the unpinned
/// nodes.  Each rank unites its local bonds with a union-find, then the
/// smallest global node index of each piece spreads across ranks through the
/// ghost nodes (a min-reduction) until no label changes: a few rounds, since
/// every round crosses at least one rank boundary.
class PieceFinder {
 public:
  explicit PieceFinder(const DistributedLattice& lattice);
  ~PieceFinder();
  PieceFinder(const PieceFinder&) = delete;
  PieceFinder& operator=(const PieceFinder&) = delete;

  PieceReport find() const;

  /// Nodes with fewer active bonds than free degrees of freedom, removed
  /// repeatedly (as the set-up does): at equilibrium their bonds carry no
  /// force, yet they leave zero-energy modes.  Pinned nodes included; per
  /// local node (owned and ghost).
  std::vector<char> underconnected() const;
  /// The piece of every local node: the smallest global index in it, over
  /// the bonds with k > 0 between nodes that are not `excluded` (per local
  /// node); -1 for excluded nodes.
  std::vector<std::int64_t> labels(const std::vector<char>& excluded) const;

 private:
  const DistributedLattice& lattice_;
  Vec labels_ = nullptr;  // one value per node, ghosted like the displacements
};

}  // namespace lem
