// Reading the cemented sample file: everything build_cemented_sample produced, so
// that a sample is built once and loaded by any number of mechanical runs.
// Its writers are in lem/sample/sample_writer.hpp.
//
// <stem>.h5 (serial HDF5, gzip-compressed chunks):
//   /nodes/coordinates (N x 3 f64), /nodes/volume (N f64, clipped Voronoi),
//   /nodes/particle (N int32, -1 outside every particle),
//   /nodes/phase (N uint8: 0 particle, 1 matrix, 2 void)
//   /bonds/connectivity (M x 2 int64, i < j), /bonds/phase (M uint8, lem::Phase),
//   /bonds/stiffness (M f64, as built, before the phase table is applied)
//   /particles/centres (P x 3), /particles/radii (P)
//   /bridges/particles (B x 2 int32), /bridges/lambda (B)
//   root attributes: format = "lem-cemented-sample", format_version = 1,
//   box_lo / box_hi, every CementedSampleStats field (bonds_per_phase as
//   bonds_p, bonds_m, ...; a statistic newer than the file reads as 0), the spec (packing_*, sample_particles,
//   lattice_*, matrix_*), void_bonds ("any_end" or "both_ends": the rule
//   that made /bonds/phase; absent in older files, which used any_end) and
//   the provenance.
//   /nodes/vertices, /particles/vertices (int64 rows 0..N-1: the vertex
//   connectivity of the XDMF point grids; absent in older files)
// <stem>.xmf: the bonds (phase, stiffness) with the node fields (phase,
//   particle, volume); <stem>_nodes.xmf: the nodes as vertices;
//   <stem>_particles.xmf: the particles (radius) as vertices.  One grid per
//   file, for ParaView and meshio.
#pragma once

#include "lem/sample/cemented_sample.hpp"
#include "lem/base/provenance.hpp"

#include <mpi.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace lem {

inline constexpr const char* kSampleFormat = "lem-cemented-sample";
inline constexpr int kSampleFormatVersion = 1;

/// A sample file's whole content.
struct SampleFile {
  CementedSample sample;
  CementedSampleSpec spec;
  Provenance provenance;  // of the run that built the sample
};

/// Read and check a sample file (serial).  Throws InputError naming the file
/// if it does not exist, is not HDF5, is not a sample file, has another
/// format version, or is corrupt (missing datasets, inconsistent sizes,
/// indices or phase codes out of range).
SampleFile read_sample_file(const std::string& path);
CementedSample read_sample(const std::string& path);
/// Only the attributes, particles and bridges (serial, cheap): the sizes of
/// a sample before it is read.  Its lattice holds only the box.
SampleFile read_sample_description(const std::string& path);

/// One rank's share of a sample: a block of its node rows and a block of its
/// bond rows (lem::RowBlocks over the ranks), and the rest whole.
struct SampleBlock {
  /// The attributes, particles, bridges and provenance; its lattice holds
  /// only the box (no nodes, no bonds).
  SampleFile description;
  std::int64_t nodes = 0, bonds = 0;            // rows in the file
  std::int64_t node_begin = 0, bond_begin = 0;  // file rows of this rank's first entries
  std::vector<Point> coords;                    // per node row of the block
  std::vector<double> volume;
  std::vector<std::int32_t> particle;
  std::vector<char> matrix;
  std::vector<std::array<std::int64_t, 2>> ends;  // per bond row of the block
  std::vector<std::array<Point, 2>> end_coords;   // the positions of those ends
  std::vector<Phase> bond_phase;
};

/// Collective: every rank reads its blocks through parallel HDF5, with the
/// checks of read_sample_file (the positions of its bonds' ends and the
/// bonds repeated come from the ranks that read those rows).  Throws the
/// same InputError on every rank: of the first bad row when rows are bad.
SampleBlock read_sample_block(MPI_Comm comm, const std::string& path);

}  // namespace lem
