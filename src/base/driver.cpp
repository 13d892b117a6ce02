#include "lem/driver.hpp"

#include "lem/error.hpp"

#include <petscsys.h>

#include <cstdio>

namespace lem {

int run_driver(int argc, char** argv, const char* help,
               const std::function<void(MPI_Comm)>& body) {
  if (PetscInitialize(&argc, &argv, nullptr, help)) return 3;
  int status = 0;
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  try {
    body(PETSC_COMM_WORLD);
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
  return status;
}

}  // namespace lem
