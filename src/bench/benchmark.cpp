#include "lem/bench/benchmark.hpp"

#include "level_accounting.hpp"
#include "rank_max.hpp"

#include "lem/base/driver.hpp"
#include "lem/base/error.hpp"
#include "lem/base/log.hpp"
#include "lem/base/options.hpp"
#include "lem/base/petsc_handle.hpp"
#include "lem/lattice/voronoi.hpp"
#include "lem/system/single_cycle.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <numeric>
#include <string>
#include <vector>

namespace lem {

namespace {


// Wall time of f() on the slowest rank, all ranks starting together.
template <class F>
double timed(MPI_Comm comm, F&& f) {
  MPI_Barrier(comm);
  const double t = MPI_Wtime();
  f();
  return max_over(comm, MPI_Wtime() - t);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n == 0 ? 0.0 : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string list(const std::vector<double>& v) {
  std::string s;
  for (double x : v) {
    if (!s.empty()) s += ' ';
    s += std::to_string(static_cast<long>(x));
  }
  return s;
}

// STREAM triad a = b + s c on every rank at once (three arrays of `mb` MB per
// rank); aggregate GB/s counting 24 bytes per element, best of 5.
double stream_triad_gbs(MPI_Comm comm, double mb) {
  const auto n = static_cast<std::size_t>(mb * 1e6 / 8.0);
  std::vector<double> a(n, 0.0), b(n, 1.0), c(n, 2.0);  // first touch here
  double best = 1e300;
  for (int trial = 0; trial < 5; ++trial) {
    const double s = 0.5 + trial;
    best = std::min(best, timed(comm, [&] {
                      for (std::size_t i = 0; i < n; ++i) a[i] = b[i] + s * c[i];
                    }));
  }
  if (a[n / 2] != 1.0 + 4.5 * 2.0) throw std::logic_error("STREAM triad: wrong result");
  int size = 1;
  MPI_Comm_size(comm, &size);
  return 24.0 * static_cast<double>(n) * size / best / 1e9;
}

// The multigrid of `ksp`: its PC, or the one inside the single-precision cycle.
PC multigrid(KSP ksp) {
  if (SingleCycle* cycle = SingleCycle::of(ksp)) return cycle->inner();
  PC pc;
  LEM_PETSC(KSPGetPC(ksp, &pc));
  return pc;
}

// Rows and nonzeros of each multigrid level, finest first (PCMG/PCGAMG only).
void print_levels(KSP ksp) {
  PC pc = multigrid(ksp);
  PetscBool mg = PETSC_FALSE;
  LEM_PETSC(PetscObjectTypeCompareAny(reinterpret_cast<PetscObject>(pc), &mg, PCGAMG, PCMG, ""));
  if (!mg) return;
  PetscInt levels = 0;
  LEM_PETSC(PCMGGetLevels(pc, &levels));
  double fine = 0, total = 0;
  std::string text;
  for (PetscInt l = levels - 1; l >= 0; --l) {
    KSP smoother;
    Mat A;
    MatInfo info;
    PetscInt rows = 0;
    LEM_PETSC(PCMGGetSmoother(pc, l, &smoother));
    LEM_PETSC(KSPGetOperators(smoother, nullptr, &A));  // assembled even with -pc_use_amat
    LEM_PETSC(MatGetInfo(A, MAT_GLOBAL_SUM, &info));
    LEM_PETSC(MatGetSize(A, &rows, nullptr));
    if (l == levels - 1) fine = info.nz_used;
    total += info.nz_used;
    text += ' ';
    text += std::to_string(rows);
    text += '/';
    text += std::to_string(static_cast<long long>(info.nz_used));
  }
  say("multigrid: %d levels, rows/nnz fine to coarse:%s, operator complexity %.3f\n",
      static_cast<int>(levels), text.c_str(), total / fine);
}

// Make `A` the operator of `ksp`'s CG and of the multigrid's finest level
// (smoother and residual), with the preconditioner built from `P` kept.
// KSPSetOperators alone is not enough: a PC that is already set up keeps the
// finest level's operators of its set-up.
void use_fine_operator(KSP ksp, Mat A, Mat P) {
  LEM_PETSC(KSPSetOperators(ksp, A, P));
  PC pc = multigrid(ksp);
  PetscInt levels = 0;
  LEM_PETSC(PCMGGetLevels(pc, &levels));
  if (levels < 2) return;
  KSP smoother;
  LEM_PETSC(PCMGGetSmoother(pc, levels - 1, &smoother));
  LEM_PETSC(KSPSetOperators(smoother, A, P));
  LEM_PETSC(PCMGSetResidual(pc, levels - 1, PCMGResidualDefault, A));
}

// Box-clipped Voronoi volumes of a random lattice, timed on rank 0 (the
// routine is serial).  The volumes must tile the box, or the figure is void.
void bench_voronoi(MPI_Comm comm, RandomLatticeSpec spec, std::int64_t repeat) {
  run_on_root(comm, [&] {
    double t = MPI_Wtime();
    const Lattice lattice = make_random_lattice(spec);
    const double generation = MPI_Wtime() - t;
    std::vector<double> seconds;
    double gap = 0;
    for (std::int64_t r = 0; r < std::max<std::int64_t>(repeat, 1); ++r) {
      t = MPI_Wtime();
      const std::vector<double> v = voronoi_volumes(lattice);
      seconds.push_back(MPI_Wtime() - t);
      const double volume = lattice.box.volume();
      gap = std::fabs(std::accumulate(v.begin(), v.end(), 0.0) - volume) / volume;
      if (gap > 1e-10) throw NumericalError("Voronoi volumes do not tile the box");
    }
    std::printf("voronoi_volumes: %zu nodes, %zu bonds (generation %.2f s): median %.3f s "
                "over %zu runs (min %.3f, max %.3f); |sum - V|/V = %.1e\n",
                lattice.node_count(), lattice.bond_count(), generation, median(seconds),
                seconds.size(), *std::min_element(seconds.begin(), seconds.end()),
                *std::max_element(seconds.begin(), seconds.end()), gap);
    std::printf("# VORONOI columns: nodes,bonds,generation_s,median_s,runs\n");
    std::printf("VORONOI,%zu,%zu,%.3f,%.4f,%zu\n", lattice.node_count(), lattice.bond_count(),
                generation, median(seconds), seconds.size());
  });
}

}  // namespace

void run_voronoi_benchmark(MPI_Comm comm, SampleOptions sample, const BenchOptions& bench) {
  sample.random.nodes = bench.voronoi_nodes;
  sample.random.bonds = 0;
  bench_voronoi(comm, sample.random, bench.repeat);
}

void run_tension_benchmark(MPI_Comm comm, SampleOptions sample, const BenchOptions& bench,
                           const SolverOptions& solver) {
  const std::int64_t repeat = bench.repeat, matmults = bench.matmults;
  const bool morton = bench.morton;
  const double stream_mb = bench.stream_mb;
  sample.random.nodes = 0;
  sample.random.bonds = bench.bonds;
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);

  SetupReport setup;
  // The serial set-up takes -bench_morton; the parallel one (a sample file
  // with -sample_parallel, the cells generator) numbers along the Morton
  // curve inside its cell partition.
  const bool serial = !sample.parallel && sample.generator == LatticeGenerator::serial;
  const double t_setup = MPI_Wtime();
  auto lattice = !serial ? setup_sample_lattice(comm, sample, setup)
                         : setup_tension_lattice(
                               comm, [&](SampleInfo& info) { return build_sample(sample, info); },
                               setup, morton);
  const double seconds_setup = MPI_Wtime() - t_setup;
  const auto rss_setup = peak_memory_per_rank_mb(comm);
  const long long nodes = setup.sample.stats.nodes, nbonds = setup.sample.stats.bonds;
  say("lattice: %lld nodes, %lld bonds (%lld active), %d ranks, %s, edge cut %lld\n", nodes, nbonds,
      static_cast<long long>(setup.active_bonds), ranks,
      serial ? (morton ? "Morton order" : "METIS order") : "set up in parallel (cells)",
      static_cast<long long>(setup.edge_cut));
  // Load balance: the largest rank's share over the mean.
  const auto max_over_mean = [&](double mine) {
    double largest = 0, total = 0;
    MPI_Allreduce(&mine, &largest, 1, MPI_DOUBLE, MPI_MAX, comm);
    MPI_Allreduce(&mine, &total, 1, MPI_DOUBLE, MPI_SUM, comm);
    return total > 0 ? largest * ranks / total : 1.0;
  };
  say("balance:  owned nodes max/mean %.3f, bonds held max/mean %.3f; set-up %.2f s\n",
      max_over_mean(lattice.owned), max_over_mean(lattice.local_bonds()), seconds_setup);

  const double delta = 3e-4 * lattice.mean_bond_length;
  // The events of every multigrid level (the per-level accounting).
  {
    PetscBool set = PETSC_FALSE;
    LEM_PETSC(PetscOptionsHasName(nullptr, nullptr, "-pc_mg_log", &set));
    if (!set) LEM_PETSC(PetscOptionsSetValue(nullptr, "-pc_mg_log", "true"));
  }
  ElasticSystem* sys = nullptr;
  const double t_create = timed(comm, [&] { sys = new ElasticSystem(lattice, solver); });
  std::unique_ptr<ElasticSystem> owner(sys);
  check_unused_options(SolverStage::created);
  const double t_asm = timed(comm, [&] { sys->assemble(); });
  const SolveReport first = sys->solve(delta);
  check_unused_options();
  const Mat K = sys->matrix();
  const KSP ksp = sys->ksp();
  PC pc;
  LEM_PETSC(KSPGetPC(ksp, &pc));
  print_levels(ksp);
  // The figures up to the per-level accounting are those of the double cycle.
  if (SingleCycle* cycle = SingleCycle::of(ksp)) cycle->use_single(false);

  // b = K u reproduces the right-hand side of the problem just solved.
  VecHandle x, b;
  LEM_PETSC(MatCreateVecs(K, x.replace(), b.replace()));
  {
    const auto u = sys->owned_displacements();
    PetscScalar* xa = nullptr;
    LEM_PETSC(VecGetArray(x, &xa));
    for (std::size_t n = 0; n < u.size(); ++n)
      for (std::size_t a = 0; a < 3; ++a) xa[3 * n + a] = u[n][a];
    LEM_PETSC(VecRestoreArray(x, &xa));
    LEM_PETSC(MatMult(K, x, b));
  }
  std::vector<double> asm_s, setup_s, solve_s, its;
  for (std::int64_t r = 0; r < repeat; ++r) {
    asm_s.push_back(timed(comm, [&] { sys->assemble(); }));
    // KSPSetUp alone does not rebuild the PC after a change of matrix values
    // (KSPSolve would, inside the solve timing): call PCSetUp explicitly.
    setup_s.push_back(timed(comm, [&] {
      LEM_PETSC(KSPSetUp(ksp));
      LEM_PETSC(PCSetUp(pc));
    }));
    LEM_PETSC(VecZeroEntries(x));
    solve_s.push_back(timed(comm, [&] { LEM_PETSC(KSPSolve(ksp, b, x)); }));
    PetscInt n = 0;
    KSPConvergedReason reason;
    LEM_PETSC(KSPGetIterationNumber(ksp, &n));
    LEM_PETSC(KSPGetConvergedReason(ksp, &reason));
    if (reason < 0) throw NumericalError("repeated solve diverged");
    its.push_back(static_cast<double>(n));
  }

  // One fine-level MatMult: time, bytes (values + column indices + row
  // starts + x read + y written; ghost exchange not counted).
  const double t_mm = timed(comm,
                            [&] {
                              for (std::int64_t k = 0; k < matmults; ++k)
                                LEM_PETSC(MatMult(K, x, b));
                            }) /
                      static_cast<double>(matmults);
  MatInfo info;
  PetscInt rows = 0, bs = 1;
  MatType type;
  LEM_PETSC(MatGetInfo(K, MAT_GLOBAL_SUM, &info));
  LEM_PETSC(MatGetSize(K, &rows, nullptr));
  LEM_PETSC(MatGetBlockSize(K, &bs));
  LEM_PETSC(MatGetType(K, &type));
  const bool blocked = std::strstr(type, "baij") != nullptr;
  const double index_rows = blocked ? static_cast<double>(rows) / bs : static_cast<double>(rows);
  const double mm_bytes =
      info.nz_used * (sizeof(PetscScalar) + sizeof(PetscInt) / (blocked ? bs * bs : 1.0)) +
      index_rows * sizeof(PetscInt) + 2.0 * rows * sizeof(PetscScalar);
  // The bond operator on the same x, and the same solve with each operator
  // in turn, both with the preconditioner of the last repeat (not rebuilt:
  // the preconditioner matrix is the same K).
  sys->set_operator(SolverOperator::bonds);
  const Mat B = sys->operator_matrix();
  double bo_difference = 0;
  {
    VecHandle y;
    LEM_PETSC(VecDuplicate(b, y.replace()));
    LEM_PETSC(MatMult(K, x, b));
    LEM_PETSC(MatMult(B, x, y));
    PetscReal norm_b = 0, norm_d = 0;
    LEM_PETSC(VecNorm(b, NORM_INFINITY, &norm_b));
    LEM_PETSC(VecAXPY(y, -1.0, b));
    LEM_PETSC(VecNorm(y, NORM_INFINITY, &norm_d));
    bo_difference = norm_d / norm_b;
  }
  const double t_bo = timed(comm,
                            [&] {
                              for (std::int64_t k = 0; k < matmults; ++k)
                                LEM_PETSC(MatMult(B, x, b));
                            }) /
                      static_cast<double>(matmults);
  double bo_bytes = 0;
  {
    const double local = sys->bond_operator_bytes();
    MPI_Allreduce(&local, &bo_bytes, 1, MPI_DOUBLE, MPI_SUM, comm);
  }
  LEM_PETSC(MatMult(K, x, b));  // the right-hand side again
  std::vector<double> cg_ms[2], cg_its[2];
  for (std::int64_t r = 0; r < std::max<std::int64_t>(repeat, 1); ++r)
    for (int o = 0; o < 2; ++o) {
      use_fine_operator(ksp, o ? B : K, K);
      LEM_PETSC(VecZeroEntries(x));
      const double t = timed(comm, [&] { LEM_PETSC(KSPSolve(ksp, b, x)); });
      PetscInt n = 0;
      LEM_PETSC(KSPGetIterationNumber(ksp, &n));
      cg_ms[o].push_back(1e3 * t / static_cast<double>(n));
      cg_its[o].push_back(static_cast<double>(n));
    }
  // What one CG iteration sends and reduces on each rank (the default bond
  // operator; the input of the scaling projection, docs/scaling.md).
  LEM_PETSC(PetscLogDefaultBegin());
  PetscLogStage message_stage;
  LEM_PETSC(PetscLogStageRegister("Bench messages", &message_stage));
  PetscLogEvent solve_event;
  LEM_PETSC(PetscLogEventGetId("KSPSolve", &solve_event));
  LEM_PETSC(VecZeroEntries(x));
  LEM_PETSC(PetscLogStagePush(message_stage));
  LEM_PETSC(KSPSolve(ksp, b, x));
  LEM_PETSC(PetscLogStagePop());
  PetscInt message_its = 0;
  LEM_PETSC(KSPGetIterationNumber(ksp, &message_its));
  PetscEventPerfInfo perf{};
  LEM_PETSC(PetscLogEventGetPerfInfo(message_stage, solve_event, &perf));
  const double per_iteration = 1.0 / static_cast<double>(std::max<PetscInt>(message_its, 1));
  const auto over_ranks = [&](double mine) {  // {mean, max}
    double total = 0, largest = 0;
    MPI_Allreduce(&mine, &total, 1, MPI_DOUBLE, MPI_SUM, comm);
    MPI_Allreduce(&mine, &largest, 1, MPI_DOUBLE, MPI_MAX, comm);
    return std::array<double, 2>{total / ranks, largest};
  };
  const auto messages = over_ranks(perf.numMessages * per_iteration);
  const auto message_bytes = over_ranks(perf.messageLength * per_iteration);
  const auto reductions = over_ranks(perf.numReductions * per_iteration);
  account_levels(comm, *sys, lattice, solver, b, delta, bench.cycle_repeat);
  x.reset();
  b.reset();

  const auto rss = peak_memory_per_rank_mb(comm);
  const double stream = stream_triad_gbs(comm, stream_mb);

  const double pcsetup_rep = median(setup_s), solve_rep = median(solve_s), its_rep = median(its);
  const double per_it = repeat ? solve_rep / its_rep : first.solve_seconds / first.iterations;
  const double mm_stream = mm_bytes / (stream * 1e9);  // MatMult time at the STREAM bound
  const double mem_max = *std::max_element(rss.begin(), rss.end());
  say("set-up:   generation %.2f s, constraints %.2f s, partition %.2f s, distribution "
      "%.2f s\n",
      setup.seconds_build, setup.seconds_constraints, setup.seconds_partition,
      setup.seconds_distribute);
  say("system:   create+preallocate %.3f s, assembly %.3f s (repeats: median %.3f s)\n", t_create,
      t_asm, median(asm_s));
  say("first:    PC setup %.3f s, solve %.3f s, %d CG its (affine initial guess)\n",
      first.setup_seconds, first.solve_seconds, first.iterations);
  say("repeat:   PC setup median %.3f s, solve median %.3f s, %.0f CG its (zero initial "
      "guess, %d repeats)\n",
      pcsetup_rep, solve_rep, its_rep, static_cast<int>(repeat));
  say("per CG iteration %.2f ms = %.1f measured fine MatMults = %.1f STREAM-bound MatMults\n",
      1e3 * per_it, per_it / t_mm, per_it / mm_stream);
  say("MatMult (%s): %.2f ms, %.3g MB moved (nnz %.4g), %.2f GB/s = %.0f%% of STREAM\n", type,
      1e3 * t_mm, mm_bytes / 1e6, info.nz_used, mm_bytes / t_mm / 1e9, 100.0 * mm_stream / t_mm);
  say("operators side by side (same x, same preconditioner, %d solves each):\n",
      static_cast<int>(cg_its[0].size()));
  say("  assembled (%s): %.2f ms per product, %.3g MB, %.0f%% of STREAM; CG %.2f ms per "
      "iteration, %.0f its\n",
      type, 1e3 * t_mm, mm_bytes / 1e6, 100.0 * mm_stream / t_mm, median(cg_ms[0]),
      median(cg_its[0]));
  say("  bonds:     %.2f ms per product, %.3g MB (%.1f B per bond), %.0f%% of STREAM; CG "
      "%.2f ms per iteration, %.0f its; max |K_bonds x - K x| / max |K x| = %.1e\n",
      1e3 * t_bo, bo_bytes / 1e6, bo_bytes / static_cast<double>(setup.active_bonds),
      100.0 * bo_bytes / (stream * 1e9) / t_bo, median(cg_ms[1]), median(cg_its[1]), bo_difference);
  say("  ratio assembled/bonds: product %.2f, CG iteration %.2f\n", t_mm / t_bo,
      median(cg_ms[0]) / median(cg_ms[1]));
  say("STREAM triad: %.2f GB/s aggregate over %d ranks (3 x %.0f MB per rank)\n", stream, ranks,
      stream_mb);
  say("per CG iteration and rank: %.1f messages (max %.1f), %.3g bytes sent (max %.3g), "
      "%.1f reductions\n",
      messages[0], messages[1], message_bytes[0], message_bytes[1], reductions[1]);
  say("peak RSS MB: max %.0f; per rank after set-up [%s], at end [%s]\n", mem_max,
      list(rss_setup).c_str(), list(rss).c_str());
  say("# MESSAGES columns: ranks,bonds,messages_mean,messages_max,bytes_mean,bytes_max,"
      "reductions (per CG iteration and rank)\n");
  say("MESSAGES,%d,%lld,%.2f,%.2f,%.4g,%.4g,%.2f\n", ranks, nbonds, messages[0], messages[1],
      message_bytes[0], message_bytes[1], reductions[1]);
  say("# BENCH columns: ranks,bonds,nodes,gen_s,partition_s,distribute_s,assembly_s,"
      "pcsetup_s,solve_s,its,mem_max_MB,stream_GBs,constraints_s,morton,pcsetup_rep_s,"
      "solve_rep_s,its_rep,ms_per_it,matmult_ms,matmult_MB,matmult_GBs,it_in_matmults,"
      "stream_fraction_matmult\n");
  say("BENCH,%d,%lld,%lld,%.3f,%.3f,%.3f,%.4f,%.4f,%.4f,%d,%.0f,%.2f,%.3f,%d,%.4f,%.4f,%.0f,"
      "%.3f,%.3f,%.1f,%.2f,%.2f,%.3f\n",
      ranks, nbonds, nodes, setup.seconds_build, setup.seconds_partition, setup.seconds_distribute,
      t_asm, first.setup_seconds, first.solve_seconds, first.iterations, mem_max, stream,
      setup.seconds_constraints, morton ? 1 : 0, pcsetup_rep, solve_rep, its_rep, 1e3 * per_it,
      1e3 * t_mm, mm_bytes / 1e6, mm_bytes / t_mm / 1e9, per_it / t_mm, mm_stream / t_mm);
}

}  // namespace lem
