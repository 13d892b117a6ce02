// The direct route for the slow tail (-solver_direct_tail) changes how the
// elastic system is solved, never what it solves: once taken, a solve of the
// damaged lattice is exact to rounding (Woodbury's identity on the factor of
// K made before the bonds broke), so CG stops at its first check, and the
// field equals the multigrid's; a bond broken twice over the run, or more
// broken bonds than -solver_direct_columns, makes the factor again.  Runs at
// 1 and 2 ranks.
#include "lem/system/elastic_system.hpp"
#include "lem/base/error.hpp"
#include "lem/setup/setup.hpp"

#include "lem/base/collective.hpp"

#include "../compared_solves.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

using namespace lem;

namespace {

Lattice random_lattice(std::int64_t nodes) {
  RandomLatticeSpec spec;
  spec.nodes = nodes;
  spec.seed = 7;
  return make_random_lattice(spec);
}

SolverOptions routed(SolverOptions o, int trigger = 1) {
  o.levers.push_back({"lem_direct_tail", static_cast<double>(trigger)});
  return o;
}

// What the route did so far, from its line of the run's log.
struct RouteWork {
  int solves = 0, applications = 0, factorizations = 0, columns = 0;
};
RouteWork route_work(const ElasticSystem& s) {
  const std::string line = s.levers().back()->work_line();
  RouteWork w;
  double seconds = 0;
  EXPECT_EQ(std::sscanf(line.c_str(),
                        "direct tail: %d solves on the route (%d applications, %lf s), %d "
                        "factorizations (%lf s), %d broken",
                        &w.solves, &w.applications, &seconds, &w.factorizations, &seconds,
                        &w.columns),
            6)
      << line;
  return w;
}

// Breaks the intact bonds whose id is `residue` modulo `every`.
void damage(DistributedLattice& dl, ElasticSystem& s, int every, int residue) {
  for (int b = 0; b < dl.local_bonds(); ++b)
    if (dl.bond_stiffness[b] > 0 && dl.bond_id[b] % every == residue) s.set_bond_stiffness(b, 0.0);
  s.finish_updates();
}

// The same damage on both systems; the plain one solved, the other's report.
SolveReport break_and_solve(DistributedLattice& lp, ElasticSystem& plain, DistributedLattice& ld,
                            ElasticSystem& with, int every, int residue) {
  damage(lp, plain, every, residue);
  damage(ld, with, every, residue);
  plain.solve(1e-3);
  return with.solve(1e-3);
}

void assemble_reusing(ElasticSystem& plain, ElasticSystem& with) {
  for (ElasticSystem* s : {&plain, &with}) {
    s->set_reuse_preconditioner(true);
    s->assemble();
  }
}

std::int64_t broken_bonds(const DistributedLattice& dl) {
  std::int64_t n = 0;
  for (int b = 0; b < dl.local_bonds(); ++b)
    if (dl.bond_reported[b] && dl.bond_stiffness[b] == 0) ++n;
  return sum_over_ranks(dl.comm, n);
}

class DirectTailTest : public ::testing::Test {
 protected:
  void SetUp() override { PetscOptionsSetValue(nullptr, "-ksp_rtol", "1e-9"); }
  void TearDown() override {
    PetscOptionsClearValue(nullptr, "-ksp_rtol");
    PetscOptionsClearValue(nullptr, "-solver_direct_columns");
    PetscOptionsClearValue(nullptr, "-solver_direct_memory");
  }
};

}  // namespace

TEST_F(DirectTailTest, SolvesTheDamagedLatticeExactlyFromOneFactor) {
  const Lattice l = random_lattice(1500);
  DistributedLattice lp = distributed(PETSC_COMM_WORLD, l), ld = distributed(PETSC_COMM_WORLD, l);
  const SolverOptions grounded;
  ElasticSystem plain(lp, grounded), with(ld, routed(grounded));
  assemble_reusing(plain, with);
  // The multigrid for the first eight solves (the window the choice looks
  // back on), each after a few bonds broke, then the route.
  for (int i = 1; i <= 8; ++i)
    EXPECT_GT(break_and_solve(lp, plain, ld, with, 500, i).iterations, 1) << "solve " << i;
  EXPECT_EQ(route_work(with).solves, 0);
  std::int64_t factored_with = 0;  // broken bonds when the factor was made
  for (int round = 0; round < 3; ++round) {
    const SolveReport r = break_and_solve(lp, plain, ld, with, 60, round);
    if (round == 0) factored_with = broken_bonds(ld);
    const RouteWork w = route_work(with);
    EXPECT_EQ(w.solves, round + 1);
    // One factorization, a column per bond broken since, and the solution
    // exact to rounding: CG checks its true residual and stops at its
    // start, so a solve is one pass over the factor (the load's, with the
    // new columns).
    EXPECT_EQ(w.factorizations, 1);
    EXPECT_EQ(w.columns, broken_bonds(ld) - factored_with) << "round " << round;
    EXPECT_EQ(r.iterations, 0) << "round " << round;
    EXPECT_EQ(w.applications, round + 1);
    EXPECT_LT(worst_tension_difference(ld, with, lp, plain), 1e-6) << "round " << round;
    EXPECT_NEAR(with.response().young_modulus / plain.response().young_modulus, 1.0, 1e-8);
  }
  EXPECT_GT(route_work(with).columns, 200);
}

TEST_F(DirectTailTest, FactorsAgainBeyondItsColumns) {
  PetscOptionsSetValue(nullptr, "-solver_direct_tail", "1");
  PetscOptionsSetValue(nullptr, "-solver_direct_columns", "20");
  PetscOptionsSetValue(nullptr, "-solver_cycle_precision", "double");  // the lever alone
  const SolverOptions o = read_solver_options(PETSC_COMM_WORLD);
  PetscOptionsClearValue(nullptr, "-solver_direct_tail");
  PetscOptionsClearValue(nullptr, "-solver_cycle_precision");
  ASSERT_EQ(o.levers.size(), 1u);
  EXPECT_EQ(o.levers[0].type, "lem_direct_tail");
  const Lattice l = random_lattice(1500);
  DistributedLattice lp = distributed(PETSC_COMM_WORLD, l), ld = distributed(PETSC_COMM_WORLD, l);
  ElasticSystem plain(lp, SolverOptions{}), with(ld, o);
  assemble_reusing(plain, with);
  for (int i = 1; i <= 8; ++i) break_and_solve(lp, plain, ld, with, 500, i);
  // The route is taken with this damage in its factor; then 1 in 300 more
  // bonds break, over 20: a new factor.
  break_and_solve(lp, plain, ld, with, 300, 0);
  const std::int64_t factored_with = broken_bonds(ld);
  EXPECT_EQ(break_and_solve(lp, plain, ld, with, 300, 1).iterations, 0);
  EXPECT_GT(broken_bonds(ld) - factored_with, 20);
  const RouteWork w = route_work(with);
  EXPECT_EQ(w.factorizations, 2);
  EXPECT_EQ(w.columns, 0);
  EXPECT_LT(worst_tension_difference(ld, with, lp, plain), 1e-6);
}

// A factor that would not fit the share of the machine's memory the option
// allows is never made: the run keeps the multigrid, with the same fields.
TEST_F(DirectTailTest, LeftWhenTheFactorWouldNotFit) {
  PetscOptionsSetValue(nullptr, "-solver_direct_tail", "1");
  PetscOptionsSetValue(nullptr, "-solver_direct_memory", "1e-9");
  const SolverOptions o = read_solver_options(PETSC_COMM_WORLD);
  PetscOptionsClearValue(nullptr, "-solver_direct_tail");
  const Lattice l = random_lattice(1500);
  DistributedLattice lp = distributed(PETSC_COMM_WORLD, l), ld = distributed(PETSC_COMM_WORLD, l);
  ElasticSystem plain(lp, SolverOptions{}), with(ld, o);
  assemble_reusing(plain, with);
  for (int i = 1; i <= 12; ++i)
    EXPECT_GT(break_and_solve(lp, plain, ld, with, 500, i).iterations, 1) << "solve " << i;
  const RouteWork w = route_work(with);
  EXPECT_EQ(w.solves, 0);
  EXPECT_EQ(w.factorizations, 0);
  // The estimate it refused: MUMPS's analysis of a 4 500-dof K, a few MB.
  const std::string line = with.levers().back()->work_line();
  double mb = 0;
  ASSERT_EQ(std::sscanf(line.substr(line.find("estimated at")).c_str(), "estimated at %lf MB", &mb),
            1)
      << line;
  EXPECT_GT(mb, 0.1);
  EXPECT_LT(worst_tension_difference(ld, with, lp, plain), 1e-6);
}

TEST_F(DirectTailTest, ChosenWithItsOptionNotWithPcType) {
  PetscOptionsSetValue(nullptr, "-pc_type", "lem_direct_tail");
  EXPECT_THROW(read_solver_options(PETSC_COMM_WORLD), InputError);
  PetscOptionsClearValue(nullptr, "-pc_type");
}
