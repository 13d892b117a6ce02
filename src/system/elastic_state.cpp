// The state of the elastic system: the displacement field, the field kept
// beside it by a decided solve (the decision certificate), and what is
// computed from them (bond tensions, the macroscopic response).
#include "lem/system/elastic_system.hpp"

#include "bond_operator.hpp"

#include "lem/base/error.hpp"
#include "lem/system/lateral_strain.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace lem {

namespace {
// The ghost values of a ghosted field from their owners.
void update_ghost_values(Vec u_ghosted) {
  LEM_PETSC(VecGhostUpdateBegin(u_ghosted, INSERT_VALUES, SCATTER_FORWARD));
  LEM_PETSC(VecGhostUpdateEnd(u_ghosted, INSERT_VALUES, SCATTER_FORWARD));
}
}  // namespace

void ElasticSystem::update_ghosts() const { update_ghost_values(u_); }

Point ElasticSystem::local_displacement(const PetscScalar* u_local, int node) const {
  return {u_local[3 * node], u_local[3 * node + 1], u_local[3 * node + 2]};
}

namespace {
// Calls f(bond, n, stretch) for every local bond, with the unit vector n from
// the first to the second end and stretch = n.(u_second - u_first).
template <class F>
void for_each_bond_stretch(const DistributedLattice& l, Vec u_ghosted, F&& f) {
  Vec local;
  LEM_PETSC(VecGhostGetLocalForm(u_ghosted, &local));
  const PetscScalar* u = nullptr;
  LEM_PETSC(VecGetArrayRead(local, &u));
  for (int b = 0; b < l.local_bonds(); ++b) {
    const auto [p, q] = l.bond_ends[b];
    double n[3], stretch = 0;
    bond_direction(l, b, n);
    for (int a = 0; a < 3; ++a) stretch += n[a] * (u[3 * q + a] - u[3 * p + a]);
    f(b, n, stretch);
  }
  LEM_PETSC(VecRestoreArrayRead(local, &u));
  LEM_PETSC(VecGhostRestoreLocalForm(u_ghosted, &local));
}

// An owned node of the loaded top face.
bool owned_top(const DistributedLattice& l, int node) {
  return node < l.owned && (l.dof_flags[node] & kLoadedTop);
}

// A bond's share of the reaction on the top face (the load on a top node
// balances the pull of its bonds: +n on the first end, -n on the second).
double top_load_share(const DistributedLattice& l, int b, const double* n, double tension) {
  const auto [p, q] = l.bond_ends[b];
  double share = 0;
  if (owned_top(l, p)) share -= tension * n[2];
  if (owned_top(l, q)) share += tension * n[2];
  return share;
}

std::vector<double> tensions_of(const DistributedLattice& l, Vec u_ghosted) {
  std::vector<double> tension(l.local_bonds());
  for_each_bond_stretch(l, u_ghosted, [&](int b, const double*, double stretch) {
    tension[b] = l.bond_stiffness[b] * stretch;
  });
  return tension;
}
}  // namespace

std::vector<double> ElasticSystem::bond_tensions() const { return tensions_of(lattice_, u_); }

std::vector<double> ElasticSystem::check_tensions() const {
  if (equilibrium_ || !u_check_)
    throw std::logic_error("ElasticSystem::check_tensions: no check field (at an equilibrium, "
                           "or a patch field)");
  return tensions_of(lattice_, u_check_);
}

double ElasticSystem::stress_of(const std::vector<double>& tension) const {
  const DistributedLattice& l = lattice_;
  double local = 0, total = 0;
  for (int b = 0; b < l.local_bonds(); ++b) {
    const auto [p, q] = l.bond_ends[b];
    if (!owned_top(l, p) && !owned_top(l, q)) continue;  // the direction only where it counts
    double n[3];
    bond_direction(l, b, n);
    local += top_load_share(l, b, n, tension[b]);
  }
  MPI_Allreduce(&local, &total, 1, MPI_DOUBLE, MPI_SUM, l.comm);
  return total / (l.box.length(0) * l.box.length(1));
}

std::vector<Point> ElasticSystem::owned_displacements() const {
  std::vector<Point> d(lattice_.owned);
  const PetscScalar* u = nullptr;
  LEM_PETSC(VecGetArrayRead(u_, &u));
  for (int n = 0; n < lattice_.owned; ++n) d[n] = local_displacement(u, n);
  LEM_PETSC(VecRestoreArrayRead(u_, &u));
  return d;
}

TensionResponse ElasticSystem::response() const {
  const DistributedLattice& l = lattice_;
  // sums: reaction, energy of the bonds, energy of the ground springs.
  double sums[3] = {};
  for_each_bond_stretch(l, u_, [&](int b, const double* n, double stretch) {
    const double k = l.bond_stiffness[b], tension = k * stretch;
    if (l.bond_reported[b]) sums[1] += 0.5 * k * stretch * stretch;
    sums[0] += top_load_share(l, b, n, tension);
  });
  const PetscScalar* u = nullptr;
  LEM_PETSC(VecGetArrayRead(u_, &u));
  // The ground spring of every free degree of freedom of an owned node
  // (-lattice_ground_stiffness), as the matrix and the bond operator hold it.
  for (int n = 0; n < l.owned; ++n)
    for (int a = 0; a < 3; ++a)
      if (!is_fixed(l.dof_flags[n], a)) sums[2] += 0.5 * ground_ * u[3 * n + a] * u[3 * n + a];
  const LateralStrain lateral = lateral_strains(l, u);
  LEM_PETSC(VecRestoreArrayRead(u_, &u));
  double totals[3];
  MPI_Allreduce(sums, totals, 3, MPI_DOUBLE, MPI_SUM, l.comm);

  TensionResponse r;
  r.top_displacement = current_displacement_;
  r.reaction = totals[0];
  r.stored_energy = totals[1];
  r.ground_energy = totals[2];
  r.external_work = 0.5 * r.reaction * current_displacement_;
  r.stress_zz = r.reaction / (l.box.length(0) * l.box.length(1));
  r.strain_zz = current_displacement_ / l.box.length(2);
  r.strain_xx = lateral.xx;
  r.strain_yy = lateral.yy;
  if (r.strain_zz != 0) {
    r.young_modulus = r.stress_zz / r.strain_zz;
    r.poisson_ratio = -(r.strain_xx + r.strain_yy) / (2 * r.strain_zz);
  }
  return r;
}

namespace {
// Scale a ghosted field to a new top displacement.  `top`: set the loaded
// top values exactly to it (an equilibrium, whose scaled values may differ
// in the last bit); 0: scale only.
void scale_field(const DistributedLattice& l, Vec u_ghosted, double factor, double top) {
  LEM_PETSC(VecScale(u_ghosted, factor));
  if (top != 0) {
    PetscScalar* u = nullptr;
    LEM_PETSC(VecGetArray(u_ghosted, &u));
    for (int n = 0; n < l.owned; ++n)
      if (l.dof_flags[n] & kLoadedTop) u[3 * n + 2] = top;
    LEM_PETSC(VecRestoreArray(u_ghosted, &u));
  }
  update_ghost_values(u_ghosted);
}

std::vector<double> owned_values(const DistributedLattice& l, Vec u_ghosted) {
  std::vector<double> values(3 * static_cast<std::size_t>(l.owned));
  const PetscScalar* u = nullptr;
  LEM_PETSC(VecGetArrayRead(u_ghosted, &u));
  std::copy(u, u + values.size(), values.begin());
  LEM_PETSC(VecRestoreArrayRead(u_ghosted, &u));
  return values;
}

void set_owned_values(Vec u_ghosted, const std::vector<double>& values) {
  PetscScalar* u = nullptr;
  LEM_PETSC(VecGetArray(u_ghosted, &u));
  std::copy(values.begin(), values.end(), u);
  LEM_PETSC(VecRestoreArray(u_ghosted, &u));
  update_ghost_values(u_ghosted);
}
}  // namespace

void ElasticSystem::rescale(double top_displacement) {
  if (operator_changed_ || current_displacement_ == 0.0)
    throw std::logic_error("ElasticSystem::rescale: K changed (or nothing solved) since the "
                           "last solve");
  // Linear in the load: a decided field and its check field scale alike, so
  // the certificate of the scaled field is the scaled certificate.
  if (!equilibrium_ && !u_check_)
    throw std::logic_error("ElasticSystem::rescale: a field that is no equilibrium and has no "
                           "check field");
  // An unfinished CG iterate has not quite its prescribed values either
  // (the multigrid couples them in): a decided field is only scaled, so that
  // it stays the scaled field its certificate is about.
  const double factor = top_displacement / current_displacement_;
  scale_field(lattice_, u_, factor, equilibrium_ ? top_displacement : 0.0);
  if (!equilibrium_) scale_field(lattice_, u_check_, factor, 0.0);
  current_displacement_ = top_displacement;
  ties_settled_ = false;  // the near-ties of another load
}

void ElasticSystem::mark_check() {
  if (!u_check_) LEM_PETSC(VecDuplicate(u_, u_check_.replace()));
  LEM_PETSC(VecCopy(u_, u_check_));
  update_ghost_values(u_check_);
}

void ElasticSystem::stretch_check(double factor) {
  if (!u_check_) throw std::logic_error("ElasticSystem::stretch_check: no check field");
  LEM_PETSC(VecAXPBY(u_check_, 1.0 - factor, factor, u_));  // factor u_check + (1 - factor) u
  update_ghost_values(u_check_);
}

std::vector<double> ElasticSystem::solution() const { return owned_values(lattice_, u_); }

std::vector<double> ElasticSystem::check_solution() const {
  if (!equilibrium_ && !u_check_)
    throw std::logic_error("ElasticSystem::check_solution: a patch field has no check field");
  return equilibrium_ ? std::vector<double>{} : owned_values(lattice_, u_check_);
}

void ElasticSystem::set_state(const std::vector<double>& owned, double top_displacement,
                              const std::vector<double>& owned_check) {
  const std::size_t size = 3 * static_cast<std::size_t>(lattice_.owned);
  if (owned.size() != size || (!owned_check.empty() && owned_check.size() != size))
    throw std::logic_error("ElasticSystem::set_state: wrong number of values");
  set_owned_values(u_, owned);
  if (!owned_check.empty()) {
    if (!u_check_) LEM_PETSC(VecDuplicate(u_, u_check_.replace()));
    set_owned_values(u_check_, owned_check);
  }
  current_displacement_ = top_displacement;
  operator_changed_ = false;  // the caller restores a state of the current K
  equilibrium_ = owned_check.empty();
  // What tolerance a kept field met is not kept: the least, -ksp_rtol.
  field_rtol_ = equilibrium_ ? rtol() : std::numeric_limits<double>::infinity();
  ties_settled_ = false;
}

namespace {

// The space of the first lever that learns (choices exclude a second).
SolverLever* learner(const std::vector<SolverLever*>& levers) {
  for (SolverLever* lever : levers)
    if (!lever->learning_option().empty()) return lever;
  return nullptr;
}

}  // namespace

std::vector<VecHandle> ElasticSystem::learnt_space() const {
  const SolverLever* lever = learner(levers_);
  return lever ? lever->learnt_space() : std::vector<VecHandle>{};
}

void ElasticSystem::restore_learnt_space(const std::vector<std::vector<double>>& columns) {
  SolverLever* lever = learner(levers_);
  if (!lever) return;
  std::vector<VecHandle> space;
  for (const std::vector<double>& owned : columns) {
    if (owned.size() != 3 * static_cast<std::size_t>(lattice_.owned))
      throw std::logic_error("ElasticSystem::restore_learnt_space: wrong number of values");
    space.emplace_back();
    LEM_PETSC(MatCreateVecs(K_, space.back().replace(), nullptr));
    PetscScalar* w = nullptr;
    LEM_PETSC(VecGetArray(space.back(), &w));
    std::copy(owned.begin(), owned.end(), w);
    LEM_PETSC(VecRestoreArray(space.back(), &w));
  }
  lever->restore_learnt_space(std::move(space));
}

std::string ElasticSystem::learning_option() const {
  const SolverLever* lever = learner(levers_);
  return lever ? lever->learning_option() : "";
}

}  // namespace lem
