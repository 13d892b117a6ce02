#include "lem/setup.hpp"

#include "lem/error.hpp"
#include "lem/log.hpp"
#include "lem/options.hpp"
#include "lem/parallel_setup.hpp"
#include "lem/partition.hpp"
#include "lem/sample_file.hpp"
#include "lem/sample_options.hpp"
#include "lem/tension.hpp"

#include <algorithm>
#include <cstring>

namespace lem {

namespace {

// Options that generate a lattice or change it: a sample file fixes both.
const char* const kGenerationOptions[] = {
    "-lattice_type", "-lattice_box", "-lattice_nodes", "-lattice_bonds", "-lattice_Ln",
    "-lattice_min_separation", "-lattice_seed", "-lattice_k", "-fcc_cells", "-inclusion_type",
    "-inclusion_fraction", "-inclusion_radius", "-inclusion_seed", "-inclusion_stiffness_ratio",
    "-inclusion_void_bonds"};

}  // namespace

SampleOptions read_sample_options(MPI_Comm comm) {
  SampleOptions o;
  {
    OptionGroup g(comm, "Cemented sample file");
    o.sample_file = g.string("-sample_file", "HDF5 sample written by lem_sample (e.g. "
                             "meshes/tiny.h5); replaces the -lattice_* and -inclusion_* "
                             "generation, bond moduli from -phase_E_*", "");
    o.parallel = g.flag("-sample_parallel", "Set the sample file up in parallel: every rank "
                        "reads its share of the rows, the lattice is partitioned by spatial "
                        "cells and constrained in parallel (no rank holds the whole sample)",
                        false);
    if (o.parallel && o.sample_file.empty())
      throw InputError("option -sample_parallel sets up a sample file: it needs -sample_file");
    if (!o.sample_file.empty())
      for (const char* name : kGenerationOptions)
        if (g.given(name))
          throw InputError("option " + std::string(name) + " cannot be combined with "
                           "-sample_file '" + o.sample_file + "': the sample file fixes the "
                           "lattice and its phases (bond moduli: -phase_E_*)");
  }
  o.phases = read_phase_table(comm);
  // Asked of the options database: a value equal to the default is given too.
  if (o.sample_file.empty())
    for (const OptionRecord& r : registered_options())
      if (r.given && r.name.rfind("-phase_", 0) == 0)
        throw InputError("option " + r.name + " sets the bonds of a cemented sample and needs "
                         "-sample_file");
  {
    OptionGroup g(comm, "Lattice");
    o.lattice_type = g.choice<LatticeType>("-lattice_type", "Lattice geometry",
                                           {{"random", LatticeType::random}, {"fcc", LatticeType::fcc}},
                                           LatticeType::random);
    const auto box = g.positive_reals("-lattice_box", "Box side lengths Lx,Ly,Lz", {1.0, 1.0, 1.0});
    for (int a = 0; a < 3; ++a) o.random.box.hi[a] = box[a];
    if (!read_random_lattice_options(g, o.random)) o.random.nodes = 20000;
    o.random.stiffness = g.real("-lattice_k", "Hooke constant k of the bonds", 1.0, 0.0, 1e300, true);
    const int cells = static_cast<int>(g.integer("-fcc_cells", "FCC lattice: unit cells per axis",
                                                 4, 1, 400));
    o.fcc_cells = {cells, cells, cells};
    o.halve_face_bonds = read_face_bond_option(g);
    if (o.lattice_type == LatticeType::fcc && g.given("-lattice_face_bonds"))
      throw InputError("option -lattice_face_bonds applies to random and sample lattices: the "
                       "FCC block always halves its face bonds");
    if (!o.sample_file.empty()) o.lattice_type = LatticeType::sample;
  }
  {
    OptionGroup g(comm, "Inclusions (two-phase samples)");
    o.inclusion_type = g.choice<InclusionType>(
        "-inclusion_type", "Spherical inclusions",
        {{"none", InclusionType::none}, {"stiff", InclusionType::stiff}, {"pore", InclusionType::pore}},
        InclusionType::none);
    o.inclusions.volume_fraction = g.real("-inclusion_fraction", "Volume fraction of inclusions",
                                          0.2, 0.0, 0.6, true);
    o.inclusions.radius = g.real("-inclusion_radius", "Inclusion radius / smallest box side", 0.1,
                                 0.0, 0.5, true, true);
    o.inclusions.seed = static_cast<std::uint64_t>(
        g.integer("-inclusion_seed", "Random seed of the inclusion centres", 7, 0, PETSC_MAX_INT));
    o.inclusion_stiffness_ratio = g.real("-inclusion_stiffness_ratio", "k inside stiff inclusions "
                                         "/ k of the matrix", 10.0, 0.0, 1e6, true);
    o.pore_needs_both_ends = g.choice<bool>(
        "-inclusion_void_bonds", "Which bonds a pore removes (the paper states only f^v = 0): "
        "any_end = every bond with an end in a pore, both_ends = only bonds with both ends in "
        "it; any and both are older spellings",
        {{"any_end", false}, {"both_ends", true}, {"any", false}, {"both", true}}, false);
  }
  return o;
}

Lattice build_sample(const SampleOptions& o, SampleInfo& info) {
  Lattice lattice;
  if (!o.sample_file.empty()) {
    CementedSample sample = read_sample(o.sample_file);
    if (o.homogeneous) std::fill(sample.bond_phase.begin(), sample.bond_phase.end(), Phase::p);
    lattice = mechanical_lattice(sample, o.phases);
    if (o.halve_face_bonds) halve_face_bonds(lattice);
    // Statistics (and a) of the whole lattice, void bonds included.
    info.stats = lattice_stats(sample.lattice);
    info.cemented = sample.stats;
    info.affine = affine_moduli(lattice);
    return lattice;
  }
  if (o.lattice_type == LatticeType::fcc) {
    // Bond length a = 1 (the cube side is sqrt 2).
    lattice = make_fcc_lattice(o.fcc_cells, 1.0, o.random.stiffness);
  } else {
    lattice = make_random_lattice(o.random);
    if (o.halve_face_bonds) halve_face_bonds(lattice);
  }
  info.stats = lattice_stats(lattice);
  if (o.inclusion_type != InclusionType::none) {
    const Inclusions inc = place_inclusions(lattice.box, o.inclusions);
    info.inclusion_fraction = inc.volume_fraction();
    info.inclusion_node_fraction = node_fraction_inside(lattice, inc);
    info.inclusion_count = static_cast<std::int64_t>(inc.centres.size());
    if (o.inclusion_type == InclusionType::stiff)
      stiffen_inclusions(lattice, inc, o.inclusion_stiffness_ratio);
    else
      carve_pores(lattice, inc, o.pore_needs_both_ends);
  }
  info.affine = affine_moduli(lattice);
  return lattice;
}

DistributedLattice setup_sample_lattice(MPI_Comm comm, const SampleOptions& o,
                                        SetupReport& report) {
  if (o.parallel) return setup_sample_in_parallel(comm, o, report);
  return setup_tension_lattice(
      comm, [&](SampleInfo& info) { return build_sample(o, info); }, report);
}

DistributedLattice setup_tension_lattice(MPI_Comm comm,
                                         const std::function<Lattice(SampleInfo&)>& build,
                                         SetupReport& report, bool morton) {
  LogStageScope stage("Sample setup");
  int size = 1;
  MPI_Comm_size(comm, &size);
  Lattice lattice;
  TensionConstraints constraints;
  Partition partition;
  std::vector<std::uint8_t> faces;
  run_on_root(comm, [&] {
    double t = MPI_Wtime();
    lattice = build(report.sample);
    report.seconds_build = MPI_Wtime() - t;
    // PETSc numbers the three displacements of every node with PetscInt.
    const auto dofs = 3 * static_cast<std::uint64_t>(lattice.node_count());
    if (dofs > static_cast<std::uint64_t>(PETSC_MAX_INT))
      throw InputError("the lattice has " + std::to_string(lattice.node_count()) + " nodes: " +
                       std::to_string(dofs) + " displacements, more than this PETSc's " +
                       std::to_string(8 * sizeof(PetscInt)) + "-bit indices can number (" +
                       std::to_string(PETSC_MAX_INT) + "); build against a PETSc configured "
                       "with 64-bit indices");
    t = MPI_Wtime();
    faces = face_flags(lattice);
    constraints = make_tension_constraints(lattice, faces);
    report.seconds_constraints = MPI_Wtime() - t;
    t = MPI_Wtime();
    partition = partition_lattice(lattice, constraints.bond_active, size, morton);
    report.seconds_partition = MPI_Wtime() - t;
    report.pruned_bonds = constraints.pruned_bonds;
    report.pinned_nodes = constraints.pinned_nodes;
    report.bottom_nodes = constraints.bottom_nodes;
    report.top_nodes = constraints.top_nodes;
    report.edge_cut = partition.edge_cut;
  });
  const double t = MPI_Wtime();
  DistributedLattice dl = distribute_lattice(comm, lattice, constraints, partition, faces);
  report.active_bonds = dl.global_bonds;
  // Free the root's copies before anything else is allocated.
  lattice = Lattice{};
  constraints = TensionConstraints{};
  partition = Partition{};
  report.seconds_distribute = MPI_Wtime() - t;
  // SetupReport is trivially copyable: share the root's values.
  static_assert(std::is_trivially_copyable_v<SetupReport>);
  MPI_Bcast(&report, sizeof(report), MPI_BYTE, 0, comm);
  stage.pop();
  return dl;
}

}  // namespace lem
