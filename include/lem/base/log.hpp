// Progress lines and PETSc log stages.
#pragma once

#include <petscsys.h>

namespace lem {

/// printf on rank 0 of PETSC_COMM_WORLD, flushed (progress lines).
void say(const char* format, ...) __attribute__((format(printf, 1, 2)));
/// The same on stderr (warnings: they must not drown in the progress lines).
void say_warning(const char* format, ...) __attribute__((format(printf, 1, 2)));

/// The PETSc log stage called `name`, registered on first use (collective
/// the first time: every rank must ask for the same names in the same order).
PetscLogStage log_stage(const char* name);

/// Pushes a log stage for the lifetime of the scope, so that an exception
/// leaves the stage stack as it found it.
class LogStageScope {
 public:
  explicit LogStageScope(PetscLogStage stage);
  explicit LogStageScope(const char* name) : LogStageScope(log_stage(name)) {}
  ~LogStageScope();
  LogStageScope(const LogStageScope&) = delete;
  LogStageScope& operator=(const LogStageScope&) = delete;
  /// Pop now (reporting a PETSc error, which the destructor cannot).
  void pop();

 private:
  bool pushed_ = false;
};

}  // namespace lem
