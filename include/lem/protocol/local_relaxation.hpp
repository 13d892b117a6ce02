// Relaxation whose cost follows the damage: after a batch of ruptures found
// in a global equilibrium, the nodes within R mean bond lengths of the
// ruptures since that equilibrium are relaxed with the rest held (a patch
// solve, relax_patch); bonds whose force in that patch field exceeds
// (1 + margin) times their threshold are broken as the next batch, and so on while patches find such bonds.  Then
// one global solve restores equilibrium, and the step goes on only from the
// bonds critical in that global field.
//
// Why this keeps the break decisions: a patch field differs from the global
// one by the effect of the held boundary, which decays like a force dipole
// (a few per cent of a typical bond force at R = 3-5 a).  A bond broken on a
// patch field is above (1 + margin) f there, so it is critical in the global
// field as long as the patch error is below margin f; bonds nearer their
// threshold wait for the global solve.  The bound is checked at run time:
// the last patch of every local phase has the same damage as the global
// solve that follows it, and its largest force error against that global
// field is recorded (patch_error_max); once it exceeds the margin, the run
// stops using patches (patch_disabled_step) and relaxes globally.
//
// Experimental: on the shipped cemented samples patch errors at R = 5 a
// reach 5-18 % of a threshold (docs/model/fracture-solver.md), so the default margin is
// exceeded early; it is not the default scheme.
#pragma once

#include "lem/protocol/relaxation.hpp"

#include "lem/base/cell_grid.hpp"

#include <vector>

namespace lem {

struct RelaxationEntry;

/// The options of the local scheme (-fracture_patch_*), its own.
struct LocalRelaxationOptions {
  double radius = 5.0;        // patch = nodes within this many a of new ruptures
  double margin = 0.05;       // a patch field breaks a bond only above (1 + margin) f
  double max_fraction = 0.2;  // larger patches are solved globally
  double rtol = 1e-6;         // patch solves to this fraction of their residual
};

/// The registry entry of the scheme `local`: its factory, options and
/// fingerprint sharing one LocalRelaxationOptions.
RelaxationEntry local_relaxation_entry();

class LocalRelaxation : public Relaxation {
 public:
  /// Collective.
  LocalRelaxation(const RelaxationParts& parts, const LocalRelaxationOptions& options);
  std::string saved_state() const override;
  void restore_state(const std::string& bytes) override;
  /// patch_solves, patch_iterations, patch_nodes_mean, patch_overflows,
  /// patch_error_max, patch_disabled_step.
  std::vector<std::pair<std::string, double>> report() const override;

 protected:
  /// Patches first (local_phase), then a global solve.
  CycleEnd cycle(std::int64_t step, double top_displacement, double strain,
                 const std::vector<Rupture>& batch, bool joined, RelaxationOutcome& out) override;

 private:
  /// What the scheme counts (its checkpoint state): patch solves, their CG
  /// iterations and total free nodes, patches too large that went global,
  /// the largest force error of a patch field against the global field that
  /// confirmed it (relative to max(f, mean threshold)), and the step at
  /// which patches were given up (0: never).
  struct Counters {
    std::int64_t solves = 0, iterations = 0, nodes = 0, overflows = 0;
    double error_max = 0;
    std::int64_t disabled_step = 0;
  } counters_;

  /// Owned nodes within the patch radius of the ruptures' midpoints.
  std::vector<int> patch_nodes(const std::vector<Rupture>& ruptures) const;
  /// Bonds whose force in the current (patch) field exceeds the certified
  /// level, in the order of CriticalBonds::find.  Collective.
  std::vector<Rupture> certain(const std::vector<Rupture>& critical) const;
  /// Patch solves after `batch`, breaking the bonds they certify; returns
  /// whether the faces are still joined.  `patch_tensions` gets the last
  /// patch field when it certified nothing (the one the global solve checks).
  bool local_phase(std::int64_t step, double strain, std::vector<Rupture> batch,
                   RelaxationOutcome& out, std::vector<double>& patch_tensions);
  /// Record the patch error against the global field; give patches up
  /// once it exceeds the margin.  Collective.
  void check_patch_error(std::int64_t step, const std::vector<double>& patch_tensions);
  /// Largest |T_global - T_patch| / max(f, mean f) over reported bonds.  Collective.
  double patch_error(const std::vector<double>& patch_tensions,
                     const std::vector<double>& global_tensions) const;

  LocalRelaxationOptions o_;
  double radius_ = 1;                    // the patch radius, lattice units
  CellGrid grid_;                        // cells at least the patch radius wide
  std::vector<std::vector<int>> cells_;  // owned nodes by cell
  std::int64_t free_nodes_ = 0;          // global count of owned nodes with a free dof
};

}  // namespace lem
