// Error handling shared by every module.
//
// Bad input is reported by throwing InputError with a message that names the
// option or file, the value, and what is allowed.  Drivers catch it in
// lem::run_driver (driver.hpp), print it once on rank 0 and exit non-zero.
#pragma once

#include <mpi.h>
#include <petscsys.h>

#include <functional>
#include <stdexcept>
#include <string>

namespace lem {

/// Invalid user input (options, files, sizes).  The message is shown verbatim.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A PETSc call returned an error code (PETSc has already printed its trace).
class PetscFailure : public std::runtime_error {
 public:
  PetscFailure(const char* call, PetscErrorCode code);
};

/// A numerical failure (diverged solve, NaN) that must stop the run.
class NumericalError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A long run stopped on request (SIGTERM/SIGUSR1) after writing a
/// checkpoint; running the same command again resumes it.
class Interrupted : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// -help was given: the options have been listed (as they were read) and the
/// driver stops before doing any work, with exit status 0.
class HelpShown : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

#define LEM_PETSC(call)                                          \
  do {                                                           \
    PetscErrorCode lem_ierr_ = (call);                           \
    if (lem_ierr_) throw ::lem::PetscFailure(#call, lem_ierr_);  \
  } while (0)

/// Run `work` on rank 0 only while the other ranks wait; if it throws, the
/// exception's message is broadcast and every rank throws the same type, so
/// that serial stages (generation, partitioning) fail collectively.
void run_on_root(MPI_Comm comm, const std::function<void()>& work);

}  // namespace lem
