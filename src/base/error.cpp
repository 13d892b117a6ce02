#include "lem/base/error.hpp"

#include "lem/base/collective.hpp"

#include <cctype>
#include <chrono>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace lem {

namespace {

// PETSc's message of the error being raised (take_over_petsc_errors), until
// a PetscFailure takes it.
std::string& petsc_message() {
  static std::string text;
  return text;
}

PetscErrorCode keep_petsc_message(MPI_Comm, int line, const char* function, const char* file,
                                  PetscErrorCode code, PetscErrorType type, const char* message,
                                  void*) {
  // Later calls are the same error passing up through the callers.
  if (type == PETSC_ERROR_REPEAT) return code;
  const char* generic = nullptr;
  PetscErrorMessage(code, &generic, nullptr);
  std::string text = generic ? generic : "";
  // One line: PETSc's messages may run over several, indented.
  std::string words;
  for (const char* c = message ? message : ""; *c; ++c) {
    const bool blank = std::isspace(static_cast<unsigned char>(*c)) != 0;
    if (blank && (words.empty() || words.back() == ' ')) continue;
    words += blank ? ' ' : *c;
  }
  while (!words.empty() && words.back() == ' ') words.pop_back();
  if (!words.empty()) text += (text.empty() ? "" : ": ") + words;
  text += std::string(" (") + (function ? function : "?") + "() at " + (file ? file : "?") + ":" +
          std::to_string(line) + ")";
  petsc_message() = text;
  return code;
}

std::string taken_petsc_message() {
  std::string text;
  text.swap(petsc_message());
  return text.empty() ? text : ": " + text;
}

}  // namespace

PetscFailure::PetscFailure(const char* call, PetscErrorCode code)
    : std::runtime_error(std::string("PETSc error ") + std::to_string(code) + " in " + call +
                         taken_petsc_message()) {}

void take_over_petsc_errors() {
  for (const char* name :
       {"-on_error_abort", "-on_error_attach_debugger", "-on_error_emacs", "-start_in_debugger"}) {
    PetscBool set = PETSC_FALSE;
    if (PetscOptionsHasName(nullptr, nullptr, name, &set) == 0 && set) return;
  }
  PetscPushErrorHandler(keep_petsc_message, nullptr);
}

namespace {

// The error types that travel between ranks (most specific first: classify
// tests them in this order).
enum class ErrorType : int {
  input = 1,
  io,
  numerical,
  interrupted,
  help,
  petsc,
  invalid_argument,
  logic,
  other,
};

ErrorType classify(const std::exception& error) {
  if (dynamic_cast<const InputError*>(&error)) return ErrorType::input;
  if (dynamic_cast<const IoError*>(&error)) return ErrorType::io;
  if (dynamic_cast<const NumericalError*>(&error)) return ErrorType::numerical;
  if (dynamic_cast<const Interrupted*>(&error)) return ErrorType::interrupted;
  if (dynamic_cast<const HelpShown*>(&error)) return ErrorType::help;
  if (dynamic_cast<const PetscFailure*>(&error)) return ErrorType::petsc;
  if (dynamic_cast<const std::invalid_argument*>(&error)) return ErrorType::invalid_argument;
  if (dynamic_cast<const std::logic_error*>(&error)) return ErrorType::logic;
  return ErrorType::other;
}

[[noreturn]] void throw_as(ErrorType type, const std::string& message) {
  switch (type) {
    case ErrorType::input:
      throw InputError(message);
    case ErrorType::io:
      throw IoError(message);
    case ErrorType::numerical:
      throw NumericalError(message);
    case ErrorType::interrupted:
      throw Interrupted(message);
    case ErrorType::help:
      throw HelpShown(message);
    case ErrorType::petsc:
      throw PetscFailure(message);
    case ErrorType::invalid_argument:
      throw std::invalid_argument(message);
    case ErrorType::logic:
      throw std::logic_error(message);
    case ErrorType::other:
      break;
  }
  throw std::runtime_error(message);
}

}  // namespace

int exit_status(const std::exception& error) {
  switch (classify(error)) {
    case ErrorType::help:
      return 0;
    case ErrorType::input:
      return 1;
    case ErrorType::numerical:
      return 2;
    case ErrorType::interrupted:
      return 4;
    default:
      return 3;
  }
}

void agree_on_error(MPI_Comm comm, const std::exception_ptr& error) {
  int rank = 0, ranks = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &ranks);
  const int mine = error ? rank : ranks;
  int first = ranks;
  MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, comm);
  if (first == ranks) return;
  std::string message = "unknown error";
  int type = static_cast<int>(ErrorType::other);
  if (rank == first) {
    try {
      std::rethrow_exception(error);
    } catch (const std::exception& e) {
      type = static_cast<int>(classify(e));
      message = e.what();
    } catch (...) {
    }
  }
  // A plain MPI_Bcast of the int: through broadcast_value's lambda, inlined
  // here, GCC 12's AddressSanitizer reported an 8-byte read of the 4-byte
  // root (jobs/check-sanitizers.sh), in agree_on_error and RankEnds::finish.
  MPI_Bcast(&type, 1, MPI_INT, first, comm);
  std::vector<char> text(message.begin(), message.end());
  broadcast(comm, text, first);
  // The failing rank keeps its own exception (and its exact type).
  if (rank == first) std::rethrow_exception(error);
  throw_as(static_cast<ErrorType>(type), std::string(text.begin(), text.end()));
}

void run_collectively(MPI_Comm comm, const std::function<void()>& work) {
  std::exception_ptr error;
  try {
    work();
  } catch (...) {
    error = std::current_exception();
  }
  agree_on_error(comm, error);
}

void run_on_root(MPI_Comm comm, const std::function<void()>& work) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  run_collectively(comm, [&] {
    if (rank == 0) work();
  });
}

const char* status_label(int status) {
  switch (status) {
    case 1:
      return "error";
    case 2:
      return "numerical failure";
    case 4:
      return "interrupted";
    default:
      return "failure";
  }
}

RankEnds::RankEnds(MPI_Comm comm) { MPI_Comm_dup(comm, &comm_); }

RankEnds::~RankEnds() {
  if (comm_ != MPI_COMM_NULL) MPI_Comm_free(&comm_);
}

int RankEnds::finish(int status, const std::string& message) {
  int rank = 0, ranks = 1;
  MPI_Comm_rank(comm_, &rank);
  MPI_Comm_size(comm_, &ranks);
  MPI_Request arrived = MPI_REQUEST_NULL;
  MPI_Ibarrier(comm_, &arrived);
  const double start = MPI_Wtime();
  for (int done = 0;;) {
    MPI_Test(&arrived, &done, MPI_STATUS_IGNORE);
    if (done) break;
    // A rank that succeeded waits: a failed one ends the job in time.
    if (status != 0 && MPI_Wtime() - start > kGraceSeconds) {
      std::fprintf(stderr, "%s on rank %d (the other ranks did not stop; ending them): %s\n",
                   status_label(status), rank, message.c_str());
      std::fflush(stderr);
      MPI_Abort(MPI_COMM_WORLD, status);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  // Every rank is here: the outcome of the lowest failing one.
  const int mine = status != 0 ? rank : ranks;
  int first = ranks;
  MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, comm_);
  if (first == ranks) return 0;
  int agreed = status;
  MPI_Bcast(&agreed, 1, MPI_INT, first, comm_);  // as in agree_on_error
  const std::string text = broadcast_string(comm_, message, first);
  if (rank == 0) {
    std::fflush(stdout);
    std::fprintf(stderr, "%s: %s\n", status_label(agreed), text.c_str());
    std::fflush(stderr);
  }
  return agreed;
}

}  // namespace lem
