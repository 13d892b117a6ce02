// How an error ends the ranks of a driver (run_driver), on 2 ranks; the
// tests (tests/CMakeLists.txt, ranks_*) check the exit status, that the
// message comes once and that the job ends within seconds.
//
//   lem_rank_errors alone     rank 1 fails while rank 0 waits in a barrier
//   lem_rank_errors agreed    rank 1 fails in a collective stage
//   lem_rank_errors root      a numerical failure in a serial stage on rank 0
//   lem_rank_errors petsc     PETSc raises an error on every rank
#include "lem/base/driver.hpp"
#include "lem/base/error.hpp"

#include <petscsys.h>

#include <string>

namespace {

PetscErrorCode petsc_failure(MPI_Comm comm) {
  return PetscError(comm, __LINE__, "petsc_failure", __FILE__, PETSC_ERR_ARG_WRONG,
                    PETSC_ERROR_INITIAL, "injected PETSc error");
}

}  // namespace

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "";
  // The mode is this program's word, not an option: run_driver sees the rest.
  if (argc > 1) {
    for (int i = 2; i < argc; ++i) argv[i - 1] = argv[i];
    argv[--argc] = nullptr;
  }
  return lem::run_driver(argc, argv, "Errors on some ranks (a test).\n", [&](MPI_Comm comm) {
    int rank = 0;
    MPI_Comm_rank(comm, &rank);
    if (mode == "alone") {
      if (rank == 1) throw lem::InputError("injected error on rank 1 alone");
      MPI_Barrier(comm);  // rank 0 never learns of it here
    } else if (mode == "agreed") {
      lem::run_collectively(comm, [&] {
        if (rank == 1) throw lem::InputError("injected error on rank 1, agreed");
      });
    } else if (mode == "root") {
      lem::run_on_root(comm, [] { throw lem::NumericalError("injected numerical failure"); });
    } else if (mode == "petsc") {
      LEM_PETSC(petsc_failure(comm));
    } else {
      throw lem::InputError("mode '" + mode + "': alone, agreed, root or petsc");
    }
  });
}
