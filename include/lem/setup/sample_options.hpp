// Options of cemented samples, shared by every driver that builds or loads
// one: the packing (-pack_*), the sample and its lattice (-sample_*,
// -lattice_*), the matrix (-matrix_*) and the bond properties per phase
// (-phase_*).
#pragma once

#include "lem/sample/cemented_sample.hpp"
#include "lem/lattice/lattice.hpp"
#include "lem/base/options.hpp"
#include "lem/packing/packing.hpp"

#include <mpi.h>

#include <cstdint>

namespace lem {

/// The -pack_* options of the periodic packing (everything but the cube
/// cut).  -pack_particles defaults to 0 = "auto": the caller resolves it
/// with auto_packing_count() once the sample's particle count is known, so
/// a spec with count 0 is returned unless the option was given.
PackingSpec read_packing_spec(MPI_Comm comm);

/// Spheres in the periodic box for a cube holding `sample_particles`
/// centres: twice as many, rounded to the nearest hundred, at least 100
/// (516 -> 1000, the paper's set-up).
std::int64_t auto_packing_count(std::int64_t sample_particles);

/// The whole recipe of a cemented sample: read_packing_spec (with the count
/// resolved), -sample_particles, the random lattice (-lattice_nodes /
/// -lattice_bonds / -lattice_Ln, default 2520 bonds per sample particle,
/// i.e. the paper's 1.3e6 bonds for 516; -lattice_seed,
/// -lattice_min_separation), the matrix (-matrix_fraction,
/// -matrix_max_gap, -matrix_max_lambda) and the void rule of the bond phases
/// (-sample_void_bonds).
CementedSampleSpec read_cemented_sample_spec(MPI_Comm comm);

/// -phase_E_* and -phase_sigma_*: bond moduli and breaking stresses per
/// phase in the paper's stress units.
PhaseTable read_phase_table(MPI_Comm comm);

/// The size, seed and separation of a random lattice (-lattice_nodes,
/// -lattice_bonds, -lattice_Ln, -lattice_min_separation, -lattice_seed),
/// read into `spec` within the caller's option group; the box and the
/// stiffness are left alone.  Returns false if no size was given (the three
/// sizes are then 0 and the caller picks its default).
bool read_random_lattice_options(OptionGroup& group, RandomLatticeSpec& spec);

/// -lattice_generator (serial or cells), within the caller's option group.
LatticeGenerator read_lattice_generator(OptionGroup& group);

/// -lattice_face_bonds (whole or halved), within the caller's option group:
/// true if the bonds lying in the box faces are to be halved
/// (halve_face_bonds) in random and sample lattices.
bool read_face_bond_option(OptionGroup& group);

}  // namespace lem
