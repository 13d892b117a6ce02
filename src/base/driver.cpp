#include "lem/driver.hpp"

#include "lem/error.hpp"
#include "lem/stop.hpp"

#include <petscsys.h>

#include <cstdio>

namespace lem {

int run_driver(int argc, char** argv, const char* help,
               const std::function<void(MPI_Comm)>& body, StopHandling stops) {
  const bool handle_stops = stops == StopHandling::save_and_exit;
  if (handle_stops) install_stop_handler();  // MPI start-up can take a while
  if (PetscInitialize(&argc, &argv, nullptr, help)) return 3;
  if (handle_stops) install_stop_handler();  // in case PETSc took the signals
  int status = 0;
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  try {
    body(PETSC_COMM_WORLD);
    // A request that came after the body's last stop point.
    if (handle_stops)
      if (const int signal = stop_requested(PETSC_COMM_WORLD, "driver_end"))
        throw Interrupted(signal_name(signal) + " came after the work was complete: nothing "
                          "to resume");
  } catch (const HelpShown& e) {
    if (rank == 0) std::printf("\n%s\n", e.what());
  } catch (const std::exception& e) {
    status = exit_status(e);
    const char* kind = status == 1   ? "error"
                       : status == 2 ? "numerical failure"
                       : status == 4 ? "interrupted"
                                     : "failure";
    if (rank == 0) std::fprintf(stderr, "%s: %s\n", kind, e.what());
  }
  PetscFinalize();
  if (handle_stops) {
    install_stop_handler();  // PETSc may have restored the default actions
    // Past the last collective: this rank alone reports it.
    if (status == 0 && stop_signal_received() != 0) {
      std::fprintf(stderr, "interrupted: %s came while the run was ending; its work is "
                   "complete\n", signal_name(stop_signal_received()).c_str());
      status = 4;
    }
  }
  return status;
}

}  // namespace lem
