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

#define LEM_PETSC(call)                                         \
  do {                                                          \
    PetscErrorCode lem_ierr_ = (call);                          \
    if (lem_ierr_) throw ::lem::PetscFailure(#call, lem_ierr_); \
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

/// Call once PETSc is initialised (run_driver does): from then on PETSc's
/// errors come here instead of to its trace-back handler.  The first message
/// of an error and where it arose are kept for the PetscFailure that follows
/// (its what()); nothing is printed, so the error is reported once, by the
/// driver.  PETSc's own handler prints the trace on the communicator's first
/// rank and makes every other rank sleep 10 s and exit without finalising
/// MPI ("exiting improperly").  Left alone if an -on_error_* option asks for
/// PETSc's behaviour (abort, debugger).
void take_over_petsc_errors();

/// How a driver ends on every rank (run_driver).  Created at start-up
/// (collective: it duplicates `comm`, so that ending never mixes with the
/// collective operations of the work); finish() is then called by every
/// rank with its outcome (0 and "" on success).  The ranks wait for each
/// other on that communicator, rank 0 prints the error of the lowest failing
/// rank once ("<kind>: <message>"), and every rank returns that status.  A
/// rank that failed alone while the others wait in some collective
/// operation of the work (an error they cannot see) does not wait for ever:
/// after kGraceSeconds it prints its message itself and ends the whole job
/// with MPI_Abort and its status.
class RankEnds {
 public:
  static constexpr double kGraceSeconds = 3;
  explicit RankEnds(MPI_Comm comm);
  ~RankEnds();
  RankEnds(const RankEnds&) = delete;
  RankEnds& operator=(const RankEnds&) = delete;
  int finish(int status, const std::string& message);

 private:
  MPI_Comm comm_ = MPI_COMM_NULL;
};

/// "error", "numerical failure", "interrupted" or "failure": how a driver
/// labels an exit status of 1, 2, 4 or another.
const char* status_label(int status);

}  // namespace lem
