// Partition of the nodes over MPI ranks (METIS k-way on the bond graph) and a
// new global numbering in which every rank owns a contiguous block, ordered
// along a Morton (Z-order) curve inside each block for memory locality.
#pragma once

#include "lem/lattice/lattice.hpp"

#include <cstdint>
#include <vector>

namespace lem {

struct Partition {
  int parts = 1;
  std::vector<int> owner;               // rank owning each node (lattice numbering)
  std::vector<std::int64_t> new_index;  // lattice numbering -> distributed numbering
  std::vector<std::int64_t> offsets;    // block of rank r: [offsets[r], offsets[r+1])
  std::int64_t edge_cut = 0;            // bonds joining two ranks
};

/// `bond_active` selects the bonds of the graph (empty = all).
/// `morton` = false keeps the METIS order inside a block (for benchmarks).
Partition partition_lattice(const Lattice& lattice, const std::vector<char>& bond_active, int parts,
                            bool morton = true);

/// Parts of a graph of spatial cells (vertex weights; CSR adjacency with
/// edge weights, symmetric): METIS k-way with a fixed seed, so that every
/// rank that partitions the same graph gets the same parts.
std::vector<int> partition_cells(const std::vector<std::int64_t>& weights,
                                 const std::vector<std::int64_t>& xadj,
                                 const std::vector<std::int64_t>& adjncy,
                                 const std::vector<std::int64_t>& adjwgt, int parts);

/// 63-bit Morton code of a point of the box (21 bits per axis).
std::uint64_t morton_code(const Point& p, const Box& box);

}  // namespace lem
