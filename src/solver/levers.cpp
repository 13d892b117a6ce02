// The built-in levers, one registration line each, in the order they are
// put around the multigrid (the first innermost).  The single-precision
// cycle copies the multigrid's own levels, so it comes first; the damage
// aggregates, which need GAMG itself too, then refuse to be chosen with it.
// The direct route comes last: while it is taken it replaces all the others.
#include "lem/solver/levers.hpp"

#include "damage_aggregates.hpp"
#include "direct_tail.hpp"
#include "particle_deflation.hpp"
#include "ritz_deflation.hpp"

#include "lem/solver/single_cycle.hpp"
#include "lem/system/solver_lever.hpp"

namespace lem {

void register_solver_levers() {
  static bool done = false;
  if (done) return;
  done = true;
  register_solver_lever(SingleCycle::entry());
  register_solver_lever(DamageAggregates::entry());
  register_solver_lever(ParticleDeflation::entry());
  register_solver_lever(RitzDeflation::entry());
  register_solver_lever(DirectTail::entry());
}

}  // namespace lem
