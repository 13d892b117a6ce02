// A cemented sample built by every rank for its share (paper sect. 2.2-2.3,
// the recipe of build_cemented_sample): the packing and the cube on every
// rank (they are small), the lattice by cells (make_cell_lattice), then each
// rank the Voronoi volumes and phases of its block of nodes and the phases
// of its block of bonds.  Every sum over the nodes is exact, so the sample
// (and the file write_sample_block makes of it) has the same bits on any
// rank count; no rank holds more than its blocks and the particles.
#pragma once

#include "lem/sample/sample_reader.hpp"

#include <mpi.h>

namespace lem {

/// Collective.  spec.generator must be cells.  Throws the InputError of
/// build_cemented_sample for a bad recipe (on every rank).
SampleBlock build_cemented_sample_block(MPI_Comm comm, const CementedSampleSpec& spec);

}  // namespace lem
