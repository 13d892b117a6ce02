// sigma^[p] and E^[p], the strength and modulus of the homogeneous lattice
// of a sample's geometry (paper sect. 3), depend only on that lattice, its
// particle phase and the protocol options that change fracture results.
// They are computed once and kept in a small text file with their
// provenance, keyed by a hash of the homogeneous lattice's fingerprint
// (protocol/fingerprint.hpp, FingerprintScope::calibration: the lattice by
// content, the protocol, physics and solver options; the rank count left
// out), so every later run on the same lattice and options reuses them, and
// a calibration made under other physics or solver options has a key of its
// own.  The warnings of the calibration run are kept with the values.
#pragma once

#include "lem/io/hdf5_writer.hpp"

#include <mpi.h>

#include <optional>
#include <string>
#include <vector>

namespace lem {

struct Calibration {
  double sigma_hom = 0, e_hom = 0;    // in E^phase units
  std::vector<std::string> warnings;  // of the calibration run, "code:count"
};

/// 16 hex digits of a hash of the fingerprint without its rank count.
std::string calibration_key(const std::string& fingerprint);

/// The stored calibration at `path` if it belongs to `fingerprint`; nothing
/// when the file does not exist.  A file for another lattice or other
/// options is an InputError naming what differs.  Collective.
std::optional<Calibration> read_calibration(MPI_Comm comm, const std::string& path,
                                            const std::string& fingerprint);

/// Write it (rank 0, atomically) with the fingerprint and the provenance.
void write_calibration(MPI_Comm comm, const std::string& path, const std::string& fingerprint,
                       const Calibration& calibration, const Provenance& provenance);

}  // namespace lem
