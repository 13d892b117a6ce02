#include "lem/log.hpp"

#include "lem/error.hpp"

#include <cstdarg>
#include <cstdio>
#include <map>
#include <string>

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

PetscLogStage log_stage(const char* name) {
  static std::map<std::string, PetscLogStage> registered;
  const auto found = registered.find(name);
  if (found != registered.end()) return found->second;
  PetscLogStage stage = 0;
  LEM_PETSC(PetscLogStageRegister(name, &stage));
  registered.emplace(name, stage);
  return stage;
}

LogStageScope::LogStageScope(PetscLogStage stage) {
  LEM_PETSC(PetscLogStagePush(stage));
  pushed_ = true;
}

LogStageScope::~LogStageScope() {
  if (pushed_) PetscLogStagePop();  // an error here cannot be thrown
}

void LogStageScope::pop() {
  if (!pushed_) return;
  pushed_ = false;
  LEM_PETSC(PetscLogStagePop());
}

}  // namespace lem
