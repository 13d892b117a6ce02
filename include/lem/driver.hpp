// What every executable does around its work: PETSc start-up, one clear
// message and a non-zero exit status for bad input or a failed solve.
#pragma once

#include "lem/log.hpp"  // say, for older includers

#include <mpi.h>

#include <functional>

namespace lem {

/// Exit codes (exit_status in error.hpp): 0 success, 1 bad input,
/// 2 numerical failure, 3 other error, 4 stopped by a signal after a
/// checkpoint (rerun to resume).
int run_driver(int argc, char** argv, const char* help,
               const std::function<void(MPI_Comm)>& body);

}  // namespace lem
