// Error handling shared by every module.
//
// Bad input is reported by throwing InputError with a message that names the
// option or file, the value, and what is allowed.  Drivers catch it in
// lem::run_driver (driver.hpp), print it once on rank 0 and exit with the
// error's status (exit_status).
//
// An error seen by some ranks only must become the same error on every rank
// before anyone leaves a collective stage, or the others wait forever.
// agree_on_error is the one way to do that: every rank throws the error of
// the lowest failing rank, of the same type, so the exit status is the same
// as in a serial run.
#pragma once

#include <mpi.h>
#include <petscsys.h>

#include <exception>
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
  /// The same failure on another rank (collective agreement).
  explicit PetscFailure(const std::string& message) : std::runtime_error(message) {}
};

/// Results could not be written (full disk, failed write, close, sync or
/// rename).  The message names the file; exit status 3.
class IoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
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

/// A driver's exit status for `error`: 1 InputError, 2 NumericalError,
/// 4 Interrupted, 0 HelpShown, 3 anything else (IoError among them).
int exit_status(const std::exception& error);

/// Collective: if `error` is set on any rank, every rank throws the error of
/// the lowest such rank (that rank rethrows its own; the others a copy of the
/// same type and message: InputError, IoError, NumericalError, Interrupted,
/// HelpShown, PetscFailure, std::invalid_argument, std::logic_error, else
/// std::runtime_error).  Returns normally on every rank when no rank failed.
void agree_on_error(MPI_Comm comm, const std::exception_ptr& error);

/// Run `work` on every rank, then agree on its errors (agree_on_error).
void run_collectively(MPI_Comm comm, const std::function<void()>& work);

/// Run `work` on rank 0 only while the other ranks wait, then agree on its
/// errors, so that serial stages (generation, partitioning) fail together.
void run_on_root(MPI_Comm comm, const std::function<void()>& work);

}  // namespace lem
