// The multigrid cycle in single precision (-solver_cycle_precision single)
// against GAMG's double cycle it copies: the same preconditioner to float
// accuracy, the same CG solution to the solve tolerance, also after ruptures
// and a rebuild, and the option validated.  Runs at 1 and 2 ranks.
#include "lem/solver/single_cycle.hpp"
#include "lem/system/elastic_system.hpp"
#include "lem/base/error.hpp"
#include "lem/setup/setup.hpp"

#include "../compared_solves.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

using namespace lem;

namespace {

DistributedLattice random_problem(MPI_Comm comm, std::int64_t nodes) {
  RandomLatticeSpec s;
  s.nodes = nodes;
  s.seed = 5;
  return distributed(comm, make_random_lattice(s));
}

// The options of a run, with the single cycle or without it, as
// -solver_cycle_precision chooses it.
SolverOptions cycle_options(bool single) {
  SolverOptions o;
  if (single) o.levers.push_back({SingleCycle::kType, 1});
  return o;
}
SolverOptions single_options() { return cycle_options(true); }

bool single_chosen(const SolverOptions& o) {
  for (const LeverChoice& c : o.levers)
    if (c.type == SingleCycle::kType) return true;
  return false;
}

// |M_single r - M_double r| / |M_double r| for an r that depends on the
// global row only, both applied by the shell of the system's KSP.
double cycle_difference(ElasticSystem& system, SingleCycle& cycle) {
  VecHandle r, zs, zd;
  LEM_PETSC(MatCreateVecs(system.matrix(), r.replace(), zs.replace()));
  LEM_PETSC(VecDuplicate(zs, zd.replace()));
  PetscInt lo = 0, hi = 0;
  LEM_PETSC(VecGetOwnershipRange(r, &lo, &hi));
  PetscScalar* ra = nullptr;
  LEM_PETSC(VecGetArray(r, &ra));
  for (PetscInt i = lo; i < hi; ++i) ra[i - lo] = std::cos(0.91 * static_cast<double>(i) + 0.3);
  LEM_PETSC(VecRestoreArray(r, &ra));
  PC pc;
  LEM_PETSC(KSPGetPC(system.ksp(), &pc));
  cycle.use_single(true);
  LEM_PETSC(PCApply(pc, r, zs));
  cycle.use_single(false);
  LEM_PETSC(PCApply(pc, r, zd));
  cycle.use_single(true);
  PetscReal scale = 0, gap = 0;
  LEM_PETSC(VecNorm(zd, NORM_2, &scale));
  LEM_PETSC(VecAXPY(zs, -1.0, zd));
  LEM_PETSC(VecNorm(zs, NORM_2, &gap));
  return gap / scale;
}

TEST(SingleCycle, AppliesTheDoubleCycleInFloat) {
  DistributedLattice lattice = random_problem(PETSC_COMM_WORLD, 12000);
  ElasticSystem system(lattice, single_options());
  system.assemble();
  system.solve(1e-3 * lattice.mean_bond_length);
  SingleCycle* cycle = SingleCycle::of(system.ksp());
  ASSERT_NE(cycle, nullptr);
  PetscInt levels = 0;
  LEM_PETSC(PCMGGetLevels(cycle->inner(), &levels));
  ASSERT_GE(levels, 3);  // a W-cycle with a level visited twice
  // Float values, double vectors: the cycles agree to about float rounding;
  // a different cycle (V for W, a missing sweep) differs by O(0.1).
  const double difference = cycle_difference(system, *cycle);
  EXPECT_LT(difference, 1e-4);
  EXPECT_GT(difference, 0.0);  // it is the float cycle that ran
  EXPECT_GT(cycle->applications(), 0.0);
}

TEST(SingleCycle, SolutionEqualsDoubleCycleAlsoAfterRupturesAndRebuild) {
  std::vector<double> modulus[2], solution[2];
  std::vector<int> iterations[2];
  for (int single = 0; single < 2; ++single) {
    DistributedLattice lattice = random_problem(PETSC_COMM_WORLD, 12000);
    SolverOptions options = cycle_options(single != 0);
    ElasticSystem system(lattice, options);
    system.set_reuse_preconditioner(true);
    system.assemble();
    const double delta = 1e-3 * lattice.mean_bond_length;
    auto record = [&](const SolveReport& report) {
      modulus[single].push_back(system.response().young_modulus);
      iterations[single].push_back(report.iterations);
    };
    record(system.solve(delta));
    // Ruptures by lattice ids (every rank holding a bond breaks it): one
    // solve with the kept multigrid, one after a rebuild, one to 1e-10 (the
    // near-tie re-solves of the fracture runs).
    for (int b = 0; b < lattice.local_bonds(); ++b)
      if (lattice.bond_id[b] % 13 == 0) system.set_bond_stiffness(b, 0.0);
    system.finish_updates();
    record(system.solve(1.5 * delta));
    system.rebuild_preconditioner();
    record(system.solve(2.0 * delta));
    const SolveReport tight = system.solve_to(1e-10, 2.0 * delta);
    EXPECT_GT(tight.reason, 0) << "the 1e-10 solve did not converge";
    record(tight);
    solution[single] = system.solution();
    if (single) {
      // The ruptures changed K under the kept multigrid: the cycle read its
      // fine level again, and says so in its counters.
      const SingleCycle* cycle = SingleCycle::of(system.ksp());
      ASSERT_NE(cycle, nullptr);
      EXPECT_GE(cycle->refreshes(), 1.0);
      EXPECT_GT(cycle->refresh_seconds() + cycle->probe_seconds(), 0.0);
      EXPECT_NE(cycle->work_line().find(" refreshes: "), std::string::npos) << cycle->work_line();
    }
  }
  for (std::size_t k = 0; k < modulus[0].size(); ++k) {
    EXPECT_NEAR(modulus[1][k], modulus[0][k], 1e-9 * std::fabs(modulus[0][k])) << "solve " << k;
    EXPECT_LE(std::abs(iterations[1][k] - iterations[0][k]), 2)
        << "solve " << k << ": " << iterations[0][k] << " its with the double cycle, "
        << iterations[1][k] << " with the single one";
  }
  // The last field (to 1e-10) the same to the tolerance.
  double gap = 0, scale = 0;
  for (std::size_t i = 0; i < solution[0].size(); ++i) {
    gap = std::max(gap, std::fabs(solution[1][i] - solution[0][i]));
    scale = std::max(scale, std::fabs(solution[0][i]));
  }
  double global[2] = {gap, scale}, out[2];
  MPI_Allreduce(global, out, 2, MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD);
  EXPECT_LT(out[0], 1e-8 * out[1]);
}

TEST(SingleCycle, SingleLevelIsTheDirectSolve) {
  // Fewer rows than the coarse limit: GAMG's one level, applied as it is.
  double modulus[2] = {};
  for (int single = 0; single < 2; ++single) {
    DistributedLattice lattice = random_problem(PETSC_COMM_WORLD, 200);
    SolverOptions options = cycle_options(single != 0);
    ElasticSystem system(lattice, options);
    system.assemble();
    system.solve(1e-3 * lattice.mean_bond_length);
    modulus[single] = system.response().young_modulus;
  }
  EXPECT_NEAR(modulus[1], modulus[0], 1e-12 * std::fabs(modulus[0]));
}

TEST(SingleCycle, OptionIsValidated) {
  PetscOptionsSetValue(nullptr, "-solver_cycle_precision", "half");
  EXPECT_THROW(read_solver_options(PETSC_COMM_WORLD), InputError);
  PetscOptionsSetValue(nullptr, "-solver_cycle_precision", "single");
  EXPECT_TRUE(single_chosen(read_solver_options(PETSC_COMM_WORLD)));
  PetscOptionsSetValue(nullptr, "-solver_cycle_precision", "double");
  EXPECT_FALSE(single_chosen(read_solver_options(PETSC_COMM_WORLD)));
  PetscOptionsClearValue(nullptr, "-solver_cycle_precision");
  EXPECT_TRUE(single_chosen(read_solver_options(PETSC_COMM_WORLD)));  // the default
  // Without the option, what the float cycle cannot copy makes it double
  // instead of an error (given, `single` refuses them: below).
  const std::pair<const char*, const char*> others[] = {{"-pc_type", "jacobi"},
                                                        {"-mg_levels_ksp_type", "richardson"},
                                                        {"-mg_levels_pc_type", "sor"},
                                                        {"-mg_levels_ksp_max_it", "2"},
                                                        {"-solver_damage_aggregates", "1"}};
  for (const auto& [name, value] : others) {
    PetscOptionsSetValue(nullptr, name, value);
    EXPECT_FALSE(single_chosen(read_solver_options(PETSC_COMM_WORLD))) << name << " " << value;
    PetscOptionsClearValue(nullptr, name);
  }
  PetscOptionsSetValue(nullptr, "-pc_type", "gamg");
  EXPECT_TRUE(single_chosen(read_solver_options(PETSC_COMM_WORLD)));
  PetscOptionsClearValue(nullptr, "-pc_type");
  // A preconditioner that is no multigrid is refused by name.
  DistributedLattice lattice = random_problem(PETSC_COMM_WORLD, 1500);
  PetscOptionsSetValue(nullptr, "-pc_type", "jacobi");
  try {
    ElasticSystem system(lattice, single_options());
    ADD_FAILURE() << "no error for -pc_type jacobi";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("-pc_type jacobi"), std::string::npos) << e.what();
  }
  {
    // Chosen by default (not given), it steps aside there instead: the
    // solve is Jacobi's, and nothing names the cycle as the preconditioner.
    SolverOptions by_default;
    by_default.levers.push_back({SingleCycle::kType, SingleCycle::kByDefault});
    ElasticSystem aside(lattice, by_default), plain(lattice, SolverOptions{});
    EXPECT_EQ(SingleCycle::of(aside.ksp()), nullptr);
    for (ElasticSystem* s : {&aside, &plain}) {
      s->assemble();
      s->solve(1e-3 * lattice.mean_bond_length);
    }
    EXPECT_EQ(aside.response().young_modulus, plain.response().young_modulus);
  }
  PetscOptionsClearValue(nullptr, "-pc_type");
  // A smoother other than one Chebyshev/Jacobi sweep is refused by name.
  PetscOptionsSetValue(nullptr, "-mg_levels_ksp_max_it", "2");
  try {
    ElasticSystem system(lattice, single_options());
    ADD_FAILURE() << "no error for two sweeps";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("-mg_levels_ksp_max_it 2"), std::string::npos) << e.what();
  }
  PetscOptionsClearValue(nullptr, "-mg_levels_ksp_max_it");
}

TEST(SingleCycle, DamageAggregatesAroundItAreRefused) {
  // The damage aggregates change GAMG's own coarsening, and the single cycle
  // copies GAMG's levels: each needs the multigrid itself, so the two are
  // refused together, naming the option.
  DistributedLattice lattice = random_problem(PETSC_COMM_WORLD, 1500);
  SolverOptions options = single_options();
  options.levers.push_back({"lem_damage_aggregates", 1});
  try {
    ElasticSystem system(lattice, options);
    ADD_FAILURE() << "no error for the damage aggregates around the single cycle";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("-solver_damage_aggregates"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("single-precision cycle"), std::string::npos) << e.what();
  }
}

}  // namespace
