#include "lem/setup/setup.hpp"

#include "lem/base/driver.hpp"
#include "lem/base/error.hpp"
#include "lem/base/files.hpp"
#include "lem/base/log.hpp"
#include "lem/base/options.hpp"
#include "lem/setup/parallel_setup.hpp"
#include "lem/system/partition.hpp"
#include "lem/sample/sample_reader.hpp"
#include "lem/setup/sample_options.hpp"
#include "lem/system/tension.hpp"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <string>
#include <utility>

namespace lem {

namespace {

// Options that generate a lattice or change it: a sample file fixes both.
const char* const kGenerationOptions[] = {
    "-lattice_type",        "-lattice_box",    "-lattice_nodes",
    "-lattice_bonds",       "-lattice_Ln",     "-lattice_min_separation",
    "-lattice_seed",        "-lattice_k",      "-lattice_generator",
    "-fcc_cells",           "-inclusion_type", "-inclusion_fraction",
    "-inclusion_radius",    "-inclusion_seed", "-inclusion_stiffness_ratio",
    "-inclusion_void_bonds"};

// PETSc numbers the three displacements of every node with PetscInt.
void check_petsc_indices(std::int64_t nodes) {
  const auto dofs = 3 * static_cast<std::uint64_t>(nodes);
  if (dofs > static_cast<std::uint64_t>(PETSC_MAX_INT))
    throw InputError("the lattice has " + std::to_string(nodes) +
                     " nodes: " + std::to_string(dofs) + " displacements, more than this PETSc's " +
                     std::to_string(8 * sizeof(PetscInt)) + "-bit indices can number (" +
                     std::to_string(PETSC_MAX_INT) +
                     "); build against a PETSc configured "
                     "with 64-bit indices");
}

// What a run needs per bond of its lattice at least, over all its ranks,
// and what the serial set-up holds on rank 0 on top of that while it builds
// and scatters the lattice.  A floor, so that what is refused surely would
// not fit: measured on 2 ranks (docs/scaling.md, docs/benchmarks.md), one
// elastic solve takes 630 bytes per bond at 10^7 bonds and 800 at 3*10^7
// (the largest that fits this machine's 24 GB), a fracture run 960 at 10^7.
constexpr double kRunBytesPerBond = 400;
constexpr double kSerialSetupBytesPerBond = 150;

// Counts of the lattice the options describe: from a sample file's
// attributes (rank 0), or from the generation options.
std::pair<std::int64_t, std::int64_t> lattice_size(MPI_Comm comm, const SampleOptions& o) {
  std::int64_t size[2] = {0, 0};
  if (!o.sample_file.empty()) {
    run_on_root(comm, [&] {
      const SampleFile d = read_sample_description(o.sample_file);
      size[0] = d.sample.stats.nodes;
      size[1] = d.sample.stats.bonds;
    });
    MPI_Bcast(size, 2, MPI_INT64_T, 0, comm);
  } else if (o.lattice_type == LatticeType::fcc) {
    std::int64_t sites = 1;
    for (int c : o.fcc_cells) sites *= 2 * static_cast<std::int64_t>(c) + 1;
    size[0] = (sites + 1) / 2;
    size[1] = 6 * size[0];
  } else {
    size[0] = target_node_count(o.random);
    size[1] = (size[0] * 772) / 100;  // at most 7.72 bonds per node (nodes_for_bond_count)
  }
  return {size[0], size[1]};
}

}  // namespace

void check_lattice_fits(MPI_Comm comm, const SampleOptions& o) {
  const auto [nodes, bonds] = lattice_size(comm, o);
  check_petsc_indices(nodes);
  int rank = 0, ranks = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &ranks);
  const bool serial = !o.parallel && o.generator == LatticeGenerator::serial;
  double mine = kRunBytesPerBond * static_cast<double>(bonds) / ranks;
  if (rank == 0 && serial) mine += kSerialSetupBytesPerBond * static_cast<double>(bonds);
  const MachineMemory m = tightest_machine(comm, mine);
  if (!m.fits()) {
    char text[400];
    std::snprintf(text, sizeof(text),
                  "the lattice of %lld nodes and %lld bonds needs about %.3g GB on this "
                  "machine (%d of the job's ranks; an estimate: %.0f bytes per bond over the "
                  "run%s), but %.3g GB are available: run it on more machines%s",
                  static_cast<long long>(nodes), static_cast<long long>(bonds), m.need / 1e9,
                  m.ranks, kRunBytesPerBond,
                  serial ? ", and 150 per bond more on rank 0 for the serial set-up" : "",
                  m.available / 1e9,
                  serial && !o.sample_file.empty() ? " or with -sample_parallel" : "");
    throw InputError(text);
  }
}

SampleOptions read_sample_options(MPI_Comm comm) {
  SampleOptions o;
  {
    OptionGroup g(comm, "Cemented sample file");
    o.sample_file = g.string("-sample_file",
                             "HDF5 sample written by lem_sample (e.g. "
                             "meshes/tiny.h5); replaces the -lattice_* and -inclusion_* "
                             "generation, bond moduli from -phase_E_*",
                             "");
    o.parallel = g.flag("-sample_parallel",
                        "Set the sample file up in parallel: every rank "
                        "reads its share of the rows, the lattice is partitioned by spatial "
                        "cells and constrained in parallel (no rank holds the whole sample)",
                        false);
    if (o.parallel && o.sample_file.empty())
      throw InputError("option -sample_parallel sets up a sample file: it needs -sample_file");
    // HDF5 would wait on a pipe for a writer, deaf to stop signals.
    if (const std::string what = not_a_regular_file(o.sample_file); !what.empty())
      throw InputError("option -sample_file = '" + o.sample_file + "': " + what +
                       ", not a "
                       "sample file (HDF5 files are read by position: give a regular file)");
    if (!o.sample_file.empty())
      for (const char* name : kGenerationOptions)
        if (g.given(name))
          throw InputError("option " + std::string(name) +
                           " cannot be combined with "
                           "-sample_file '" +
                           o.sample_file +
                           "': the sample file fixes the "
                           "lattice and its phases (bond moduli: -phase_E_*)");
  }
  o.phases = read_phase_table(comm);
  // Asked of the options database: a value equal to the default is given too.
  if (o.sample_file.empty())
    for (const OptionRecord& r : registered_options())
      if (r.given && r.name.rfind("-phase_", 0) == 0)
        throw InputError("option " + r.name +
                         " sets the bonds of a cemented sample and needs "
                         "-sample_file");
  {
    OptionGroup g(comm, "Lattice");
    o.lattice_type =
        g.choice<LatticeType>("-lattice_type", "Lattice geometry",
                              {{"random", LatticeType::random}, {"fcc", LatticeType::fcc}},
                              LatticeType::random);
    const auto box = g.positive_reals("-lattice_box", "Box side lengths Lx,Ly,Lz", {1.0, 1.0, 1.0});
    for (int a = 0; a < 3; ++a) o.random.box.hi[a] = box[a];
    if (!read_random_lattice_options(g, o.random)) o.random.nodes = 20000;
    o.random.stiffness =
        g.real("-lattice_k", "Hooke constant k of the bonds", 1.0, 0.0, 1e300, true);
    o.generator = read_lattice_generator(g);
    if (o.generator == LatticeGenerator::cells && o.lattice_type != LatticeType::random)
      throw InputError("option -lattice_generator cells makes random lattices: not with "
                       "-lattice_type fcc");
    const int cells =
        static_cast<int>(g.integer("-fcc_cells", "FCC lattice: unit cells per axis", 4, 1, 400));
    o.fcc_cells = {cells, cells, cells};
    o.halve_face_bonds = read_face_bond_option(g);
    if (o.lattice_type == LatticeType::fcc && g.given("-lattice_face_bonds"))
      throw InputError("option -lattice_face_bonds applies to random and sample lattices: the "
                       "FCC block always halves its face bonds");
    if (!o.sample_file.empty()) o.lattice_type = LatticeType::sample;
  }
  {
    OptionGroup g(comm, "Inclusions (two-phase samples)");
    o.inclusion_type = g.choice<InclusionType>("-inclusion_type", "Spherical inclusions",
                                               {{"none", InclusionType::none},
                                                {"stiff", InclusionType::stiff},
                                                {"pore", InclusionType::pore}},
                                               InclusionType::none);
    o.inclusions.volume_fraction =
        g.real("-inclusion_fraction", "Volume fraction of inclusions", 0.2, 0.0, 0.6, true);
    o.inclusions.radius = g.real("-inclusion_radius", "Inclusion radius / smallest box side", 0.1,
                                 0.0, 0.5, true, true);
    o.inclusions.seed = static_cast<std::uint64_t>(
        g.integer("-inclusion_seed", "Random seed of the inclusion centres", 7, 0, PETSC_MAX_INT));
    o.inclusion_stiffness_ratio = g.real("-inclusion_stiffness_ratio",
                                         "k inside stiff inclusions "
                                         "/ k of the matrix",
                                         10.0, 0.0, 1e6, true);
    o.pore_needs_both_ends = g.choice<bool>(
        "-inclusion_void_bonds",
        "Which bonds a pore removes (the paper states only f^v = 0): "
        "any_end = every bond with an end in a pore, both_ends = only bonds with both ends in "
        "it; any and both are older spellings",
        {{"any_end", false}, {"both_ends", true}, {"any", false}, {"both", true}}, false);
    if (o.inclusion_type != InclusionType::none && o.generator == LatticeGenerator::cells)
      throw InputError("option -inclusion_type " +
                       std::string(o.inclusion_type == InclusionType::stiff ? "stiff" : "pore") +
                       " needs the whole lattice on one rank: not with -lattice_generator cells");
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
  check_lattice_fits(comm, o);
  if (o.parallel) return setup_sample_in_parallel(comm, o, report);
  if (o.generator == LatticeGenerator::cells) return setup_generated_in_parallel(comm, o, report);
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
    check_petsc_indices(static_cast<std::int64_t>(lattice.node_count()));
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
