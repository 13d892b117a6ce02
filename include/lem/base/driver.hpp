// What every executable does around its work: PETSc start-up, one clear
// message and a non-zero exit status for bad input or a failed solve.
#pragma once

#include "lem/base/log.hpp"  // say, for older includers

#include <mpi.h>

#include <functional>
#include <vector>

namespace lem {

/// What SIGTERM and SIGUSR1 do to a driver: end it (the default action), or
/// ask it to save its state and exit 4 (stop.hpp; the driver reads the
/// request at its stop points).
enum class StopHandling { end_process, save_and_exit };

/// Exit codes (exit_status in error.hpp): 0 success, 1 bad input,
/// 2 numerical failure, 3 other error, 4 stopped by a signal after a
/// checkpoint (rerun to resume).  With StopHandling::save_and_exit the stop
/// handler lives from before PetscInitialize to the return, and a stop
/// signal that no stop point saw turns a success into exit 4 too: the work
/// was complete, so running the same command again has nothing to redo.
int run_driver(int argc, char** argv, const char* help, const std::function<void(MPI_Comm)>& body,
               StopHandling stops = StopHandling::end_process);

/// The peak resident set size of every rank of `comm` since its process
/// started, in MB (getrusage), in rank order.  Collective.
std::vector<double> peak_memory_per_rank_mb(MPI_Comm comm);
/// Their largest and their mean, in MB.  Collective.
struct PeakMemory {
  double max_mb = 0, mean_mb = 0;
};
PeakMemory peak_memory(MPI_Comm comm);

/// `bytes` asked for by each rank against its machine's MemAvailable: for
/// the machine where the ranks' sum is the largest share of it, that sum,
/// what it has available (0 if /proc/meminfo does not say) and its rank
/// count.  Every rank gets the same answer.  Collective.
struct MachineMemory {
  double need = 0, available = 0;
  int ranks = 1;
  bool fits(double share = 1.0) const { return available <= 0 || need <= share * available; }
};
MachineMemory tightest_machine(MPI_Comm comm, double bytes);

}  // namespace lem
