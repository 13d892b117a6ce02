// Parallel HDF5 output of lattice fields, with an XDMF file beside it that
// ParaView opens (nodes as a point cloud, bonds as two-node polylines).
//
// Every rank passes the contiguous slice it owns; global offsets are computed
// here.  The file is written under a temporary name and renamed into place
// only after every rank has finished, so an interrupted run never leaves a
// file that looks complete.
#pragma once

#include "lem/files.hpp"       // write_text_file_atomically, for older includers
#include "lem/provenance.hpp"

#include <mpi.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace lem {

/// A named per-item field with `components` values per item: 1 (scalar), 3
/// (vector) or 6 (symmetric tensor in XDMF's Tensor6 order xx, xy, xz, yy,
/// yz, zz).
struct Field {
  std::string name;
  int components = 1;
  std::vector<double> values;  // size = local item count * components
};

/// Nodes owned by this rank (a contiguous block of the global numbering).
struct NodeSlice {
  std::vector<std::array<double, 3>> coords;
  std::vector<std::int64_t> ids;  // partition-independent node ids
  std::vector<Field> fields;      // e.g. "displacement" (3), "pinned" (1)
};

/// Bonds reported by this rank (each bond by exactly one rank).
struct BondSlice {
  /// End nodes as row numbers of the node datasets of the same file
  /// (i.e. the global numbering in which the NodeSlices are contiguous).
  std::vector<std::array<std::int64_t, 2>> ends;
  std::vector<std::int64_t> ids;  // partition-independent bond ids
  std::vector<Field> fields;      // e.g. "force", "stiffness"
};

/// Write <stem>.h5 and <stem>.xmf collectively.  Layout:
///   /nodes/coordinates (N x 3), /nodes/id (N), /nodes/<field> (N or N x 3)
///   /bonds/connectivity (M x 2, int64), /bonds/id (M), /bonds/<field>
///   root attributes: provenance strings, plus `scalars` as double attributes.
void write_lattice_fields(MPI_Comm comm, const std::string& stem, const NodeSlice& nodes,
                          const BondSlice& bonds, const Provenance& provenance,
                          const std::vector<std::pair<std::string, double>>& scalars);

}  // namespace lem
