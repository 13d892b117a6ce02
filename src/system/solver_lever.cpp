// The registry of solver levers and the one place where the chosen ones are
// put around the multigrid (lem/system/solver_lever.hpp).
#include "lem/system/solver_lever.hpp"

#include "lem/base/error.hpp"

#include <algorithm>
#include <stdexcept>
#include <utility>

namespace lem {
namespace {

std::vector<SolverLeverEntry>& table() {
  static std::vector<SolverLeverEntry> levers;
  return levers;
}

constexpr const char* kLeverName = "lem_lever";

// PETSc's registry gets the types when they are first needed: a program may
// register its levers before PETSc starts.
void register_with_petsc() {
  for (const SolverLeverEntry& e : table()) LEM_PETSC(PCRegister(e.type.c_str(), e.create));
}

}  // namespace

void register_solver_lever(SolverLeverEntry entry) {
  auto& levers = table();
  const auto same = std::find_if(levers.begin(), levers.end(),
                                 [&](const SolverLeverEntry& e) { return e.type == entry.type; });
  if (same != levers.end())
    *same = std::move(entry);
  else
    levers.push_back(std::move(entry));
}

const std::vector<SolverLeverEntry>& solver_levers() { return table(); }

std::vector<LeverChoice> read_lever_options(MPI_Comm comm) {
  register_with_petsc();
  std::vector<LeverChoice> chosen;
  std::vector<const SolverLeverEntry*> by;
  OptionGroup g(comm,
                "Solver levers (preconditioners put around the multigrid; off by default but the "
                "single-precision cycle)");
  for (const SolverLeverEntry& e : table()) {
    const double setting = e.read(g);
    if (setting == 0) continue;
    for (const SolverLeverEntry* other : by)
      if (!e.excludes.empty() && other->excludes == e.excludes)
        throw InputError("options " + other->option + " and " + e.option +
                         " cannot be used together: choose " + e.excludes);
    chosen.push_back({e.type, setting});
    by.push_back(&e);
  }
  // A lever wraps the multigrid that -pc_type chooses: as -pc_type itself
  // it would wrap nothing.
  for (const char* name : {"-pc_type", "-fallback_pc_type", "-mg_levels_pc_type",
                           "-mg_coarse_pc_type", "-patch_pc_type"}) {
    char value[256] = "";
    PetscBool set = PETSC_FALSE;
    LEM_PETSC(PetscOptionsGetString(nullptr, nullptr, name, value, sizeof value, &set));
    if (!set) continue;
    for (const SolverLeverEntry& e : table())
      if (e.type == value)
        throw InputError(std::string("option ") + name + " = " + value +
                         ": this preconditioner is a lever put around the multigrid; choose it "
                         "with " +
                         e.option);
  }
  return chosen;
}

std::vector<SolverLever*> compose_levers(KSP ksp, const std::vector<LeverChoice>& levers,
                                         const LeverSite& site) {
  if (!levers.empty()) register_with_petsc();
  std::vector<SolverLever*> used;
  for (const LeverChoice& choice : levers) {
    PC inner = nullptr;
    LEM_PETSC(KSPGetPC(ksp, &inner));
    PetscHandle<PC, PCDestroy> outer;
    LEM_PETSC(PCCreate(PetscObjectComm(reinterpret_cast<PetscObject>(ksp)), outer.replace()));
    LEM_PETSC(PCSetType(outer, choice.type.c_str()));  // PETSc's registry makes it
    SolverLever* lever = lever_of(outer);
    if (!lever) throw std::logic_error("PC type " + choice.type + " makes no SolverLever");
    const LeverSite mine{site.lattice, site.K, site.ground, site.constrained, choice.setting};
    lever->wrap(mine, inner);      // takes a reference of its own on inner
    Mat A = nullptr, P = nullptr;  // the operators live in the PC: carried over
    LEM_PETSC(KSPGetOperators(ksp, &A, &P));
    LEM_PETSC(PetscObjectReference(reinterpret_cast<PetscObject>(A)));
    LEM_PETSC(PetscObjectReference(reinterpret_cast<PetscObject>(P)));
    LEM_PETSC(KSPSetPC(ksp, outer));  // the KSP takes its own reference
    LEM_PETSC(KSPSetOperators(ksp, A, P));
    LEM_PETSC(MatDestroy(&A));
    LEM_PETSC(MatDestroy(&P));
    used.push_back(lever);
  }
  return used;
}

SolverLever* lever_of(PC pc) {
  PetscContainer container = nullptr;
  LEM_PETSC(PetscObjectQuery(reinterpret_cast<PetscObject>(pc), kLeverName,
                             reinterpret_cast<PetscObject*>(&container)));
  void* lever = nullptr;
  if (container) LEM_PETSC(PetscContainerGetPointer(container, &lever));
  return static_cast<SolverLever*>(lever);
}

void attach_lever(PC pc, SolverLever* lever) {
  PetscContainer container = nullptr;
  LEM_PETSC(PetscContainerCreate(PETSC_COMM_SELF, &container));
  LEM_PETSC(PetscContainerSetPointer(container, lever));
  LEM_PETSC(PetscObjectCompose(reinterpret_cast<PetscObject>(pc), kLeverName,
                               reinterpret_cast<PetscObject>(container)));
  LEM_PETSC(PetscContainerDestroy(&container));
}

}  // namespace lem
