#include "lem/driver.hpp"

#include "lem/error.hpp"
#include "lem/options.hpp"

#include <petscsys.h>

#include <cstdio>
#include <string>

namespace lem {

int run_driver(int argc, char** argv, const char* help,
               const std::function<void(MPI_Comm)>& body) {
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
  take_over_petsc_errors();
  int status = 0;
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  {
    RankEnds ends(PETSC_COMM_WORLD);
    std::string message;
    try {
      body(PETSC_COMM_WORLD);
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
  return status;
}

}  // namespace lem
