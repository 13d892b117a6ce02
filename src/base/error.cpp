#include "lem/error.hpp"

#include "lem/collective.hpp"

#include <stdexcept>
#include <string>
#include <vector>

namespace lem {

PetscFailure::PetscFailure(const char* call, PetscErrorCode code)
    : std::runtime_error(std::string("PETSc error ") + std::to_string(code) + " in " + call) {}

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
    case ErrorType::input: throw InputError(message);
    case ErrorType::io: throw IoError(message);
    case ErrorType::numerical: throw NumericalError(message);
    case ErrorType::interrupted: throw Interrupted(message);
    case ErrorType::help: throw HelpShown(message);
    case ErrorType::petsc: throw PetscFailure(message);
    case ErrorType::invalid_argument: throw std::invalid_argument(message);
    case ErrorType::logic: throw std::logic_error(message);
    case ErrorType::other: break;
  }
  throw std::runtime_error(message);
}

}  // namespace

int exit_status(const std::exception& error) {
  switch (classify(error)) {
    case ErrorType::help: return 0;
    case ErrorType::input: return 1;
    case ErrorType::numerical: return 2;
    case ErrorType::interrupted: return 4;
    default: return 3;
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
  broadcast_value(comm, type, first);
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

}  // namespace lem
