// Who/what/when produced a result file; stored with every output.
#pragma once

#include <mpi.h>

#include <string>

namespace lem {

struct Provenance {
  std::string program;     // driver name
  std::string version;     // project version
  std::string git_hash;    // source revision
  std::string options;     // the whole PETSc options database, one option per line
  std::string start_time;  // ISO 8601, UTC
  int ranks = 1;
};

/// "<program> (lem3d) <version>, git <hash>" and the PETSc version it was
/// built with, one per line: what -version prints.
std::string version_text(const std::string& program);
/// -version (or --version) among the arguments.
bool version_requested(int argc, char** argv);

/// This machine's clock now, ISO 8601 UTC.
std::string iso8601_utc_now();

/// Collective: rank 0's clock and options database, on every rank.
Provenance collect_provenance(MPI_Comm comm, const std::string& program);

}  // namespace lem
