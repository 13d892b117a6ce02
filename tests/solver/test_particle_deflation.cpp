// The per-particle rigid-body deflation (-solver_particle_deflation) changes
// how the elastic system is solved, never what it solves: on a lattice of
// stiff "particles" joined by soft bonds, the deflated solve equals the plain
// one, on 1 and 2 ranks, after in-place stiffness changes and pinned nodes;
// it needs fewer CG iterations; the multigrid inside it is reused like the
// plain one; a lattice without particles is refused.  Runs at 1 and 2 ranks.
#include "lem/system/elastic_system.hpp"
#include "lem/base/error.hpp"
#include "lem/setup/setup.hpp"

#include "../compared_solves.hpp"
#include "../exact_solver_test.hpp"

#include <gtest/gtest.h>
#include <petsclog.h>

#include <cmath>
#include <map>
#include <utility>
#include <vector>

using namespace lem;

namespace {

// A random lattice with eight spherical particles on a 2 x 2 x 2 grid: bonds
// inside a particle have k = 1, all others (between particles, through the
// pores) k = 1e-3, so that every particle moving as a rigid body is a
// near-null mode of K.
Lattice particle_lattice(std::int64_t nodes) {
  RandomLatticeSpec spec;
  spec.nodes = nodes;
  spec.seed = 9;
  Lattice l = make_random_lattice(spec);
  l.node_particle.assign(l.node_count(), -1);
  for (std::size_t n = 0; n < l.node_count(); ++n) {
    const Point& x = l.nodes[n];
    int cell = 0;
    double d2 = 0;
    for (int a = 0; a < 3; ++a) {
      const int half = x[a] < 0.5 ? 0 : 1;
      cell = 2 * cell + half;
      d2 += std::pow(x[a] - (0.25 + 0.5 * half), 2);
    }
    if (d2 < 0.22 * 0.22) l.node_particle[n] = cell;
  }
  for (std::size_t b = 0; b < l.bond_count(); ++b) {
    const auto [i, j] = l.bonds[b];
    const bool inside = l.node_particle[i] >= 0 && l.node_particle[i] == l.node_particle[j];
    l.stiffness[b] = inside ? 1.0 : 1e-3;
  }
  return l;
}

SolverOptions deflated(SolverOptions o) {
  o.levers.push_back({"lem_particle_deflation", 1});
  return o;
}

// Largest displacement difference between two solves of the same lattice
// (owned nodes matched through their partition-independent ids), over all
// ranks of `a`'s communicator.
double worst_difference(const DistributedLattice& la, const ElasticSystem& a,
                        const DistributedLattice& lb, const ElasticSystem& b) {
  std::map<std::int64_t, Point> by_id;
  const auto db = b.owned_displacements();
  for (int n = 0; n < lb.owned; ++n) by_id[lb.node_id[n]] = db[n];
  const auto da = a.owned_displacements();
  double worst = 0;
  for (int n = 0; n < la.owned; ++n)
    for (int c = 0; c < 3; ++c)
      worst = std::max(worst, std::fabs(da[n][c] - by_id.at(la.node_id[n])[c]));
  MPI_Allreduce(MPI_IN_PLACE, &worst, 1, MPI_DOUBLE, MPI_MAX, la.comm);
  return worst;
}

// Set-ups of PETSc's algebraic multigrid so far, all log stages together.
int multigrid_setups() {
  PetscLogEvent event;
  PetscLogEventGetId("PCSetUp_GAMG+", &event);
  PetscStageLog log;
  PetscLogGetStageLog(&log);
  int count = 0;
  for (int stage = 0; stage < log->numStages; ++stage) {
    PetscEventPerfInfo info;
    PetscLogEventGetPerfInfo(stage, event, &info);
    count += info.count;
  }
  return count;
}

using Deflation = ExactSolverTest;

}  // namespace

TEST_F(Deflation, SameSolutionAsThePlainMultigridInFewerIterations) {
  const Lattice l = particle_lattice(4000);
  DistributedLattice lp = distributed(PETSC_COMM_WORLD, l), ld = distributed(PETSC_COMM_WORLD, l);
  ElasticSystem plain(lp, exact), with(ld, deflated(exact));
  plain.assemble();
  with.assemble();
  const int its_plain = plain.solve(1e-4).iterations, its_deflated = with.solve(1e-4).iterations;
  EXPECT_NEAR(with.response().young_modulus / plain.response().young_modulus, 1.0, 1e-9);
  EXPECT_NEAR(with.response().poisson_ratio / plain.response().poisson_ratio, 1.0, 1e-8);
  EXPECT_LT(worst_difference(ld, with, lp, plain), 1e-8 * 1e-4);
  // The coarse space removes the particles' rigid-body modes: 91 against
  // 298 iterations on 1 rank.  Without it (or with a wrong one) the
  // iterations are those of the plain solve.
  EXPECT_LT(its_deflated, 0.45 * its_plain) << its_deflated << " against " << its_plain;
}

TEST_F(Deflation, SameSolutionOnAllRanksAndOnOne) {
  const Lattice l = particle_lattice(4000);
  DistributedLattice wide = distributed(PETSC_COMM_WORLD, l),
                     alone = distributed(PETSC_COMM_SELF, l);
  ElasticSystem sw(wide, deflated(exact)), sa(alone, deflated(exact));
  sw.assemble();
  sa.assemble();
  sw.solve(2e-4);
  sa.solve(2e-4);
  EXPECT_NEAR(sw.response().young_modulus / sa.response().young_modulus, 1.0, 1e-9);
  EXPECT_LT(worst_difference(wide, sw, alone, sa), 1e-8 * 2e-4);
}

TEST_F(Deflation, FollowsInPlaceChangesWithItsMultigridReused) {
  // Both systems keep their first preconditioner (as between load steps)
  // while bonds break in place: every 50th, and nine in ten of those that
  // hold particle 0 to the rest (by global id, so that every rank holding a
  // bond agrees).  The coarse operator W^T K W must follow K.
  const Lattice l = particle_lattice(4000);
  DistributedLattice lp = distributed(PETSC_COMM_WORLD, l), ld = distributed(PETSC_COMM_WORLD, l);
  // Ground springs (the default) keep K definite when nodes come loose.
  const SolverOptions grounded;
  ElasticSystem plain(lp, grounded), with(ld, deflated(grounded));
  for (ElasticSystem* s : {&plain, &with}) {
    s->set_reuse_preconditioner(true);
    s->assemble();
    s->solve(1e-4);
  }
  PetscLogDefaultBegin();
  const int setups = multigrid_setups();
  auto damage = [](DistributedLattice& dl, ElasticSystem& s) {
    for (int b = 0; b < dl.local_bonds(); ++b) {
      const auto [i, j] = dl.bond_ends[b];
      const bool leaves_0 = (dl.node_particle[i] == 0) != (dl.node_particle[j] == 0);
      if (dl.bond_id[b] % 50 == 0 || (leaves_0 && dl.bond_id[b] % 10 != 0))
        s.set_bond_stiffness(b, 0.0);
    }
    s.finish_updates();
  };
  damage(lp, plain);
  damage(ld, with);
  const SolveReport rp = plain.solve(1.5e-4), rd = with.solve(1.5e-4);
  const int its_plain = rp.iterations, its_deflated = rd.iterations;
  EXPECT_NEAR(with.response().young_modulus / plain.response().young_modulus, 1.0, 1e-9);
  EXPECT_LT(worst_tension_difference(ld, with, lp, plain), 1e-8);
  // 118 against 486 iterations on 1 rank, 117 against 545 on 2; with the
  // coarse operator of the intact K, 177 on 1 rank.
  EXPECT_LT(its_deflated, 0.3 * its_plain) << its_deflated << " against " << its_plain;
  // Neither multigrid was built again: the one inside the deflation is kept
  // like the plain one (PCApply would rebuild it after every change of K).
  EXPECT_EQ(multigrid_setups(), setups);
}

TEST_F(Deflation, FollowsPinnedNodes) {
  // One particle node in ten loses its bonds and is pinned (what loose nodes
  // get in a fracture run), and so does every node of particle 5: W loses
  // those degrees of freedom, and particle 5's six columns.
  const Lattice l = particle_lattice(4000);
  DistributedLattice lp = distributed(PETSC_COMM_WORLD, l), ld = distributed(PETSC_COMM_WORLD, l);
  const SolverOptions grounded;
  ElasticSystem plain(lp, grounded), with(ld, deflated(grounded));
  auto pin_cap = [](DistributedLattice& dl, ElasticSystem& s) {
    std::vector<char> pinned(dl.coords.size(), 0);
    std::vector<int> pins;
    for (std::size_t n = 0; n < dl.coords.size(); ++n)
      if (dl.node_particle[n] == 5 || (dl.node_particle[n] >= 0 && dl.node_id[n] % 10 == 0)) {
        pinned[n] = 1;
        pins.push_back(static_cast<int>(n));
      }
    for (int b = 0; b < dl.local_bonds(); ++b) {
      const auto [i, j] = dl.bond_ends[b];
      if (pinned[i] || pinned[j]) s.set_bond_stiffness(b, 0.0);
    }
    s.pin_nodes(pins);
    s.finish_updates();
  };
  for (auto [dl, s] : {std::pair{&lp, &plain}, std::pair{&ld, &with}}) {
    s->assemble();
    s->solve(1e-4);
    pin_cap(*dl, *s);
  }
  const SolveReport rp = plain.solve(1.5e-4), rd = with.solve(1.5e-4);
  const int its_plain = rp.iterations, its_deflated = rd.iterations;
  EXPECT_NEAR(with.response().young_modulus / plain.response().young_modulus, 1.0, 1e-9);
  EXPECT_LT(worst_tension_difference(ld, with, lp, plain), 1e-8);
  // 130 against 354 iterations on 1 rank, 130 against 389 on 2; with the
  // space of the unpinned lattice, 200 on 1 rank.
  EXPECT_LT(its_deflated, 0.45 * its_plain) << its_deflated << " against " << its_plain;
}

TEST_F(Deflation, LatticeWithoutParticlesIsRefused) {
  Lattice l = particle_lattice(1000);
  l.node_particle.clear();
  DistributedLattice dl = distributed(PETSC_COMM_WORLD, l);
  try {
    ElasticSystem system(dl, deflated(exact));
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("-solver_particle_deflation needs"), std::string::npos)
        << e.what();
  }
}
