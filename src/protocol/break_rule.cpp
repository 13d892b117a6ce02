#include "lem/protocol/break_rule.hpp"

#include "lem/base/collective.hpp"
#include "lem/base/error.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace lem {

bool is_critical(double tension, double threshold, double force_floor) {
  return tension > threshold && tension > force_floor;
}

bool more_critical(const Rupture& a, const Rupture& b) {
  return a.ratio > b.ratio || (a.ratio == b.ratio && a.id < b.id);
}

double first_breaking_step(std::int64_t step, double tension, double threshold,
                           double force_floor) {
  const double f = std::max(threshold, force_floor);
  return std::floor(static_cast<double>(step) * f / tension) + 1.0;
}

double doubt_edge(double level, double band) { return std::max(level - band, 0.5 * level); }

bool in_doubt(double tension, double level, double band) {
  return band > 0 && tension > doubt_edge(level, band) && tension <= level + band;
}

namespace {

class AllCritical final : public BreakRule {
 public:
  std::vector<Rupture> batch(std::vector<Rupture> critical) const override { return critical; }
  bool set_decides_batch() const override { return true; }
};

class MostCritical final : public BreakRule {
 public:
  std::vector<Rupture> batch(std::vector<Rupture> critical) const override {
    if (critical.empty()) return critical;
    return {*std::min_element(critical.begin(), critical.end(), more_critical)};
  }
  bool set_decides_batch() const override { return false; }
};

}  // namespace

std::unique_ptr<BreakRule> make_all_critical_rule() { return std::make_unique<AllCritical>(); }

std::unique_ptr<BreakRule> make_most_critical_rule() { return std::make_unique<MostCritical>(); }

CriticalBonds::CriticalBonds(const DistributedLattice& l, const BreakRule& rule, double tie_band)
    : lattice_(l), rule_(rule) {
  // Forces below the floor are solver noise.
  double sums[2] = {0, 0}, totals[2];
  for (int b = 0; b < l.local_bonds(); ++b)
    if (l.bond_reported[b] && !l.bond_strength.empty() && l.bond_strength[b] > 0)
      sums[0] += l.bond_strength[b], sums[1] += 1;
  MPI_Allreduce(sums, totals, 2, MPI_DOUBLE, MPI_SUM, l.comm);
  mean_threshold_ = totals[1] > 0 ? totals[0] / totals[1] : 1.0;
  force_floor_ = totals[1] > 0 ? 1e-6 * totals[0] / totals[1] : 0.0;
  band_ = tie_band * mean_threshold_;
}

double CriticalBonds::level(int b) const {
  return std::max(lattice_.bond_strength[b], force_floor_);
}

bool CriticalBonds::in_doubt(const std::vector<double>& tension) const {
  const DistributedLattice& l = lattice_;
  int mine = 0, any = 0;
  for (int b = 0; b < l.local_bonds() && band_ > 0 && !mine; ++b)
    mine =
        l.bond_reported[b] && l.bond_stiffness[b] > 0 && lem::in_doubt(tension[b], level(b), band_);
  MPI_Allreduce(&mine, &any, 1, MPI_INT, MPI_MAX, l.comm);
  return any != 0;
}

bool CriticalBonds::doubts_decided(const std::vector<double>& tension, double error) const {
  const DistributedLattice& l = lattice_;
  int open = 0, any = 0;
  for (int b = 0; b < l.local_bonds() && band_ > 0 && !open; ++b)
    open = l.bond_reported[b] && l.bond_stiffness[b] > 0 &&
           lem::in_doubt(tension[b], level(b), band_) && !(std::abs(tension[b] - level(b)) > error);
  MPI_Allreduce(&open, &any, 1, MPI_INT, MPI_MAX, l.comm);
  return any == 0;
}

double ErrorTail::next(double change) {
  const double rho = earlier_ > 0 ? change / earlier_ : 1.0;
  earlier_ = change;
  return rho < 1 ? std::max(1.0, rho / (1 - rho)) : 0.0;
}

std::vector<Rupture> CriticalBonds::find(const std::vector<double>& tension) const {
  const DistributedLattice& l = lattice_;
  std::int64_t bad = -1, worst = -1;
  for (int b = 0; b < l.local_bonds() && bad < 0; ++b)
    if (!std::isfinite(tension[b])) bad = l.bond_id[b];
  MPI_Allreduce(&bad, &worst, 1, MPI_INT64_T, MPI_MAX, l.comm);  // every rank decides alike
  if (worst >= 0) throw NumericalError("bond " + std::to_string(worst) + " has a non-finite force");
  std::vector<Rupture> mine;
  for (int b = 0; b < l.local_bonds(); ++b) {
    if (!l.bond_reported[b] || l.bond_stiffness[b] <= 0) continue;
    const double t = tension[b], f = l.bond_strength[b];
    if (!is_critical(t, f, force_floor_)) continue;
    const auto [p, q] = l.bond_ends[b];
    Rupture r{};
    r.id = l.bond_id[b];
    r.ratio = f > 0 ? t / f : std::numeric_limits<double>::infinity();
    r.force = t;
    r.threshold = f;
    r.x = 0.5 * (l.coords[p][0] + l.coords[q][0]);
    r.y = 0.5 * (l.coords[p][1] + l.coords[q][1]);
    r.z = 0.5 * (l.coords[p][2] + l.coords[q][2]);
    r.phase = l.bond_tag.empty() ? 0 : static_cast<int>(l.bond_tag[b]);
    mine.push_back(r);
  }
  auto all = allgather(l.comm, mine);
  std::sort(all.begin(), all.end(), [](const Rupture& a, const Rupture& b) { return a.id < b.id; });
  return rule_.batch(std::move(all));
}

double CriticalBonds::force_error(const std::vector<double>& tension,
                                  const std::vector<double>& earlier, double safety) const {
  const DistributedLattice& l = lattice_;
  double mine = 0, all = 0;
  for (int b = 0; b < l.local_bonds(); ++b)
    if (l.bond_reported[b] && l.bond_stiffness[b] > 0)
      mine = std::max(mine, std::abs(tension[b] - earlier[b]));  // NaN: left to find()
  MPI_Allreduce(&mine, &all, 1, MPI_DOUBLE, MPI_MAX, l.comm);
  return safety * all;
}

FieldDecision CriticalBonds::decide(const std::vector<double>& tension,
                                    const std::vector<double>& earlier, double safety) const {
  const DistributedLattice& l = lattice_;
  // One error for every force: the slow part of a solver's error is smooth
  // and reaches bonds whose own force hardly changes (a contact that carries
  // nothing), so a bond's own change says nothing about its error.
  const double error = force_error(tension, earlier, safety);
  std::int64_t counts[2] = {0, 0}, totals[2];  // certainly critical, undecided
  for (int b = 0; b < l.local_bonds(); ++b) {
    if (!l.bond_reported[b] || l.bond_stiffness[b] <= 0) continue;
    const double t = tension[b];
    const double level = this->level(b);
    if (!std::isfinite(t) || std::abs(t - level) <= error || lem::in_doubt(t, level, band_)) {
      counts[1] += 1;  // a non-finite force is left to the full solve (find() names it)
      break;
    }
    if (t > level) counts[0] += 1;
  }
  MPI_Allreduce(counts, totals, 2, MPI_INT64_T, MPI_SUM, l.comm);
  if (totals[1] > 0) return FieldDecision::undecided;
  if (totals[0] == 0) return FieldDecision::holds;
  return rule_.set_decides_batch() ? FieldDecision::breaks : FieldDecision::undecided;
}

std::int64_t CriticalBonds::next_step(const std::vector<double>& tension, std::int64_t step,
                                      std::int64_t max_steps, const std::vector<double>* earlier,
                                      double safety) const {
  const DistributedLattice& l = lattice_;
  const double error = earlier ? force_error(tension, *earlier, safety) : 0.0;
  double first = std::numeric_limits<double>::infinity();
  for (int b = 0; b < l.local_bonds(); ++b) {
    const double t = tension[b] + error;
    if (!l.bond_reported[b] || l.bond_stiffness[b] <= 0 || !(t > 0)) continue;
    // From the edge of the doubt band: a near-tie is then met at a step that
    // is evaluated (and re-solved), never skipped over on one rank count.
    first = std::min(first, first_breaking_step(step, t, doubt_edge(level(b), band_), 0.0));
  }
  double global = 0;
  MPI_Allreduce(&first, &global, 1, MPI_DOUBLE, MPI_MIN, l.comm);
  // Progress is guaranteed; rounding at most costs an idle evaluation.
  const double n = static_cast<double>(step);
  const double cap = static_cast<double>(max_steps) + 1.0;
  return static_cast<std::int64_t>(std::max(n + 1.0, std::min(global, cap)));
}

void CriticalBonds::check_first_increment(const std::vector<double>& tension,
                                          double increment) const {
  const DistributedLattice& l = lattice_;
  double local[2] = {0, 0}, global[2];  // count over threshold, largest force/threshold
  std::int64_t counted = 0, total = 0;
  for (int b = 0; b < l.local_bonds(); ++b) {
    if (!l.bond_reported[b] || l.bond_stiffness[b] <= 0 || l.bond_strength[b] <= 0) continue;
    ++counted;
    const double ratio = tension[b] / l.bond_strength[b];
    if (ratio > 1) local[0] += 1;
    local[1] = std::max(local[1], ratio);
  }
  MPI_Allreduce(&local[0], &global[0], 1, MPI_DOUBLE, MPI_SUM, l.comm);
  MPI_Allreduce(&local[1], &global[1], 1, MPI_DOUBLE, MPI_MAX, l.comm);
  MPI_Allreduce(&counted, &total, 1, MPI_INT64_T, MPI_SUM, l.comm);
  if (total > 0 && global[0] > 1e-3 * static_cast<double>(total)) {
    std::ostringstream m;
    m << "option -fracture_increment = " << increment << " is too large for this sample: "
      << "the first increment already overloads " << static_cast<long long>(global[0])
      << " bonds (up to " << global[1] << " times their threshold); take it below "
      << increment / (10 * global[1]) << " so that the elastic regime has a few steps";
    throw InputError(m.str());
  }
}

}  // namespace lem
