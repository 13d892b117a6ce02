#include "lem/driver.hpp"

#include "lem/error.hpp"
#include "lem/options.hpp"
#include "lem/provenance.hpp"
#include "lem/stop.hpp"

#include <petscsys.h>
#include <sys/resource.h>

#include <cstdio>
#include <filesystem>
#include <string>

namespace lem {

int run_driver(int argc, char** argv, const char* help,
               const std::function<void(MPI_Comm)>& body, StopHandling stops) {
  // -version answers and runs nothing (PETSc's own -version would print
  // only PETSc's and go on with the job).
  if (version_requested(argc, argv)) {
    MPI_Init(&argc, &argv);
    int rank = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    if (rank == 0)
      std::printf("%s", version_text(std::filesystem::path(argv[0]).filename().string()).c_str());
    MPI_Finalize();
    return 0;
  }
  const bool handle_stops = stops == StopHandling::save_and_exit;
  if (handle_stops) install_stop_handler();  // MPI start-up can take a while
  // PETSc cannot start on a missing options file: say which, once.
  const std::string unreadable = unreadable_options_file(argc, argv);
  if (!unreadable.empty()) {
    MPI_Init(&argc, &argv);
    int rank = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    if (rank == 0) std::fprintf(stderr, "%s: %s\n", status_label(1), unreadable.c_str());
    MPI_Finalize();
    return 1;
  }
  if (PetscInitialize(&argc, &argv, nullptr, help)) return 3;
  if (handle_stops) install_stop_handler();  // in case PETSc took the signals
  take_over_petsc_errors();
  int status = 0;
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  {
    RankEnds ends(PETSC_COMM_WORLD);
    std::string message;
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
      message = e.what();
    } catch (...) {
      status = 3;
      message = "an exception of unknown type";
    }
    status = ends.finish(status, message);
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

double peak_memory_mb(MPI_Comm comm) {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  double mine = static_cast<double>(usage.ru_maxrss) / 1024.0, largest = mine;  // kB on Linux
  MPI_Allreduce(&mine, &largest, 1, MPI_DOUBLE, MPI_MAX, comm);
  return largest;
}

}  // namespace lem
