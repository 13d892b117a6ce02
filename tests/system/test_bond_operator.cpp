// The bond operator (-solver_operator bonds) against the assembled K: the
// same product on a random lattice, also after ruptures and pinned nodes, and
// the same solve (E_eff, iterations).  Runs at 1 and 2 ranks.
#include "lem/system/elastic_system.hpp"
#include "lem/base/error.hpp"
#include "lem/setup/setup.hpp"

#include "../compared_solves.hpp"
#include "../exact_solver_test.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using namespace lem;

namespace {

DistributedLattice random_problem(MPI_Comm comm, std::int64_t nodes) {
  RandomLatticeSpec s;
  s.nodes = nodes;
  s.seed = 11;
  return distributed(comm, make_random_lattice(s));
}

// max |B x - K x| / max |K x| for an x that depends on the global row only.
double product_difference(ElasticSystem& system) {
  VecHandle x, kx, bx;
  LEM_PETSC(MatCreateVecs(system.matrix(), x.replace(), kx.replace()));
  LEM_PETSC(VecDuplicate(kx, bx.replace()));
  PetscInt lo = 0, hi = 0;
  LEM_PETSC(VecGetOwnershipRange(x, &lo, &hi));
  PetscScalar* xa = nullptr;
  LEM_PETSC(VecGetArray(x, &xa));
  for (PetscInt r = lo; r < hi; ++r) xa[r - lo] = std::sin(1.37 * static_cast<double>(r) + 0.2);
  LEM_PETSC(VecRestoreArray(x, &xa));
  LEM_PETSC(MatMult(system.matrix(), x, kx));
  LEM_PETSC(MatMult(system.operator_matrix(), x, bx));
  PetscReal scale = 0, gap = 0;
  LEM_PETSC(VecNorm(kx, NORM_INFINITY, &scale));
  LEM_PETSC(VecAXPY(bx, -1.0, kx));
  LEM_PETSC(VecNorm(bx, NORM_INFINITY, &gap));
  return gap / scale;
}

// Diagonals of both operators, max difference relative to the largest entry.
double diagonal_difference(ElasticSystem& system) {
  VecHandle dk, db;
  LEM_PETSC(MatCreateVecs(system.matrix(), dk.replace(), db.replace()));
  LEM_PETSC(MatGetDiagonal(system.matrix(), dk));
  LEM_PETSC(MatGetDiagonal(system.operator_matrix(), db));
  PetscReal scale = 0, gap = 0;
  LEM_PETSC(VecNorm(dk, NORM_INFINITY, &scale));
  LEM_PETSC(VecAXPY(db, -1.0, dk));
  LEM_PETSC(VecNorm(db, NORM_INFINITY, &gap));
  return gap / scale;
}

using BondOperatorTest = ExactSolverTest;

TEST(BondOperator, ProductEqualsAssembledAfterRupturesAndPins) {
  DistributedLattice lattice = random_problem(PETSC_COMM_WORLD, 3000);
  SolverOptions options;  // with the ground springs, which the operator must carry
  options.solver_operator = SolverOperator::bonds;
  ElasticSystem system(lattice, options);
  system.assemble();
  ASSERT_NE(system.operator_matrix(), system.matrix());
  EXPECT_LT(product_difference(system), 1e-13);
  EXPECT_LT(diagonal_difference(system), 1e-13);

  // Ruptures chosen by lattice ids, so that every rank holding a bond breaks it.
  const auto pinned = [&](int node) { return lattice.node_id[node] % 41 == 3; };
  for (int b = 0; b < lattice.local_bonds(); ++b) {
    const auto [p, q] = lattice.bond_ends[b];
    if (lattice.bond_id[b] % 9 == 0 || pinned(p) || pinned(q)) system.set_bond_stiffness(b, 0.0);
  }
  system.finish_updates();
  const double broken = product_difference(system);
  std::vector<int> pins;
  for (int n = 0; n < lattice.local_nodes(); ++n)
    if (pinned(n)) pins.push_back(n);
  system.pin_nodes(pins);
  system.finish_updates();
  EXPECT_LT(broken, 1e-13);
  EXPECT_LT(product_difference(system), 1e-13);
  EXPECT_LT(diagonal_difference(system), 1e-13);
}

TEST_F(BondOperatorTest, SolveEqualsAssembled) {
  double modulus[2] = {};
  int iterations[2] = {};
  for (int o = 0; o < 2; ++o) {
    DistributedLattice lattice = random_problem(PETSC_COMM_WORLD, 4000);
    SolverOptions options = exact;
    options.solver_operator = o ? SolverOperator::bonds : SolverOperator::assembled;
    ElasticSystem system(lattice, options);
    system.assemble();
    const SolveReport report = system.solve(1e-3 * lattice.mean_bond_length);
    modulus[o] = system.response().young_modulus;
    iterations[o] = report.iterations;
  }
  EXPECT_NEAR(modulus[1], modulus[0], 1e-10 * std::fabs(modulus[0]));
  EXPECT_LE(std::abs(iterations[1] - iterations[0]), 1);
  EXPECT_GT(modulus[0], 0.0);
}

}  // namespace
