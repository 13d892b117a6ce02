// The built-in levers, one registration line each, in the order they are
// put around the multigrid (the first innermost).
#include "lem/solver/levers.hpp"

#include "damage_aggregates.hpp"
#include "particle_deflation.hpp"
#include "ritz_deflation.hpp"

#include "lem/system/solver_lever.hpp"

namespace lem {

void register_solver_levers() {
  static bool done = false;
  if (done) return;
  done = true;
  register_solver_lever(DamageAggregates::entry());
  register_solver_lever(ParticleDeflation::entry());
  register_solver_lever(RitzDeflation::entry());
}

}  // namespace lem
