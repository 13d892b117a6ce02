// The Ritz-vector deflation (-solver_ritz_deflation) changes how the elastic
// system is solved, never what it solves: on a lattice with slow modes that
// the multigrid misses (stiff blocks joined by soft bonds), the deflated
// solve equals the plain one and needs fewer CG iterations, also after bonds
// break in place with the multigrid kept; it cannot be combined with the
// per-particle deflation.  The spectrum probe (-solver_spectrum_solves)
// writes Ritz values whose Rayleigh quotients agree with them.  Runs at 1
// and 2 ranks.
#include "lem/system/elastic_system.hpp"
#include "lem/base/error.hpp"
#include "lem/setup/setup.hpp"

#include "../compared_solves.hpp"
#include "../exact_solver_test.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

using namespace lem;

namespace {

// A random lattice cut into two blocks across x: bonds inside a block have
// k = 1, bonds between them k = 1e-4, so that the blocks moving as rigid
// bodies against each other are slow modes of the multigrid-preconditioned
// K (the lattice has no particles: the per-particle deflation could not see
// them).
Lattice block_lattice(std::int64_t nodes) {
  RandomLatticeSpec spec;
  spec.nodes = nodes;
  spec.seed = 5;
  Lattice l = make_random_lattice(spec);
  auto block = [&](std::size_t n) { return l.nodes[n][0] < 0.5 ? 0 : 1; };
  for (std::size_t b = 0; b < l.bond_count(); ++b) {
    const auto [i, j] = l.bonds[b];
    l.stiffness[b] = block(i) == block(j) ? 1.0 : 1e-4;
  }
  return l;
}

SolverOptions ritz(SolverOptions o, int count = 24) {
  o.levers.push_back({"lem_ritz_deflation", static_cast<double>(count)});
  return o;
}

using RitzDeflationTest = ExactSolverTest;

}  // namespace

TEST_F(RitzDeflationTest, FirstSolveIsThePlainOne) {
  // Nothing is learnt before the first solve: the same iterations and the
  // same field as without the deflation.
  const Lattice l = block_lattice(4000);
  DistributedLattice lp = distributed(PETSC_COMM_WORLD, l), ld = distributed(PETSC_COMM_WORLD, l);
  ElasticSystem plain(lp, exact), with(ld, ritz(exact));
  plain.assemble();
  with.assemble();
  EXPECT_EQ(with.solve(1e-4).iterations, plain.solve(1e-4).iterations);
  EXPECT_LT(worst_tension_difference(ld, with, lp, plain), 1e-12);
}

TEST_F(RitzDeflationTest, FollowsInPlaceChangesWithItsMultigridReused) {
  // Both keep their first preconditioner (as between load steps) while one
  // in three of the soft bonds between blocks breaks: the slow modes stay
  // the blocks' motions, slower; the deflation keeps its space and forms
  // W^T K W anew.
  const Lattice l = block_lattice(4000);
  DistributedLattice lp = distributed(PETSC_COMM_WORLD, l), ld = distributed(PETSC_COMM_WORLD, l);
  const SolverOptions grounded;
  ElasticSystem plain(lp, grounded), with(ld, ritz(grounded));
  for (ElasticSystem* s : {&plain, &with}) {
    s->set_reuse_preconditioner(true);
    s->assemble();
    s->solve(1e-4);
  }
  auto damage = [](DistributedLattice& dl, ElasticSystem& s) {
    for (int b = 0; b < dl.local_bonds(); ++b)
      if (dl.bond_stiffness[b] < 0.5 && dl.bond_id[b] % 3 == 0) s.set_bond_stiffness(b, 0.0);
    s.finish_updates();
  };
  damage(lp, plain);
  damage(ld, with);
  const int its_plain = plain.solve(1.5e-4).iterations,
            its_deflated = with.solve(1.5e-4).iterations;
  EXPECT_NEAR(with.response().young_modulus / plain.response().young_modulus, 1.0, 1e-7);
  EXPECT_LT(worst_tension_difference(ld, with, lp, plain), 1e-6);
  // 33 against 114 iterations on 1 rank, 32 against 114 on 2: the first
  // solve's slow Ritz vectors are the blocks' relative motions.  Without the
  // space (nothing learnt) the iterations are the plain ones.
  EXPECT_LT(its_deflated, 0.5 * its_plain) << its_deflated << " against " << its_plain;
}

TEST_F(RitzDeflationTest, NotWithThePerParticleDeflation) {
  PetscOptionsSetValue(nullptr, "-solver_ritz_deflation", "16");
  PetscOptionsSetValue(nullptr, "-solver_particle_deflation", nullptr);
  try {
    read_solver_options(PETSC_COMM_WORLD);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot be used together"), std::string::npos) << e.what();
  }
  PetscOptionsClearValue(nullptr, "-solver_particle_deflation");
  PetscOptionsSetValue(nullptr, "-solver_cycle_precision", "double");  // the lever alone
  const SolverOptions o = read_solver_options(PETSC_COMM_WORLD);
  ASSERT_EQ(o.levers.size(), 1u);
  EXPECT_EQ(o.levers[0].type, "lem_ritz_deflation");
  EXPECT_EQ(o.levers[0].setting, 16);
  PetscOptionsClearValue(nullptr, "-solver_ritz_deflation");
  EXPECT_TRUE(read_solver_options(PETSC_COMM_WORLD).levers.empty());
  PetscOptionsClearValue(nullptr, "-solver_cycle_precision");
}

TEST_F(RitzDeflationTest, ChosenWithItsOptionNotWithPcType) {
  PetscOptionsSetValue(nullptr, "-pc_type", "lem_ritz_deflation");
  EXPECT_THROW(read_solver_options(PETSC_COMM_WORLD), InputError);
  PetscOptionsClearValue(nullptr, "-pc_type");
}

TEST_F(RitzDeflationTest, SpectrumProbeWritesConsistentRitzValues) {
  // The probe at solve 1: Ritz values in (0, 2), the slowest far below the
  // bulk on this lattice, and x^T K x of each kept vector equal to its value.
  const Lattice l = block_lattice(2000);
  DistributedLattice dl = distributed(PETSC_COMM_WORLD, l);
  SolverOptions o = exact;
  o.spectrum_solves = {1};
  o.spectrum_prefix = ::testing::TempDir() + "lem_probe";
  ElasticSystem system(dl, o);
  system.assemble();
  system.solve(1e-4);
  MPI_Barrier(PETSC_COMM_WORLD);
  std::ifstream in(o.spectrum_prefix + "_1.txt");
  ASSERT_TRUE(in) << o.spectrum_prefix + "_1.txt";
  std::vector<double> theta;
  int checked = 0;
  for (std::string line; std::getline(in, line);) {
    std::istringstream words(line);
    std::string tag;
    int index = 0;
    double value = 0, quotient = 0;
    if (!(words >> tag >> index >> value) || tag != "ritz") continue;
    theta.push_back(value);
    if (words >> quotient) {
      EXPECT_NEAR(quotient / value, 1.0, 1e-6) << "Ritz value " << index;
      ++checked;
    }
  }
  ASSERT_GT(theta.size(), 10u);
  EXPECT_EQ(checked, 8);
  EXPECT_GT(theta.front(), 0.0);
  EXPECT_LT(theta.back(), 2.0);
  EXPECT_LT(theta.front(), 0.05 * theta[theta.size() / 2]);
}
