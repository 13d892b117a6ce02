#include "lem/error.hpp"

#include <string>
#include <vector>

namespace lem {

PetscFailure::PetscFailure(const char* call, PetscErrorCode code)
    : std::runtime_error(std::string("PETSc error ") + std::to_string(code) + " in " + call) {}

void run_on_root(MPI_Comm comm, const std::function<void()>& work) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  // kind: 0 = success, 1 = InputError, 2 = other failure
  int kind = 0;
  std::string message;
  if (rank == 0) {
    try {
      work();
    } catch (const InputError& e) {
      kind = 1;
      message = e.what();
    } catch (const std::exception& e) {
      kind = 2;
      message = e.what();
    }
  }
  MPI_Bcast(&kind, 1, MPI_INT, 0, comm);
  if (kind == 0) return;
  int length = static_cast<int>(message.size());
  MPI_Bcast(&length, 1, MPI_INT, 0, comm);
  message.resize(static_cast<std::size_t>(length));
  MPI_Bcast(message.data(), length, MPI_CHAR, 0, comm);
  if (kind == 1) throw InputError(message);
  throw std::runtime_error(message);
}

}  // namespace lem
