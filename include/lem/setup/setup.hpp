// From options to a distributed tension problem: the stages every driver
// shares (lattice -> two-phase sample -> constraints -> partition -> scatter).
#pragma once

#include "lem/sample/cemented_sample.hpp"
#include "lem/system/distributed_lattice.hpp"
#include "lem/lattice/inclusions.hpp"
#include "lem/lattice/lattice.hpp"

#include <mpi.h>

#include <functional>
#include <string>

namespace lem {

/// What a lattice sample is made of; read from the -lattice_* and
/// -inclusion_* options, or from a cemented sample file (-sample_file, with
/// the bond moduli of -phase_*), which excludes the generation options.
enum class LatticeType { random, fcc, sample /* set by -sample_file */ };
enum class InclusionType { none, stiff, pore };

struct SampleOptions {
  LatticeType lattice_type = LatticeType::random;
  std::string sample_file;  // lem_sample's HDF5 file
  PhaseTable phases;        // bond moduli of a sample file's phases
  RandomLatticeSpec random;
  /// Random lattices: made on rank 0, or by every rank (lem/lattice/cell_lattice.hpp).
  LatticeGenerator generator = LatticeGenerator::serial;
  std::array<int, 3> fcc_cells{4, 4, 4};
  InclusionType inclusion_type = InclusionType::none;
  InclusionSpec inclusions;
  double inclusion_stiffness_ratio = 10.0;
  bool pore_needs_both_ends = false;  // void-bond rule, see carve_pores()
  bool halve_face_bonds = false;      // random and sample lattices, see halve_face_bonds()
  /// Sample file only: every bond (void and interface ones too) gets the
  /// particle phase -- the homogeneous lattice of the same geometry that
  /// calibrates E^[p] and sigma^[p] (paper sect. 3).
  bool homogeneous = false;
  /// Sample file only: set it up in parallel (lem/setup/parallel_setup.hpp).
  bool parallel = false;
};
SampleOptions read_sample_options(MPI_Comm comm);

/// Facts about the built sample, known on every rank after setup.
struct SampleInfo {
  LatticeStats stats;                  // of the lattice before inclusions
  AffineModuli affine;                 // of the sample as built (with inclusions)
  double inclusion_fraction = 0;       // geometric, exact
  double inclusion_node_fraction = 0;  // share of nodes inside inclusions
  std::int64_t inclusion_count = 0;
  CementedSampleStats cemented{};  // of a sample file (zero otherwise)
};

/// Build (or read) the sample on the calling rank (normally rank 0).  A
/// sample file's bonds get k = E^phase a with a the mean bond length of its
/// whole lattice (void bonds included), as in the paper.
Lattice build_sample(const SampleOptions& options, SampleInfo& info);

/// Counts and timings of the set-up stages, identical on every rank.
struct SetupReport {
  SampleInfo sample;
  std::int64_t active_bonds = 0, pruned_bonds = 0, pinned_nodes = 0;
  std::int64_t bottom_nodes = 0, top_nodes = 0, edge_cut = 0;
  double seconds_build = 0, seconds_constraints = 0, seconds_partition = 0, seconds_distribute = 0;
};

/// Named errors before any work for a lattice that cannot run here: more
/// displacements than PETSc's indices number, or more memory than the
/// machines of the job have available (an estimate per bond).  A sample
/// file's sizes come from its attributes.  Collective.
void check_lattice_fits(MPI_Comm comm, const SampleOptions& options);

/// The tension lattice of these options (checked by check_lattice_fits
/// first): setup_tension_lattice of build_sample, or
/// setup_sample_in_parallel for a sample file with `parallel` set, or
/// setup_generated_in_parallel for the cells generator.  Collective.
DistributedLattice setup_sample_lattice(MPI_Comm comm, const SampleOptions& options,
                                        SetupReport& report);

/// Run `build` on rank 0, add the tension constraints, partition over the
/// ranks of `comm` and scatter.  Errors on rank 0 are raised on every rank.
DistributedLattice setup_tension_lattice(MPI_Comm comm,
                                         const std::function<Lattice(SampleInfo&)>& build,
                                         SetupReport& report, bool morton = true);

}  // namespace lem
