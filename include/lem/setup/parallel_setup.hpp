// The tension lattice of a sample file (or of a lattice generated in
// parallel) set up by every rank for its share, so that no rank reads,
// holds or partitions the whole sample:
//   1. each rank reads a block of the file's node rows and of its bond rows;
//   2. the bonds get their stiffness and strength (k = E a, f = sigma a^2,
//      a the mean length of every bond, summed exactly: the same bits on any
//      rank count) and their ids (the file's order without the void bonds,
//      as the serial set-up numbers them);
//   3. the nodes are partitioned by spatial cells: every rank counts its
//      nodes and bonds per cell, and the same METIS partition of the small
//      cell graph is made on every rank;
//   4. nodes and bonds go to their owners, who number their nodes along a
//      Morton curve and learn their ghosts from the ghosts' owners;
//   5. the tension constraints (under-connected nodes and pieces pinned,
//      each piece anchored on a face) are found in parallel.
#pragma once

#include "lem/system/distributed_lattice.hpp"
#include "lem/setup/setup.hpp"

#include <mpi.h>

namespace lem {

/// Collective.  `options.sample_file` must name a sample file.  The result
/// has the nodes, bonds, ids, stiffnesses, strengths and constraints of
/// setup_tension_lattice(build_sample(options)), up to the partition (and
/// the last bits of a, summed in another order there).
DistributedLattice setup_sample_in_parallel(MPI_Comm comm, const SampleOptions& options,
                                            SetupReport& report);

/// The same for a random lattice made by make_cell_lattice
/// (-lattice_generator cells): its blocks take the place of the file's.
/// Every bond k = -lattice_k (halved on the faces with -lattice_face_bonds
/// halved), no breaking forces (the drivers set them).  Collective.
DistributedLattice setup_generated_in_parallel(MPI_Comm comm, const SampleOptions& options,
                                               SetupReport& report);

}  // namespace lem
