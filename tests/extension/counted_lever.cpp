// A solver lever added from outside the library: this one file and one
// registration line (lem::register_solver_lever(counted_lever_entry()) in
// extended_fracture.cpp).  The lever is a PETSc PC type of its own
// ("ext_counted"), put around the multigrid when -solver_counted_applications
// is given; it hands every application to the multigrid and counts them,
// so it changes no result.  A real lever adds its correction in `apply` and
// may use the other hooks of lem::SolverLever (operator_changed, prepare,
// after_solve, ...).
#include "lem/base/log.hpp"
#include "lem/solver/wrapped_lever.hpp"

namespace {

class CountedLever final : public lem::WrappedLever {
 public:
  static constexpr const char* kType = "ext_counted";
  static constexpr const char* kName = "counted applications of the multigrid";
  CountedLever() = default;
  ~CountedLever() override {
    if (count_ > 0) lem::say("counted_lever: %lld applications of the multigrid\n", count_);
  }

 private:
  friend class lem::WrappedLever;
  void wrapped(const lem::LeverSite&) override {}
  static PetscErrorCode apply(PC pc, Vec r, Vec z) {
    PetscFunctionBeginUser;
    CountedLever* lever = nullptr;
    PetscCall(context(pc, &lever));
    ++lever->count_;
    PetscCall(PCApply(lever->inner_, r, z));
    PetscFunctionReturn(0);
  }

  long long count_ = 0;
};

}  // namespace

lem::SolverLeverEntry counted_lever_entry() {
  return lem::WrappedLever::entry<CountedLever>(
      "-solver_counted_applications", [](lem::OptionGroup& g) -> double {
        return g.flag("-solver_counted_applications",
                      "Example lever: count the applications of the multigrid (changes no result)",
                      false)
                   ? 1
                   : 0;
      });
}
