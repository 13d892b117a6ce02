// Per-level accounting of the multigrid cycle and the two cycle precisions
// side by side (lem_bench; lem/bench/benchmark.hpp).
#include "level_accounting.hpp"

#include "lem/base/collective.hpp"
#include "lem/base/error.hpp"
#include "lem/base/log.hpp"
#include "lem/base/driver.hpp"
#include "lem/solver/single_cycle.hpp"
#include "lem/system/solver_lever.hpp"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <string>
#include <vector>

namespace lem {
namespace {


double median_of(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n == 0 ? 0.0 : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Time and count of a logged event in a stage on this rank (0 if either
// does not exist).
struct Perf {
  double seconds = 0, count = 0;
};
Perf event_perf(const char* stage_name, const char* event_name) {
  PetscLogStage stage = -1;
  PetscLogEvent event = -1;
  if (PetscLogStageGetId(stage_name, &stage) || stage < 0) return {};
  if (PetscLogEventGetId(event_name, &event) || event < 0) return {};
  PetscEventPerfInfo info{};
  LEM_PETSC(PetscLogEventGetPerfInfo(stage, event, &info));
  return {info.time, static_cast<double>(info.count)};
}

struct Row {
  std::string name;
  long long rows = 0, nonzeros = 0;
  double visits = 0, products = 0, transfers = 0, megabytes = 0, ms = 0;
};

// Bytes of one product of an assembled AIJ level (values and column
// indices, row starts, x read, y written, b read by a residual).
double aij_product_bytes(Mat A) {
  MatInfo info;
  PetscInt rows = 0, cols = 0;
  LEM_PETSC(MatGetInfo(A, MAT_GLOBAL_SUM, &info));
  LEM_PETSC(MatGetSize(A, &rows, &cols));
  return 12.0 * info.nz_used + 4.0 * rows + 8.0 * (static_cast<double>(cols) + 2.0 * rows);
}

void print_rows(const char* title, const std::vector<Row>& rows, double ms_per_it) {
  say("%s\n", title);
  say("  %-22s %10s %12s %8s %9s %10s %9s %8s\n", "level", "rows", "nonzeros", "visits", "products",
      "transfers", "MB (model)", "ms");
  double sum = 0;
  for (const Row& r : rows) {
    say("  %-22s %10lld %12lld %8.2f %9.2f %10.2f %9.1f %8.2f\n", r.name.c_str(), r.rows,
        r.nonzeros, r.visits, r.products, r.transfers, r.megabytes, r.ms);
    sum += r.ms;
  }
  say("  sum of the rows %.2f ms = %.0f%% of the measured %.2f ms per CG iteration\n", sum,
      100.0 * sum / ms_per_it, ms_per_it);
}

// The per-level events of a stage, in a fixed order: CG's PCApply and
// MatMult, then kVectorEvents - 2 vector events, then three a level.
constexpr std::size_t kVectorEvents = 8;  // the events before the levels' in a snapshot

std::vector<Perf> snapshot(const char* stage_name, PetscInt levels) {
  std::vector<Perf> p;
  for (const char* e :
       {"PCApply", "MatMult", "VecTDot", "VecDot", "VecNorm", "VecAXPY", "VecAYPX", "VecCopy"})
    p.push_back(event_perf(stage_name, e));
  for (PetscInt l = 0; l < levels; ++l)
    for (const char* kind : {"MGSmooth", "MGResid", "MGInterp"})
      p.push_back(
          event_perf("MG Apply", (std::string(kind) + " Level " + std::to_string(l)).c_str()));
  return p;
}

// One logged solve: the events before and after it, and the iterations.
struct LoggedSolve {
  MPI_Comm comm;
  std::vector<Perf> before, after;
  PetscInt its = 0;
  double per = 1;  // 1 / iterations
  double seconds = 0;

  // The change of event k (its count, or its time) per CG iteration, on the
  // slowest rank.
  double delta(std::size_t k, bool count) const {
    const double d =
        count ? after[k].count - before[k].count : after[k].seconds - before[k].seconds;
    return max_over_ranks(comm, d) * per;
  }
};

LoggedSolve logged_solve(MPI_Comm comm, KSP ksp, Vec b, Vec x, PetscLogStage stage,
                         const char* stage_name, PetscInt levels) {
  LoggedSolve out;
  out.comm = comm;
  LEM_PETSC(VecZeroEntries(x));
  out.before = snapshot(stage_name, levels);
  MPI_Barrier(comm);
  const double t0 = MPI_Wtime();
  LEM_PETSC(PetscLogStagePush(stage));
  LEM_PETSC(KSPSolve(ksp, b, x));
  LEM_PETSC(PetscLogStagePop());
  out.seconds = max_over_ranks(comm, MPI_Wtime() - t0);
  out.after = snapshot(stage_name, levels);
  LEM_PETSC(KSPGetIterationNumber(ksp, &out.its));
  out.per = 1.0 / static_cast<double>(std::max<PetscInt>(out.its, 1));
  return out;
}

// The level rows of the single cycle, from its own counts.
std::vector<Row> single_cycle_rows(const SingleCycle& cycle, double per) {
  std::vector<Row> rows;
  const auto stats = cycle.level_stats();
  for (std::size_t i = 0; i < stats.size(); ++i) {
    const auto& s = stats[i];
    Row r;
    r.name = i == 0                  ? "0 (fine, bonds)"
             : i + 1 == stats.size() ? std::to_string(i) + " (coarse, double LU)"
                                     : std::to_string(i);
    r.rows = s.rows;
    r.nonzeros = s.nonzeros;
    r.visits = s.visits * per;
    r.products = s.products * per;
    r.transfers = s.transfers * per;
    r.megabytes = s.bytes * per / 1e6;
    r.ms = 1e3 * s.seconds * per;
    rows.push_back(r);
  }
  return rows;
}

// The level rows of PETSc's (double) cycle, from its logged events; the
// finest level's product is the bond operator's when `bond_bytes` > 0.
std::vector<Row> double_cycle_rows(PC mg, PetscInt levels, const LoggedSolve& solve,
                                   double bond_bytes) {
  std::vector<Row> rows;
  for (PetscInt l = levels - 1; l >= 0; --l) {
    const LevelOperator op = level_operator(mg, l);
    const Mat A = op.A;
    const PetscInt n = op.rows;
    const std::size_t k = kVectorEvents + 3 * static_cast<std::size_t>(l);
    Row r;
    const long long depth = levels - 1 - l;
    r.name = l == levels - 1 ? "0 (fine, bonds)"
             : l == 0        ? std::to_string(depth) + " (coarse, LU)"
                             : std::to_string(depth);
    r.rows = n;
    r.nonzeros = static_cast<long long>(op.nonzeros);
    r.ms = 1e3 * (solve.delta(k, false) + solve.delta(k + 1, false) + solve.delta(k + 2, false));
    if (l > 0) {
      // The nonzero-guess smoother multiplies even a zero initial guess:
      // three products per visit, a restriction and an interpolation.
      r.visits = solve.delta(k + 1, true);
      r.products = 3 * r.visits;
      r.transfers = 2 * r.visits;
      Mat P;
      LEM_PETSC(PCMGGetInterpolation(mg, l, &P));
      const double product = l == levels - 1 && bond_bytes > 0 ? bond_bytes : aij_product_bytes(A);
      r.megabytes = r.visits * (3 * product + 2 * aij_product_bytes(P) + 12.0 * 8.0 * n) / 1e6;
    } else {
      r.visits = solve.delta(k, true);
    }
    rows.push_back(r);
  }
  return rows;
}

// What the multigrid cycle and the benchmark measure it on.
struct CycleUnderTest {
  ElasticSystem& sys;
  SingleCycle& cycle;
  KSP ksp;
  PC mg;
  PetscInt levels = 0;
  double bond_bytes = 0;  // of the bond operator, summed over ranks (0: none)
};

// One logged solve of a precision, printed as the table of its levels.
void account_one_precision(MPI_Comm comm, const CycleUnderTest& c, bool single, Vec b, Vec x,
                           PetscLogStage stage, const char* stage_name) {
  c.cycle.use_single(single);
  c.cycle.reset_stats();
  const LoggedSolve solve = logged_solve(comm, c.ksp, b, x, stage, stage_name, c.levels);
  const double per = solve.per;
  // (The coarse solve of the single cycle is a KSPSolve and a PCApply of
  // its own, in the same stage: its own timer instead.)
  const double solve_ms = 1e3 * solve.seconds * per;
  const double pc_ms =
      1e3 * (single ? max_over_ranks(comm, c.cycle.apply_seconds()) * per : solve.delta(0, false));
  double vector_ms = 0;  // CG's own vector operations and reductions
  for (std::size_t k = 2; k < kVectorEvents; ++k) vector_ms += 1e3 * solve.delta(k, false);
  std::vector<Row> rows = single ? single_cycle_rows(c.cycle, per)
                                 : double_cycle_rows(c.mg, c.levels, solve, c.bond_bytes);
  double level_ms = 0;
  for (const Row& r : rows) level_ms += r.ms;
  Row product;
  product.name = c.bond_bytes > 0 ? "CG: operator (bonds)" : "CG: operator (K)";
  product.products = 1;
  product.megabytes = (c.bond_bytes > 0 ? c.bond_bytes : aij_product_bytes(c.sys.matrix())) / 1e6;
  product.ms = 1e3 * solve.delta(1, false);
  rows.push_back(product);
  Row vectors;
  vectors.name = "CG: vectors, reductions";
  vectors.ms = vector_ms;
  rows.push_back(vectors);

  const std::string title = std::string("per-level accounting, ") + (single ? "single" : "double") +
                            "-precision cycle, one solve of " + std::to_string(solve.its) +
                            " CG its (per CG iteration; MB summed "
                            "over ranks):";
  // The measured figure: the same solve without the logging of levels.
  print_rows(title.c_str(), rows, solve_ms);
  say("  (the preconditioner: %.2f ms per CG iteration, %.2f of it in the level rows)\n", pc_ms,
      level_ms);
  if (single) say("  (%s)\n", c.cycle.work_line().c_str());
}

// Both precisions alternately, unlogged (index 0 double, 1 single): ms
// per iteration (wall and CPU), iterations, and E_eff and iterations of
// the system's own solve from a zero field.
struct PrecisionRuns {
  std::vector<double> ms[2], cpu_ms[2], its[2];
  double young[2] = {0, 0};
  int system_its[2] = {0, 0};
};

PrecisionRuns alternate_precisions(MPI_Comm comm, const CycleUnderTest& c,
                                   const DistributedLattice& lattice, Vec b, Vec x, double delta,
                                   std::int64_t repeat) {
  PrecisionRuns out;
  const std::vector<double> zero(3 * static_cast<std::size_t>(lattice.owned), 0.0);
  for (std::int64_t r = 0; r < repeat; ++r)
    for (int single = 0; single < 2; ++single) {
      c.cycle.use_single(single != 0);
      LEM_PETSC(VecZeroEntries(x));
      MPI_Barrier(comm);
      const double t = MPI_Wtime();
      const std::clock_t cpu_start = std::clock();
      LEM_PETSC(KSPSolve(c.ksp, b, x));
      const double seconds = max_over_ranks(comm, MPI_Wtime() - t);
      const double cpu =
          max_over_ranks(comm, static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC);
      PetscInt n = 0;
      LEM_PETSC(KSPGetIterationNumber(c.ksp, &n));
      out.ms[single].push_back(1e3 * seconds / static_cast<double>(n));
      out.cpu_ms[single].push_back(1e3 * cpu / static_cast<double>(n));
      out.its[single].push_back(static_cast<double>(n));
      if (r == 0) {
        c.sys.set_state(zero, delta);
        const SolveReport report = c.sys.solve(delta);
        out.system_its[single] = report.iterations;
        out.young[single] = c.sys.response().young_modulus;
      }
    }
  return out;
}

void print_precisions(MPI_Comm comm, const PrecisionRuns& p, const SingleCycle& cycle) {
  const auto& ms = p.ms;
  const double memory = max_over_ranks(comm, cycle.memory_bytes()) / 1e6;
  const auto rss = peak_memory_per_rank_mb(comm);
  say("cycle precision (same preconditioner, %d alternating solves each):\n",
      static_cast<int>(ms[0].size()));
  say("  double: %.2f ms per CG iteration, %.0f its; E_eff %.12g (%d its from zero)\n",
      median_of(ms[0]), median_of(p.its[0]), p.young[0], p.system_its[0]);
  say("  single: %.2f ms per CG iteration, %.0f its; E_eff %.12g (%d its from zero)\n",
      median_of(ms[1]), median_of(p.its[1]), p.young[1], p.system_its[1]);
  say("  ratio double/single per CG iteration %.2f (each pair: ",
      median_of(ms[0]) / median_of(ms[1]));
  for (std::size_t k = 0; k < ms[0].size(); ++k) say("%s%.2f", k ? " " : "", ms[0][k] / ms[1][k]);
  say("), CPU time %.2f / %.2f ms = %.2f", median_of(p.cpu_ms[0]), median_of(p.cpu_ms[1]),
      median_of(p.cpu_ms[0]) / median_of(p.cpu_ms[1]));
  say("; |E_single - E_double| / E_double = %.1e; float copies %.1f MB per rank (max), "
      "peak RSS %.0f MB\n",
      std::fabs(p.young[1] - p.young[0]) / p.young[0], memory,
      *std::max_element(rss.begin(), rss.end()));
  say("# CYCLE columns: ranks,double_ms_per_it,single_ms_per_it,double_its,single_its,"
      "E_double,E_single,float_MB_per_rank\n");
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  say("CYCLE,%d,%.3f,%.3f,%.0f,%.0f,%.12g,%.12g,%.1f\n", ranks, median_of(ms[0]), median_of(ms[1]),
      median_of(p.its[0]), median_of(p.its[1]), p.young[0], p.young[1], memory);
}

// The multigrid `mg` back on the KSP in place of the single cycle, as it
// was before the benchmark added that.
void restore_multigrid(KSP ksp, PC mg) {
  Mat A = nullptr, P = nullptr;
  LEM_PETSC(KSPGetOperators(ksp, &A, &P));
  LEM_PETSC(PetscObjectReference(reinterpret_cast<PetscObject>(A)));
  LEM_PETSC(PetscObjectReference(reinterpret_cast<PetscObject>(P)));
  LEM_PETSC(KSPSetPC(ksp, mg));
  LEM_PETSC(KSPSetOperators(ksp, A, P));
  MatDestroy(&A);
  MatDestroy(&P);
}

}  // namespace

LevelOperator level_operator(PC mg, PetscInt level) {
  LevelOperator out;
  KSP smoother;
  MatInfo info;
  LEM_PETSC(PCMGGetSmoother(mg, level, &smoother));
  LEM_PETSC(KSPGetOperators(smoother, nullptr, &out.A));
  LEM_PETSC(MatGetInfo(out.A, MAT_GLOBAL_SUM, &info));
  LEM_PETSC(MatGetSize(out.A, &out.rows, nullptr));
  out.nonzeros = info.nz_used;
  return out;
}

void account_levels(MPI_Comm comm, ElasticSystem& sys, DistributedLattice& lattice,
                    const SolverOptions& solver, Vec b, double delta, std::int64_t repeat) {
  const KSP ksp = sys.ksp();
  PC pc;
  LEM_PETSC(KSPGetPC(ksp, &pc));
  SingleCycle* cycle = SingleCycle::of(ksp);
  if (!cycle && !SingleCycle::can_wrap(pc)) {  // the cycle walks PETSc's own multigrid only
    PetscPrintf(comm, "levels: not accounted (-pc_type is not gamg or mg)\n");
    return;
  }
  // A run of the double cycle gets a single cycle around its multigrid for
  // the comparison, as the option would have put it (owned by its PC, which
  // restore_multigrid drops again).
  const bool added = !cycle;
  if (added) {
    const double scale = sys.constrained_diagonal();
    const LeverSite site{lattice, sys.matrix(), solver.ground_stiffness * scale, scale, 1};
    compose_levers(ksp, {{SingleCycle::kType, 1}}, site);
    cycle = SingleCycle::of(ksp);
    LEM_PETSC(KSPSetUp(ksp));
  }
  CycleUnderTest c{sys, *cycle, ksp, cycle->inner()};
  LEM_PETSC(PCMGGetLevels(c.mg, &c.levels));
  VecHandle x;
  LEM_PETSC(VecDuplicate(b, x.replace()));
  const char* stage_name = "Bench levels";
  PetscLogStage stage;
  LEM_PETSC(PetscLogDefaultBegin());
  LEM_PETSC(PetscLogStageRegister(stage_name, &stage));
  const double local_bond_bytes = sys.bond_operator_bytes();
  MPI_Allreduce(&local_bond_bytes, &c.bond_bytes, 1, MPI_DOUBLE, MPI_SUM, comm);

  // One logged solve of each precision: the rows of the tables.
  for (const bool single : {false, true})
    account_one_precision(comm, c, single, b, x, stage, stage_name);
  print_precisions(comm, alternate_precisions(comm, c, lattice, b, x, delta, repeat), *cycle);
  cycle->use_single(!added);                // as the options asked
  if (added) restore_multigrid(ksp, c.mg);  // the multigrid back on the KSP, as it was
}

}  // namespace lem
