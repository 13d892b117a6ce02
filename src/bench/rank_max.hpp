// What the benchmark's timings share: a figure is the slowest rank's.
#pragma once

#include <mpi.h>

namespace lem {

/// The largest `mine` over the ranks, on every rank.
inline double max_over(MPI_Comm comm, double mine) {
  double m = 0;
  MPI_Allreduce(&mine, &m, 1, MPI_DOUBLE, MPI_MAX, comm);
  return m;
}

}  // namespace lem
