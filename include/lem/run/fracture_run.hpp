// A whole lem_fracture run around the protocol (lem/protocol/fracture.hpp): the
// sample prepared (thresholds of generated lattices, disorder), the units
// decided, sigma^[p] and E^[p] calibrated on the homogeneous lattice or
// read from their store, the protocol run in its result folder
// (result_folder.hpp), and the summary committed with the result.
#pragma once

#include "lem/system/elastic_system.hpp"
#include "lem/protocol/fracture.hpp"
#include "lem/base/provenance.hpp"
#include "lem/setup/setup.hpp"

#include <mpi.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace lem {

/// How a fracture run is normalised and where it writes ("Fracture run and
/// output"; the protocol's own options are FractureOptions).
struct FractureRunOptions {
  double break_strain = 1e-3;               // generated lattices: f = k a eps_b
  bool calibrate = true;                    // sample files: sigma^[p], E^[p] first
  std::string calibration_file;             // "": beside the sample, named by a hash
  double sigma_unit = 0, modulus_unit = 0;  // given units (0: calibrate)
  std::string output_dir = "results/fracture";
  bool overwrite = false;
  bool fields = true;               // fields.h5 and elastic.h5
  std::int64_t snapshot_steps = 0;  // fields every this many load steps
};

/// Read the "Fracture run and output" options (also -output_write_grace).
FractureRunOptions read_fracture_run_options(MPI_Comm comm);

/// The run: nothing if the folder holds its finished result already.
/// Collective.  Throws InputError for bad input (before the folder is
/// touched), NumericalError, Interrupted after a stop request (the same
/// call resumes).
void run_fracture_job(MPI_Comm comm, const SampleOptions& sample, const FractureOptions& protocol,
                      const FractureRunOptions& run, const SolverOptions& solver,
                      const Provenance& provenance);

/// A file that a program adds to each of its lem_fracture results
/// (docs/developer/extending.md, "An output").
struct FractureOutputEntry {
  std::string file;  // its name in the result folder, e.g. "damage_profile.csv"
  /// Writes it at the end of the sample's run (not the calibration's),
  /// collectively, from the broken lattice and the run's result.  `path` is
  /// in the folder being written: the commit lists the file in the manifest
  /// and a run that does not finish leaves nothing that looks complete.
  std::function<void(const DistributedLattice& lattice, const FractureResult& result,
                     const std::string& path)>
      write;
};

/// Add one before fracture_program reads the options (std::invalid_argument
/// if its file is one lem_fracture writes or already registered).
void register_fracture_output(FractureOutputEntry entry);
const std::vector<FractureOutputEntry>& fracture_outputs();

/// The whole program lem_fracture (its main): the options read, then the
/// job, inside the driver frame that turns errors and stop requests into
/// exit statuses.  A program that registers its own break rules or
/// relaxation schemes (registry.hpp) calls it after registering them.
int fracture_program(int argc, char** argv, const char* help);

}  // namespace lem
