// What every executable does around its work: PETSc start-up, one clear
// message and a non-zero exit status for bad input or a failed solve.
#pragma once

#include <mpi.h>

#include <functional>

namespace lem {

/// Exit codes: 0 success, 1 bad input, 2 numerical failure, 3 other error,
/// 4 stopped by a signal after a checkpoint (rerun to resume).
int run_driver(int argc, char** argv, const char* help,
               const std::function<void(MPI_Comm)>& body);

/// printf on rank 0 of PETSC_COMM_WORLD, flushed (progress lines).
void say(const char* format, ...) __attribute__((format(printf, 1, 2)));

}  // namespace lem
