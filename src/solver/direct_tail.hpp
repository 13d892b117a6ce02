// A direct route for the slow tail of a fracture run (-solver_direct_tail).
//
// Far past the peak of a sample with little matrix, CG with the multigrid
// needs hundreds of iterations a solve while each batch of ruptures removes
// only a few bonds.  Then one sparse Cholesky factorization of K (MUMPS), kept
// while the bonds break, is cheaper: every bond that breaks after it removes
// a rank-one term k g g^T from K (a central spring), so with U = [g_1 ...],
// S = diag(k_1 ...) and Z = F^-1 U (F the factored K),
//
//   (F - U S U^T)^-1 = F^-1 + Z (S^-1 - U^T Z)^-1 Z^T       (Woodbury),
//
// and a solve of the damaged K is one solve with the factor, m dot products
// and a product with Z: the capacitance C = S^-1 - U^T Z is small, dense and
// positive definite (K stays so, by its ground springs), factored on every
// rank and extended by a row per broken bond.  Each broken bond costs one
// more factor solve (a column of Z), done in blocks.  The route is a
// preconditioner around the multigrid: CG on the true K checks every solve,
// and takes one or two iterations while the route is exact.
//
// The route is taken when the last solves needed at least the option's
// iterations on average, and kept while its cost per solve (factorization,
// columns and solves since it was taken) stays below the multigrid's when it
// was left; otherwise the run goes back to the multigrid and takes the route
// again only when the multigrid has become slower than the route was.  The
// factor is made again when the columns reach -solver_direct_columns, when
// nodes are pinned, or when C loses its positive pivots.  Before the first
// factorization MUMPS's analysis estimates its memory: a route that would
// not fit -solver_direct_memory of a machine's available memory is not
// taken, and the run keeps the multigrid.
#pragma once

#include "lem/base/petsc_handle.hpp"
#include "lem/solver/wrapped_lever.hpp"

#include <petscksp.h>

#include <cstdint>
#include <deque>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace lem {

class DirectTail final : public WrappedLever {
 public:
  static constexpr const char* kType = "lem_direct_tail";
  static constexpr const char* kName = "direct route for the slow tail";
  /// The registry entry: -solver_direct_tail N chooses it.
  static SolverLeverEntry entry();

  DirectTail() = default;
  void operator_changed() override { changed_ = true; }
  void constraints_changed() override {
    changed_ = true;
    stale_factor_ = true;
  }
  void prepare(Vec b, Vec u) override;
  void after_solve() override;
  bool start_is_solution() const override { return rhs_ != nullptr; }
  std::string work_line() const override;

 private:
  /// Broken bonds carried by the low-rank update now.
  int columns() const { return static_cast<int>(delta_.size()); }
  friend class WrappedLever;
  void wrapped(const LeverSite& site) override;
  static PetscErrorCode apply(PC pc, Vec r, Vec z);
  void route_apply(Vec r, Vec z);
  void correct(Vec y);  // y = F^-1 r becomes the route's z

  bool want_route() const;
  bool want_multigrid() const;
  void factor();
  void check_memory();
  void factor_or_leave();
  void release();
  /// Adds the bonds changed since the factor (or the last update) as
  /// columns, solving for b in the same pass over the factor (solution_
  /// then holds F^-1 b): 1 if it did, 0 if nothing changed, -1 when the
  /// factor must be made again instead.
  int update(Vec b);
  bool add_columns(const std::vector<std::pair<std::int64_t, double>>& bonds, Vec b);
  /// t_j = g_j^T x over the owned dofs, for every column j: this rank's
  /// part (the caller sums over the ranks).
  void project(const PetscScalar* x, double* t) const;
  void solve_capacitance(std::vector<double>& t) const;  // t = C^-1 t

  const DistributedLattice* lattice_ = nullptr;
  Mat K_ = nullptr;
  int trigger_ = 0;          // mean iterations a solve that takes the route
  int most_columns_ = 0;     // columns before a new factorization
  double memory_share_ = 0;  // of a machine's available memory
  double estimated_mb_ = 0;  // MUMPS's factor and the columns, largest rank

  // The route.
  bool direct_ = false;
  bool changed_ = false;
  bool stale_factor_ = false;
  MatHandle K0_;                 // K as factored (a copy: K changes in place)
  MatHandle factor_;             // MUMPS's Cholesky factor of K0_
  std::vector<double> assumed_;  // per local bond: the stiffness the route assumes
  std::unordered_map<std::int64_t, int> local_bond_;  // bond id -> local index
  std::vector<char> in_column_;                       // per local bond
  // Per column: its bond's owned entries of g (dof, value), its k, and
  // Z's column (owned dofs) in one array, column after column.
  std::vector<std::vector<std::pair<int, double>>> g_;
  std::vector<double> delta_;
  std::vector<double> Z_;
  std::vector<std::vector<double>> L_;  // rows of the Cholesky factor of C
  int dofs_ = 0;                        // owned dofs

  // The route's K^-1 b of this solve: the solution CG starts from, and the
  // scale of its tolerance (the convergence test's application to b).
  VecHandle solution_;
  Vec rhs_ = nullptr;

  // What each route costs, measured (max over ranks).
  double solve_start_ = 0;
  int applications_ = 0;
  std::deque<std::pair<int, double>> recent_;  // multigrid solves: applications, seconds
  double multigrid_cost_ = 0;                  // seconds a solve when the route was taken
  double route_cost_ = 0;                      // seconds a solve of the route when it was left
  double route_seconds_ = 0;                   // since it was taken
  int route_solves_ = 0;

  // For the work line.
  int factorizations_ = 0, switches_back_ = 0, total_columns_ = 0, total_solves_ = 0;
  int route_applications_ = 0;
  double factor_seconds_ = 0, column_seconds_ = 0, solve_seconds_ = 0;
};

}  // namespace lem
