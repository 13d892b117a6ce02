// The part of the lattice one rank works on: the nodes it owns (a contiguous
// block of the distributed numbering), the ghost nodes at the other end of its
// bonds, and every active bond touching an owned node.  A bond joining two
// ranks is held by both (each assembles its own rows) and reported by the one
// owning its lower-numbered end.
#pragma once

#include "lem/lattice/lattice.hpp"
#include "lem/system/partition.hpp"
#include "lem/system/tension.hpp"

#include <mpi.h>

#include <array>
#include <cstdint>
#include <vector>

namespace lem {

struct DistributedLattice {
  MPI_Comm comm = MPI_COMM_NULL;
  Box box;
  double mean_bond_length = 0;  // a: the mean length of the lattice's elements
                                // (a sample file's: every row of /bonds, voids too)
  std::int64_t global_nodes = 0;
  std::int64_t global_bonds = 0;  // active bonds in the system
  std::int64_t node_begin = 0;    // owned block [node_begin, node_begin + owned)
  int owned = 0;                  // local nodes [0, owned) are owned, the rest ghosts

  // Per local node (owned first, then ghosts in increasing global order).
  std::vector<std::int64_t> global_index;  // distributed numbering
  std::vector<std::int64_t> node_id;       // lattice numbering (partition-independent)
  std::vector<Point> coords;
  std::vector<std::uint8_t> dof_flags;      // DofFlag bits
  std::vector<std::uint8_t> faces;          // Face bits
  std::vector<double> node_volume;          // Voronoi volume (empty: lattice had none)
  std::vector<std::int32_t> node_particle;  // particle, -1 none (empty: lattice had none)

  // Per local bond.
  std::vector<std::array<int, 2>> bond_ends;  // local node indices
  std::vector<std::int64_t> bond_id;          // lattice bond id (a sample file's /bonds row)
  std::vector<double> bond_stiffness;         // current k (0 once broken)
  std::vector<double> bond_strength;          // breaking force (empty: lattice had none)
  std::vector<std::uint8_t> bond_tag;         // e.g. phase (empty: lattice had none)
  std::vector<char> bond_reported;            // this rank reports it in sums and files

  int local_nodes() const { return static_cast<int>(global_index.size()); }
  int local_bonds() const { return static_cast<int>(bond_id.size()); }
  int ghosts() const { return local_nodes() - owned; }
};

/// Unit vector of a local bond, from its first end to its second.
void bond_direction(const DistributedLattice& l, int bond, double n[3]);

/// Scatter from rank 0: `lattice`, `constraints` and `partition` are read on
/// rank 0 only (other ranks may pass empty objects).
DistributedLattice distribute_lattice(MPI_Comm comm, const Lattice& lattice,
                                      const TensionConstraints& constraints,
                                      const Partition& partition,
                                      const std::vector<std::uint8_t>& faces);

}  // namespace lem
