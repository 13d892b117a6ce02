// Finer aggregates near broken bonds (-solver_damage_aggregates): a lever
// around GAMG that marks the nodes near the damage before every build, for
// GAMG's coarsening to split their aggregates (damage_aggregates.cpp).
#pragma once

#include "lem/solver/wrapped_lever.hpp"

#include "lem/system/distributed_lattice.hpp"

namespace lem {

class DamageAggregates final : public WrappedLever {
 public:
  static constexpr const char* kType = "lem_damage_aggregates";
  static constexpr const char* kName = "GAMG with its aggregates split near broken bonds";
  /// The registry entry: -solver_damage_aggregates N chooses it.
  static SolverLeverEntry entry();

  DamageAggregates() = default;
  void before_build() override;

 private:
  friend class WrappedLever;
  /// Throws InputError unless the wrapped PC is GAMG's aggregation.
  void wrapped(const LeverSite& site) override;
  static PetscErrorCode apply(PC pc, Vec r, Vec z);

  const DistributedLattice* lattice_ = nullptr;
  int layers_ = 0;
};

}  // namespace lem
