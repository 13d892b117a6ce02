#include "lem/base/log.hpp"

#include "lem/base/error.hpp"

#include <cstdarg>
#include <cstdio>
#include <map>
#include <string>

namespace lem {

namespace {

void print_on_root(std::FILE* stream, const char* format, va_list args) {
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank != 0) return;
  std::fflush(stdout);  // keep the order of the two streams in a joint log
  std::vfprintf(stream, format, args);
  std::fflush(stream);
}

}  // namespace

void say(const char* format, ...) {
  va_list args;
  va_start(args, format);
  print_on_root(stdout, format, args);
  va_end(args);
}

void say_warning(const char* format, ...) {
  va_list args;
  va_start(args, format);
  print_on_root(stderr, format, args);
  va_end(args);
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
