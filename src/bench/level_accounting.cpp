// Per-level accounting of the multigrid cycle and the two cycle precisions
// side by side (lem_bench; lem/bench/benchmark.hpp).
#include "level_accounting.hpp"
#include "rank_max.hpp"

#include "lem/base/error.hpp"
#include "lem/base/log.hpp"
#include "lem/base/driver.hpp"
#include "lem/system/single_cycle.hpp"

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

}  // namespace

void account_levels(MPI_Comm comm, ElasticSystem& sys, DistributedLattice& lattice,
                    const SolverOptions& solver, Vec b, double delta, std::int64_t repeat) {
  const KSP ksp = sys.ksp();
  SingleCycle* cycle = SingleCycle::of(ksp);
  std::unique_ptr<SingleCycle> added;
  if (!cycle) {
    added =
        std::make_unique<SingleCycle>(lattice, solver.ground_stiffness * sys.constrained_diagonal(),
                                      sys.constrained_diagonal(), ksp);
    cycle = added.get();
    LEM_PETSC(KSPSetUp(ksp));
  }
  const PC mg = cycle->inner();
  PetscInt levels = 0;
  LEM_PETSC(PCMGGetLevels(mg, &levels));
  VecHandle x;
  LEM_PETSC(VecDuplicate(b, x.replace()));
  const char* stage_name = "Bench levels";
  PetscLogStage stage;
  constexpr std::size_t kVectorEvents = 8;  // the events before the levels' in a snapshot
  LEM_PETSC(PetscLogDefaultBegin());
  LEM_PETSC(PetscLogStageRegister(stage_name, &stage));
  const double bond_bytes = [&] {
    double local = sys.bond_operator_bytes(), total = 0;
    MPI_Allreduce(&local, &total, 1, MPI_DOUBLE, MPI_SUM, comm);
    return total;
  }();

  // One logged solve of each precision: the rows of the tables.
  for (const bool single : {false, true}) {
    cycle->use_single(single);
    cycle->reset_stats();
    std::vector<Perf> before;
    auto snapshot = [&] {
      std::vector<Perf> p;
      for (const char* e :
           {"PCApply", "MatMult", "VecTDot", "VecDot", "VecNorm", "VecAXPY", "VecAYPX", "VecCopy"})
        p.push_back(event_perf(stage_name, e));
      for (PetscInt l = 0; l < levels; ++l)
        for (const char* kind : {"MGSmooth", "MGResid", "MGInterp"})
          p.push_back(
              event_perf("MG Apply", (std::string(kind) + " Level " + std::to_string(l)).c_str()));
      return p;
    };
    LEM_PETSC(VecZeroEntries(x));
    before = snapshot();
    MPI_Barrier(comm);
    const double t0 = MPI_Wtime();
    LEM_PETSC(PetscLogStagePush(stage));
    LEM_PETSC(KSPSolve(ksp, b, x));
    LEM_PETSC(PetscLogStagePop());
    const double solve_seconds = max_over(comm, MPI_Wtime() - t0);
    const std::vector<Perf> after = snapshot();
    PetscInt its = 0;
    LEM_PETSC(KSPGetIterationNumber(ksp, &its));
    const double per = 1.0 / static_cast<double>(std::max<PetscInt>(its, 1));
    auto delta_of = [&](std::size_t k, bool count) {
      const double d =
          count ? after[k].count - before[k].count : after[k].seconds - before[k].seconds;
      return max_over(comm, d) * per;
    };
    // (The coarse solve of the single cycle is a KSPSolve and a PCApply of
    // its own, in the same stage: its own timer instead.)
    const double solve_ms = 1e3 * solve_seconds * per;
    const double pc_ms =
        1e3 * (single ? max_over(comm, cycle->apply_seconds()) * per : delta_of(0, false));
    const double matmult_ms = 1e3 * delta_of(1, false);
    double vector_ms = 0;  // CG's own vector operations and reductions
    for (std::size_t k = 2; k < kVectorEvents; ++k) vector_ms += 1e3 * delta_of(k, false);
    std::vector<Row> rows;
    double level_ms = 0;
    if (single) {
      const auto stats = cycle->level_stats();
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
        level_ms += r.ms;
        rows.push_back(r);
      }
    } else {
      for (PetscInt l = levels - 1; l >= 0; --l) {
        KSP smoother;
        Mat A;
        MatInfo info;
        PetscInt n = 0;
        LEM_PETSC(PCMGGetSmoother(mg, l, &smoother));
        LEM_PETSC(KSPGetOperators(smoother, nullptr, &A));
        LEM_PETSC(MatGetInfo(A, MAT_GLOBAL_SUM, &info));
        LEM_PETSC(MatGetSize(A, &n, nullptr));
        const std::size_t k = kVectorEvents + 3 * static_cast<std::size_t>(l);
        Row r;
        const long long depth = levels - 1 - l;
        r.name = l == levels - 1 ? "0 (fine, bonds)"
                 : l == 0        ? std::to_string(depth) + " (coarse, LU)"
                                 : std::to_string(depth);
        r.rows = n;
        r.nonzeros = static_cast<long long>(info.nz_used);
        r.ms = 1e3 * (delta_of(k, false) + delta_of(k + 1, false) + delta_of(k + 2, false));
        if (l > 0) {
          // The nonzero-guess smoother multiplies even a zero initial guess:
          // three products per visit, a restriction and an interpolation.
          r.visits = delta_of(k + 1, true);
          r.products = 3 * r.visits;
          r.transfers = 2 * r.visits;
          Mat P;
          LEM_PETSC(PCMGGetInterpolation(mg, l, &P));
          const double product =
              l == levels - 1 && bond_bytes > 0 ? bond_bytes : aij_product_bytes(A);
          PetscInt rows_here = 0;
          LEM_PETSC(MatGetSize(A, &rows_here, nullptr));
          r.megabytes =
              r.visits * (3 * product + 2 * aij_product_bytes(P) + 12.0 * 8.0 * rows_here) / 1e6;
        } else {
          r.visits = delta_of(k, true);
        }
        level_ms += r.ms;
        rows.push_back(r);
      }
    }
    Row product;
    product.name = bond_bytes > 0 ? "CG: operator (bonds)" : "CG: operator (K)";
    product.products = 1;
    product.megabytes = (bond_bytes > 0 ? bond_bytes : aij_product_bytes(sys.matrix())) / 1e6;
    product.ms = matmult_ms;
    rows.push_back(product);
    Row vectors;
    vectors.name = "CG: vectors, reductions";
    vectors.ms = vector_ms;
    rows.push_back(vectors);

    const std::string title = std::string("per-level accounting, ") +
                              (single ? "single" : "double") + "-precision cycle, one solve of " +
                              std::to_string(its) +
                              " CG its (per CG iteration; MB summed "
                              "over ranks):";
    // The measured figure: the same solve without the logging of levels.
    print_rows(title.c_str(), rows, solve_ms);
    say("  (the preconditioner: %.2f ms per CG iteration, %.2f of it in the level rows)\n", pc_ms,
        level_ms);
  }

  // Both precisions alternately, unlogged: ms per iteration, iterations,
  // and E_eff from the system's own solve from a zero field.
  std::vector<double> ms[2], cpu_ms[2], its[2];
  double young[2] = {0, 0};
  int system_its[2] = {0, 0};
  const std::vector<double> zero(3 * static_cast<std::size_t>(lattice.owned), 0.0);
  for (std::int64_t r = 0; r < repeat; ++r)
    for (int single = 0; single < 2; ++single) {
      cycle->use_single(single != 0);
      LEM_PETSC(VecZeroEntries(x));
      MPI_Barrier(comm);
      const double t = MPI_Wtime();
      const std::clock_t c = std::clock();
      LEM_PETSC(KSPSolve(ksp, b, x));
      const double seconds = max_over(comm, MPI_Wtime() - t);
      const double cpu = max_over(comm, static_cast<double>(std::clock() - c) / CLOCKS_PER_SEC);
      PetscInt n = 0;
      LEM_PETSC(KSPGetIterationNumber(ksp, &n));
      ms[single].push_back(1e3 * seconds / static_cast<double>(n));
      cpu_ms[single].push_back(1e3 * cpu / static_cast<double>(n));
      its[single].push_back(static_cast<double>(n));
      if (r == 0) {
        sys.set_state(zero, delta);
        const SolveReport report = sys.solve(delta);
        system_its[single] = report.iterations;
        young[single] = sys.response().young_modulus;
      }
    }
  const double memory = max_over(comm, cycle->memory_bytes()) / 1e6;
  const auto rss = peak_memory_per_rank_mb(comm);
  say("cycle precision (same preconditioner, %d alternating solves each):\n",
      static_cast<int>(ms[0].size()));
  say("  double: %.2f ms per CG iteration, %.0f its; E_eff %.12g (%d its from zero)\n",
      median_of(ms[0]), median_of(its[0]), young[0], system_its[0]);
  say("  single: %.2f ms per CG iteration, %.0f its; E_eff %.12g (%d its from zero)\n",
      median_of(ms[1]), median_of(its[1]), young[1], system_its[1]);
  say("  ratio double/single per CG iteration %.2f (each pair: ",
      median_of(ms[0]) / median_of(ms[1]));
  for (std::size_t k = 0; k < ms[0].size(); ++k) say("%s%.2f", k ? " " : "", ms[0][k] / ms[1][k]);
  say("), CPU time %.2f / %.2f ms = %.2f", median_of(cpu_ms[0]), median_of(cpu_ms[1]),
      median_of(cpu_ms[0]) / median_of(cpu_ms[1]));
  say("; |E_single - E_double| / E_double = %.1e; float copies %.1f MB per rank (max), "
      "peak RSS %.0f MB\n",
      std::fabs(young[1] - young[0]) / young[0], memory, *std::max_element(rss.begin(), rss.end()));
  say("# CYCLE columns: ranks,double_ms_per_it,single_ms_per_it,double_its,single_its,"
      "E_double,E_single,float_MB_per_rank\n");
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  say("CYCLE,%d,%.3f,%.3f,%.0f,%.0f,%.12g,%.12g,%.1f\n", ranks, median_of(ms[0]), median_of(ms[1]),
      median_of(its[0]), median_of(its[1]), young[0], young[1], memory);
  cycle->use_single(!added);  // as the options asked
  if (added) {                // the multigrid back on the KSP, as it was
    Mat A = nullptr, P = nullptr;
    LEM_PETSC(KSPGetOperators(ksp, &A, &P));
    LEM_PETSC(PetscObjectReference(reinterpret_cast<PetscObject>(A)));
    LEM_PETSC(PetscObjectReference(reinterpret_cast<PetscObject>(P)));
    LEM_PETSC(KSPSetPC(ksp, mg));
    LEM_PETSC(KSPSetOperators(ksp, A, P));
    MatDestroy(&A);
    MatDestroy(&P);
  }
}

}  // namespace lem
