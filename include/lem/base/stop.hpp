// Stop requests: SIGTERM and SIGUSR1 ask a long run to save its state and end
// with exit status 4 (a batch system's warning before the time limit).
//
// A driver that can save its state installs one handler for the whole
// process (run_driver with StopHandling::save_and_exit, before MPI starts and
// again after PETSc has started): from then to exit the two signals only
// record which one came.  The run reads that record collectively at points
// where its state can be saved (stop_requested), so every rank stops at the
// same point whichever rank got the signal.  Drivers that save nothing keep
// the default action (the signal ends them).
#pragma once

#include <mpi.h>

#include <string>

namespace lem {

/// Record SIGTERM and SIGUSR1 from now on instead of ending the process
/// (SA_RESTART, so an interrupted system call resumes).  Idempotent.
void install_stop_handler();

/// The first stop signal this process got (0: none).  Not collective.
int stop_signal_received();

/// Collective: the stop signal some rank got (the largest number if several;
/// 0: none).  Every rank must call it at the same point of the run.  Runs the
/// test hook of `point` first (fault_pause).
int stop_requested(MPI_Comm comm, const char* point);

/// "SIGTERM", "SIGUSR1", or "signal <n>".
std::string signal_name(int signal);

/// Test hook, collective: if the environment variable LEM_FAULT_PAUSE is
/// `point` or `point:<n>`, the n-th time (default 1) the run passes `point`
/// every rank prints "test hook: paused at <point> ..." (rank 0 also its pid,
/// every rank its own on stderr) and waits until a stop signal reaches some
/// rank, so that a test can signal a run at an exact point (docs/developer/testing.md).
/// The wait ends after 120 s without a signal.  `detail` is added to the
/// message.
void fault_pause(MPI_Comm comm, const char* point, const std::string& detail = "");

}  // namespace lem
