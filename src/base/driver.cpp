#include "lem/driver.hpp"

#include "lem/error.hpp"

#include <petscsys.h>

#include <cstdarg>
#include <cstdio>

namespace lem {

void say(const char* format, ...) {
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank != 0) return;
  va_list args;
  va_start(args, format);
  std::vfprintf(stdout, format, args);
  va_end(args);
  std::fflush(stdout);
}

int run_driver(int argc, char** argv, const char* help,
               const std::function<void(MPI_Comm)>& body) {
  if (PetscInitialize(&argc, &argv, nullptr, help)) return 3;
  int status = 0;
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  auto report = [&](const char* kind, const char* what) {
    if (rank == 0) std::fprintf(stderr, "%s: %s\n", kind, what);
  };
  try {
    body(PETSC_COMM_WORLD);
  } catch (const HelpShown& e) {
    if (rank == 0) std::printf("\n%s\n", e.what());
  } catch (const InputError& e) {
    report("error", e.what());
    status = 1;
  } catch (const Interrupted& e) {
    report("interrupted", e.what());
    status = 4;
  } catch (const NumericalError& e) {
    report("numerical failure", e.what());
    status = 2;
  } catch (const std::exception& e) {
    report("failure", e.what());
    status = 3;
  }
  PetscFinalize();
  return status;
}

}  // namespace lem
