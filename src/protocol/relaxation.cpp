#include "lem/protocol/relaxation.hpp"

#include "lem/collective.hpp"
#include "lem/error.hpp"

#include <algorithm>

namespace lem {

namespace {
PetscLogStage rupture_stage() {
  static PetscLogStage stage = [] {
    PetscLogStage s;
    PetscLogStageRegister("Ruptures", &s);
    return s;
  }();
  return stage;
}
}  // namespace

GlobalRelaxation::GlobalRelaxation(const RelaxationParts& parts)
    : p_(parts), pieces_(parts.lattice) {}

bool GlobalRelaxation::pin_loose_pieces() {
  // Pinned rows trade their bonds for a diagonal of the same size: the kept
  // preconditioner stays usable (a failure would retry with a new one).
  const PieceReport pieces = pieces_.find();
  // Every rank must list the same nodes: gather the owned ones.
  std::vector<std::int64_t> owned_loose;
  for (int n : pieces.loose_nodes)
    if (n < p_.lattice.owned) owned_loose.push_back(p_.lattice.node_id[n]);
  std::vector<std::int64_t> loose = allgather(p_.lattice.comm, owned_loose);
  std::sort(loose.begin(), loose.end());
  if (!loose.empty()) {
    p_.tally.detached_bonds += p_.ledger.pin_nodes(loose);
    p_.tally.pinned_nodes += static_cast<std::int64_t>(loose.size());
  }
  p_.tally.pieces = pieces.pieces;
  return pieces.faces_joined;
}

RelaxationOutcome GlobalRelaxation::relax(std::int64_t step, double top_displacement,
                                          double strain, double stress_before) {
  RelaxationOutcome out;
  for (;;) {
    LEM_PETSC(PetscLogStagePush(rupture_stage()));
    const std::vector<Rupture> critical = p_.critical.find(p_.system.bond_tensions());
    if (critical.empty()) {
      LEM_PETSC(PetscLogStagePop());
      break;
    }
    p_.ledger.open_batch();
    std::vector<std::int64_t> ids;
    ids.reserve(critical.size());
    for (const Rupture& x : critical) {
      ids.push_back(x.id);
      p_.tally.broken[x.phase] += 1;
      p_.recorder.rupture(step, out.cycles, strain, x);
    }
    out.broken += static_cast<std::int64_t>(critical.size());
    p_.ledger.break_bonds(ids);
    const bool faces_joined = pin_loose_pieces();
    p_.system.finish_updates();
    LEM_PETSC(PetscLogStagePop());
    p_.solver.note_ruptures(static_cast<std::int64_t>(critical.size()));
    p_.solver.solve(top_displacement, true);
    out.cycles += 1;
    p_.progress.relaxing(step, out.cycles, out.broken, p_.clock.elapsed());
    if (!faces_joined) {
      out.disconnected = true;
      break;
    }
    if (p_.options.stop_within_step &&
        p_.system.response().stress_zz <
            p_.options.stop_fraction * std::max(p_.tally.peak_stress, stress_before))
      break;  // the run ends after this step (the stress check of the protocol)
  }
  if (out.broken > 0) p_.recorder.flush_ruptures();
  return out;
}

}  // namespace lem
