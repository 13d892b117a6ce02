// Solver options and defaults of the elastic system: -lattice_ground_stiffness,
// the CG + GAMG defaults set on the objects, and the patch solver's KSP.
#include "solver_defaults.hpp"

#include "lem/system/elastic_system.hpp"
#include "lem/system/solver_lever.hpp"
#include "lem/base/error.hpp"
#include "lem/base/files.hpp"
#include "lem/base/options.hpp"
#include "lem/base/petsc_handle.hpp"

#include <cmath>
#include <sstream>
#include <string>

namespace lem {
namespace {

// Solver defaults measured on this problem (docs/benchmarks-solver.md).  They are
// set on the objects before KSPSetFromOptions, so any -ksp_*/-pc_*/-mg_*
// option overrides them; this table only documents them (-help, provenance)
// and must follow apply_solver_defaults() and default_no_inodes().
struct SolverDefault {
  const char *name, *value, *help;
};
const SolverDefault kSolverDefaults[] = {
    {"-ksp_type", "cg", "Krylov method (K is symmetric positive definite)"},
    {"-ksp_rtol", "1e-8", "Relative tolerance on the residual norm"},
    {"-pc_type", "gamg",
     "Preconditioner: algebraic multigrid with the rigid-body modes as near "
     "null space"},
    {"-pc_gamg_agg_nsmooths", "0", "Plain aggregation (no smoothing of the prolongator)"},
    {"-pc_gamg_coarse_eq_limit", "1000", "Rows of the coarsest grid"},
    {"-pc_gamg_threshold", "0",
     "Aggregate over nonzero couplings only: a rebuilt multigrid "
     "follows the cracks (broken bonds leave zero blocks in K)"},
    {"-pc_gamg_reuse_interpolation", "false",
     "A rebuild aggregates anew instead of keeping the "
     "prolongator of the first build"},
    {"-pc_mg_cycle_type", "w", "Multigrid cycle"},
    {"-mg_levels_ksp_max_it", "1",
     "Chebyshev sweeps per level (with the coarse grid limit: "
     "30-40 % less solve time than GAMG's defaults at 1.4e6 "
     "bonds)"},
    {"-mat_no_inode", "true", "No inode kernels for the AIJ matrix"},
};

bool option_given(const char* name) {
  PetscBool set = PETSC_FALSE;
  LEM_PETSC(PetscOptionsHasName(nullptr, nullptr, name, &set));
  return set == PETSC_TRUE;
}

// GAMG creates its levels when the preconditioner is set up and only then
// reads -pc_mg_cycle_type and -mg_levels_ksp_max_it (PCMGSetCycleType needs
// the levels): apply the defaults to the levels before every solve, after
// KSPSetUp has (re)built them, unless an option sets them.
PetscErrorCode multigrid_level_defaults(KSP ksp, Vec, Vec, void*) {
  PetscFunctionBeginUser;
  PC pc;
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(apply_multigrid_level_defaults(pc));
  PetscFunctionReturn(0);
}

}  // namespace

PetscErrorCode apply_multigrid_level_defaults(PC pc) {
  PetscFunctionBeginUser;
  PetscBool mg = PETSC_FALSE;
  // ML and HMG are built on PCMG: the level defaults reach them too.
  PetscCall(PetscObjectTypeCompareAny(reinterpret_cast<PetscObject>(pc), &mg, PCGAMG, PCMG, PCML,
                                      PCHMG, ""));
  PetscInt levels = 0;
  if (mg) PetscCall(PCMGGetLevels(pc, &levels));
  if (levels > 0) {
    PetscBool set = PETSC_FALSE;
    PetscCall(PetscOptionsHasName(nullptr, nullptr, "-pc_mg_cycle_type", &set));
    if (!set) PetscCall(PCMGSetCycleType(pc, PC_MG_CYCLE_W));
    PetscCall(PetscOptionsHasName(nullptr, nullptr, "-mg_levels_ksp_max_it", &set));
    if (!set) PetscCall(PCMGSetNumberSmooth(pc, 1));
  }
  PetscFunctionReturn(0);
}

void apply_solver_defaults(KSP ksp) {
  LEM_PETSC(KSPSetType(ksp, KSPCG));
  LEM_PETSC(KSPSetTolerances(ksp, 1e-8, PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT));
  PC pc;
  LEM_PETSC(KSPGetPC(ksp, &pc));
  LEM_PETSC(PCSetType(pc, PCGAMG));
  LEM_PETSC(PCGAMGSetNSmooths(pc, 0));
  LEM_PETSC(PCGAMGSetCoarseEqLim(pc, 1000));
  PetscReal threshold = 0.0;
  LEM_PETSC(PCGAMGSetThreshold(pc, &threshold, 1));
  LEM_PETSC(PCGAMGSetReuseInterpolation(pc, PETSC_FALSE));
  LEM_PETSC(KSPSetPreSolve(ksp, multigrid_level_defaults, nullptr));
}

void apply_fallback_defaults(KSP ksp) {
  LEM_PETSC(KSPSetOptionsPrefix(ksp, "fallback_"));
  LEM_PETSC(KSPSetType(ksp, KSPCG));
  PC pc;
  LEM_PETSC(KSPGetPC(ksp, &pc));
  LEM_PETSC(PCSetType(pc, PCJACOBI));
  LEM_PETSC(KSPSetInitialGuessNonzero(ksp, PETSC_TRUE));
}

void set_from_options(KSP ksp) {
  read_petsc_options([&] { LEM_PETSC(KSPSetFromOptions(ksp)); });
  // preonly (and its alias none) refuses a non-zero initial guess, and every
  // solve starts from the last solution: it would fail at the first solve.
  PetscBool once = PETSC_FALSE;
  LEM_PETSC(PetscObjectTypeCompareAny(reinterpret_cast<PetscObject>(ksp), &once, KSPPREONLY,
                                      KSPNONE, ""));
  if (!once) return;
  const char* prefix = nullptr;
  LEM_PETSC(KSPGetOptionsPrefix(ksp, &prefix));
  throw InputError("option -" + std::string(prefix ? prefix : "") +
                   "ksp_type = preonly (or "
                   "none) cannot be used: every solve starts from the previous solution, which "
                   "these refuse (for one application of the preconditioner, use richardson "
                   "with -" +
                   (prefix ? prefix : "") + "ksp_max_it 1)");
}

// -mat_no_inode must also reach the matrices that GAMG creates inside
// (coarse operators, prolongators), which only the options database does:
// the one default still put there, unless the option was given.
void default_no_inodes() {
  if (option_given("-mat_no_inode")) return;
  LEM_PETSC(PetscOptionsSetValue(nullptr, "-mat_no_inode", "true"));
  option_given("-mat_no_inode");  // mark it used: BAIJ ignores it, which is no typo
}

namespace {

// Beyond any run's solve count (10^7-bond runs make about 10^4 solves).
constexpr double kMaxSpectrumSolve = 1e9;

// The program's own options of the elastic system and its solver.
SolverOptions read_elastic_system_options(MPI_Comm comm) {
  SolverOptions o;
  {
    OptionGroup g(comm, "Elastic system");
    o.ground_stiffness =
        g.real("-lattice_ground_stiffness",
               "Weak spring tying every free degree of freedom "
               "to its rest position, relative to the mean nodal stiffness.  Phase "
               "patterns and ruptures leave hinged clusters (mechanisms) that make K "
               "singular and the multigrid preconditioner indefinite; 1e-10 removes them "
               "and changes E_eff by < 1e-6 relative (docs/model/cemented-samples.md); 0 "
               "disables",
               o.ground_stiffness, 0.0, 1e-3);
    o.solver_operator = g.choice<SolverOperator>(
        "-solver_operator",
        "What CG multiplies by: the assembled matrix K, or K applied "
        "bond by bond from each bond's stiffness and direction (less memory traffic per "
        "product; the multigrid is built from the assembled K either way)",
        {{"assembled", SolverOperator::assembled}, {"bonds", SolverOperator::bonds}},
        o.solver_operator);
    for (const double s : g.positive_reals(
             "-solver_spectrum_solves",
             "Diagnostic: at these "
             "solves (counted from 1), run one more preconditioned CG that keeps its Lanczos "
             "vectors and write the Ritz values of the preconditioned operator, the residual "
             "history and the 8 slowest Ritz vectors (docs/guide/running.md)",
             {}, true)) {
      // A solve count: a fraction would be cut, and a count past any run's
      // would never fire.
      if (s != std::floor(s) || s > kMaxSpectrumSolve) {
        std::ostringstream why;
        why << "option -solver_spectrum_solves: " << s << " is not a solve number (a whole "
            << "number from 1 to " << kMaxSpectrumSolve << ")";
        throw InputError(why.str());
      }
      o.spectrum_solves.push_back(static_cast<std::int64_t>(s));
    }
    o.spectrum_prefix = g.string("-solver_spectrum_prefix",
                                 "Diagnostic: path prefix of the "
                                 "files of -solver_spectrum_solves",
                                 o.spectrum_prefix);
    // The probe fires late in a run: a prefix it cannot write is refused now.
    if (!o.spectrum_solves.empty())
      run_on_root(comm, [&] {
        if (const std::string why = unwritable_file(o.spectrum_prefix + "_check"); !why.empty())
          throw InputError("option -solver_spectrum_prefix = '" + o.spectrum_prefix +
                           "': the probe's files cannot be written there (" + why + ")");
      });
  }
  return o;
}

}  // namespace

SolverOptions read_solver_options(MPI_Comm comm) {
  SolverOptions o = read_elastic_system_options(comm);
  o.levers = read_lever_options(comm);
  OptionGroup g(comm, "Linear solver (defaults set on PETSc's objects; any -ksp_*, -pc_*, "
                      "-mg_* or -mat_* option overrides them)");
  for (const SolverDefault& d : kSolverDefaults) g.petsc_default(d.name, d.help, d.value);
  // Misspelt types fail here, before any work, rather than in KSPSetFromOptions.
  LEM_PETSC(KSPInitializePackage());
  LEM_PETSC(PCInitializePackage());
  for (const char* prefix : {"-", "-fallback_", "-mg_levels_", "-mg_coarse_"}) {
    check_type_option((std::string(prefix) + "ksp_type").c_str(), KSPList, "KSP");
    check_type_option((std::string(prefix) + "pc_type").c_str(), PCList, "PC");
  }
  // (-mat_type is left to MatSetFromOptions: "aij", "baij" are root names
  // outside MatList.)
  // The solvers' options read once by throwaway objects (the system's own
  // are made only after the sample): a value PETSc cannot take fails here,
  // before any work.  With -help, PETSc lists its KSP and PC options, with
  // our defaults as current values.
  check_petsc_numbers();
  const auto read_solvers = [comm] {
    for (const bool fallback : {false, true}) {
      KspHandle ksp;
      LEM_PETSC(KSPCreate(comm, ksp.replace()));
      if (fallback)
        apply_fallback_defaults(ksp);
      else
        apply_solver_defaults(ksp);
      set_from_options(ksp);
    }
  };
  read_solvers();
  PetscBool help = PETSC_FALSE;
  LEM_PETSC(PetscOptionsHasHelp(nullptr, &help));
  if (!help) check_bare_petsc_options(read_solvers);  // (each reading would list them again)
  MatHandle matrix;  // -mat_type and the options of the matrix type
  LEM_PETSC(MatCreate(comm, matrix.replace()));
  LEM_PETSC(MatSetSizes(matrix, 3, 3, PETSC_DETERMINE, PETSC_DETERMINE));
  LEM_PETSC(MatSetBlockSize(matrix, 3));
  LEM_PETSC(MatSetType(matrix, MATAIJ));
  read_petsc_options([&] { LEM_PETSC(MatSetFromOptions(matrix)); });
  return o;
}

KSP create_patch_solver(MPI_Comm comm, double rtol) {
  KSP ksp = nullptr;
  LEM_PETSC(KSPCreate(comm, &ksp));
  LEM_PETSC(KSPSetOptionsPrefix(ksp, "patch_"));
  LEM_PETSC(KSPSetType(ksp, KSPCG));
  PC pc = nullptr;
  LEM_PETSC(KSPGetPC(ksp, &pc));
  LEM_PETSC(PCSetType(pc, PCJACOBI));
  LEM_PETSC(KSPSetTolerances(ksp, rtol, PETSC_DEFAULT, PETSC_DEFAULT, 5000));
  try {
    read_petsc_options([&] { LEM_PETSC(KSPSetFromOptions(ksp)); });
  } catch (...) {
    KSPDestroy(&ksp);
    throw;
  }
  return ksp;
}

}  // namespace lem
