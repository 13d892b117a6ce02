// Owners of PETSc objects: the object is destroyed when its owner goes out
// of scope, so an exception between creating an object and storing it in
// a longer-lived place leaks nothing.
#pragma once

#include <petscksp.h>
#include <petscmat.h>
#include <petscvec.h>

#include <utility>

namespace lem {

template <class Object, PetscErrorCode (*destroy)(Object*)>
class PetscHandle {
 public:
  PetscHandle() = default;
  /// Takes ownership of `object` (which may be null).
  explicit PetscHandle(Object object) : object_(object) {}
  ~PetscHandle() { reset(); }
  PetscHandle(const PetscHandle&) = delete;
  PetscHandle& operator=(const PetscHandle&) = delete;
  PetscHandle(PetscHandle&& other) noexcept : object_(std::exchange(other.object_, nullptr)) {}
  PetscHandle& operator=(PetscHandle&& other) noexcept {
    if (this != &other) {
      reset();
      object_ = std::exchange(other.object_, nullptr);
    }
    return *this;
  }

  Object get() const { return object_; }
  operator Object() const { return object_; }  // pass straight to PETSc calls
  explicit operator bool() const { return object_ != nullptr; }

  /// For PETSc's creation calls, e.g. MatCreate(comm, k.replace()): destroys
  /// the object held so far and returns where to store the new one.
  Object* replace() {
    reset();
    return &object_;
  }
  /// Gives up ownership without destroying: for an object that a failed
  /// PETSc call left half-way, which destroying could crash on.
  Object release() { return std::exchange(object_, nullptr); }
  void reset() {
    if (object_ != nullptr) destroy(&object_);  // sets object_ to null
    object_ = nullptr;
  }

 private:
  Object object_ = nullptr;
};

using MatHandle = PetscHandle<Mat, MatDestroy>;
using VecHandle = PetscHandle<Vec, VecDestroy>;
using KspHandle = PetscHandle<KSP, KSPDestroy>;
using IsHandle = PetscHandle<IS, ISDestroy>;
using VecScatterHandle = PetscHandle<VecScatter, VecScatterDestroy>;
using NullSpaceHandle = PetscHandle<MatNullSpace, MatNullSpaceDestroy>;

}  // namespace lem
