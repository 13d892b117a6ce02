// Finer aggregates near broken bonds (-solver_damage_aggregates).
//
// GAMG aggregates the finest level on the squared graph of K (aggregates
// two bonds across), which keeps its coarse levels small; on a damaged
// lattice those aggregates reach across weak necks and crack tips, and the
// coarse space misses the slow modes there (docs/notes/slow-modes.md: the
// plain graph everywhere saves a third of the iterations after the peak,
// for three times the bytes per iteration).  This lever keeps GAMG's
// aggregates where the lattice is intact and, before every build, marks
// the nodes near the damage; GAMG's coarsening of the finest level then
// splits each aggregate that holds a marked node into pieces one bond
// across (petsc318_private.cpp), so the coarse level grows only near the
// damage.  As a PC it only hands each application to the GAMG it wraps.
#include "damage_aggregates.hpp"

#include "petsc318_private.hpp"

#include "lem/base/error.hpp"

#include <utility>
#include <vector>

namespace lem {

SolverLeverEntry DamageAggregates::entry() {
  return WrappedLever::entry<DamageAggregates>(
      "-solver_damage_aggregates", [](OptionGroup& g) -> double {
        return static_cast<double>(g.integer(
            "-solver_damage_aggregates",
            "Split GAMG's aggregates of the finest level near broken bonds into pieces one "
            "bond across, at every preconditioner build: 1 splits those holding a node of a "
            "broken bond (bare contacts, which have no strength, not counted), 2 also those "
            "one intact bond away, ...; the coarse level grows only near the cracks "
            "(docs/model/fracture.md); 0: GAMG's aggregates as they are",
            0, 0, 4));
      });
}

void DamageAggregates::wrapped(const LeverSite& site) {
  lattice_ = &site.lattice;
  layers_ = static_cast<int>(site.setting);
  if (!is_gamg_aggregation(inner_))
    throw InputError("option -solver_damage_aggregates needs GAMG's aggregation (-pc_type gamg "
                     "-pc_gamg_type agg) as the preconditioner itself, not wrapped by a "
                     "deflation or the single-precision cycle");
  before_build();
}

// The owned nodes that end a broken bond (stiffness 0, a strength above 0),
// and with more layers those up to layers - 1 intact bonds from them.
void DamageAggregates::before_build() {
  const DistributedLattice& lattice = *lattice_;
  std::vector<char> near(lattice.owned, 0);
  for (int b = 0; b < lattice.local_bonds(); ++b) {
    if (lattice.bond_stiffness[b] != 0.0) continue;
    // Bare contacts (no strength) all break at the first load: they are the
    // texture of the sample, not a crack, and splitting there would grow the
    // coarse level everywhere (docs/notes/slow-modes.md).
    if (!lattice.bond_strength.empty() && lattice.bond_strength[b] <= 0.0) continue;
    for (int end : lattice.bond_ends[b])
      if (end < lattice.owned) near[end] = 1;
  }
  for (int layer = 1; layer < layers_; ++layer) {
    std::vector<char> grown = near;
    for (int b = 0; b < lattice.local_bonds(); ++b) {
      const int u = lattice.bond_ends[b][0], v = lattice.bond_ends[b][1];
      if (lattice.bond_stiffness[b] == 0.0 || u >= lattice.owned || v >= lattice.owned) continue;
      if (near[u]) grown[v] = 1;
      if (near[v]) grown[u] = 1;
    }
    near.swap(grown);
  }
  split_aggregates_near(inner_, std::move(near));
}

PetscErrorCode DamageAggregates::apply(PC pc, Vec r, Vec z) {
  PetscFunctionBeginUser;
  DamageAggregates* d = nullptr;
  PetscCall(context(pc, &d));
  PetscCall(PCApply(d->inner_, r, z));
  PetscFunctionReturn(0);
}

}  // namespace lem
