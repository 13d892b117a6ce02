// Who/what/when produced a result file; stored with every output.
#pragma once

#include <mpi.h>

#include <string>

namespace lem {

struct Provenance {
  std::string program;      // driver name
  std::string version;      // project version
  std::string git_hash;     // source revision
  std::string options;      // the whole PETSc options database, one option per line
  std::string start_time;   // ISO 8601, UTC
  int ranks = 1;
};

/// Collective: rank 0's clock and options database, on every rank.
Provenance collect_provenance(MPI_Comm comm, const std::string& program);

}  // namespace lem
