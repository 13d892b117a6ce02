// From options to a distributed tension problem: the stages every driver
// shares (lattice -> two-phase sample -> constraints -> partition -> scatter).
#pragma once

#include "lem/distributed_lattice.hpp"
#include "lem/inclusions.hpp"
#include "lem/lattice.hpp"

#include <mpi.h>

#include <functional>
#include <string>

namespace lem {

/// What a lattice sample is made of; read from the -lattice_* and
/// -inclusion_* options.
struct SampleOptions {
  std::string lattice_type = "random";  // random | fcc
  RandomLatticeSpec random;
  std::array<int, 3> fcc_cells{4, 4, 4};
  std::string inclusion_type = "none";  // none | stiff | pore
  InclusionSpec inclusions;
  double inclusion_stiffness_ratio = 10.0;
  bool pore_needs_both_ends = false;  // void-bond rule, see carve_pores()
};
SampleOptions read_sample_options(MPI_Comm comm);

/// Facts about the built sample, known on every rank after setup.
struct SampleInfo {
  LatticeStats stats;          // of the lattice before inclusions
  AffineModuli affine;         // of the sample as built (with inclusions)
  double inclusion_fraction = 0;       // geometric, exact
  double inclusion_node_fraction = 0;  // share of nodes inside inclusions
  std::int64_t inclusion_count = 0;
};

/// Build the sample on the calling rank (normally rank 0).
Lattice build_sample(const SampleOptions& options, SampleInfo& info);

/// Counts and timings of the set-up stages, identical on every rank.
struct SetupReport {
  SampleInfo sample;
  std::int64_t active_bonds = 0, pruned_bonds = 0, pinned_nodes = 0;
  std::int64_t bottom_nodes = 0, top_nodes = 0, edge_cut = 0;
  double seconds_build = 0, seconds_constraints = 0, seconds_partition = 0,
         seconds_distribute = 0;
};

/// Run `build` on rank 0, add the tension constraints, partition over the
/// ranks of `comm` and scatter.  Errors on rank 0 are raised on every rank.
DistributedLattice setup_tension_lattice(MPI_Comm comm,
                                         const std::function<Lattice(SampleInfo&)>& build,
                                         SetupReport& report, bool morton = true);

}  // namespace lem
