// Parallel HDF5 output of lattice fields, with an XDMF file beside it that
// ParaView opens (nodes as a point cloud, bonds as two-node polylines).
//
// Every rank passes the contiguous slice it owns; global offsets are computed
// here.  The file is written under a temporary name and renamed into place
// only after every rank has finished, so an interrupted run never leaves a
// file that looks complete.
#pragma once

#include "lem/base/files.hpp"  // write_text_file_atomically, for older includers
#include "lem/base/provenance.hpp"

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
  /// Whole numbers (phases, flags, counts): stored as 32-bit integers.
  bool integer = false;
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

/// Write <stem>.h5 and, beside it, two XDMF files of one grid each (what
/// meshio and ParaView's XDMF3 reader take): <stem>.xmf, the bonds as
/// two-node polylines carrying the node and the bond fields, and
/// <stem>_nodes.xmf, the nodes as vertices.  Collective.  Layout:
///   /nodes/coordinates (N x 3), /nodes/id (N), /nodes/vertices (N x 1, the
///   rows 0..N-1: the vertex connectivity), /nodes/<field> (N, N x 3, N x 6)
///   /bonds/connectivity (M x 2, int64), /bonds/id (M), /bonds/<field>
///   root attributes: provenance strings, plus `scalars` as double attributes.
/// Integer fields are int32; large datasets are chunked and compressed.
void write_lattice_fields(MPI_Comm comm, const std::string& stem, const NodeSlice& nodes,
                          const BondSlice& bonds, const Provenance& provenance,
                          const std::vector<std::pair<std::string, double>>& scalars);

}  // namespace lem
