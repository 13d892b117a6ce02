#include "lem/bench/benchmark.hpp"

#include "level_accounting.hpp"

#include "lem/base/driver.hpp"
#include "lem/base/collective.hpp"
#include "lem/base/error.hpp"
#include "lem/base/log.hpp"
#include "lem/base/options.hpp"
#include "lem/base/petsc_handle.hpp"
#include "lem/lattice/voronoi.hpp"
#include "lem/solver/single_cycle.hpp"

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
  return max_over_ranks(comm, MPI_Wtime() - t);
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
  if (!SingleCycle::can_wrap(pc)) return;
  PetscInt levels = 0;
  LEM_PETSC(PCMGGetLevels(pc, &levels));
  double fine = 0, total = 0;
  std::string text;
  for (PetscInt l = levels - 1; l >= 0; --l) {
    const LevelOperator op = level_operator(pc, l);
    if (l == levels - 1) fine = op.nonzeros;
    total += op.nonzeros;
    text += ' ';
    text += std::to_string(op.rows);
    text += '/';
    text += std::to_string(static_cast<long long>(op.nonzeros));
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

// Load balance: the largest rank's share of `mine` over the mean.
double max_over_mean(MPI_Comm comm, double mine) {
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  double largest = 0, total = 0;
  MPI_Allreduce(&mine, &largest, 1, MPI_DOUBLE, MPI_MAX, comm);
  MPI_Allreduce(&mine, &total, 1, MPI_DOUBLE, MPI_SUM, comm);
  return total > 0 ? largest * ranks / total : 1.0;
}

// The mean and the largest of `mine` over the ranks.
std::array<double, 2> mean_and_max(MPI_Comm comm, double mine) {
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  double total = 0, largest = 0;
  MPI_Allreduce(&mine, &total, 1, MPI_DOUBLE, MPI_SUM, comm);
  MPI_Allreduce(&mine, &largest, 1, MPI_DOUBLE, MPI_MAX, comm);
  return {total / ranks, largest};
}

// The events of every multigrid level (the per-level accounting), unless
// the options already say.  Read back once, so that PETSc counts it as used:
// a preconditioner not built on PCMG never reads it, and an option of the
// program's own must not fail the unused-option check.
void log_multigrid_levels() {
  PetscBool set = PETSC_FALSE;
  LEM_PETSC(PetscOptionsHasName(nullptr, nullptr, "-pc_mg_log", &set));
  if (set) return;
  LEM_PETSC(PetscOptionsSetValue(nullptr, "-pc_mg_log", "true"));
  LEM_PETSC(PetscOptionsHasName(nullptr, nullptr, "-pc_mg_log", &set));
}

// b = K u: the right-hand side of the problem just solved, with x = u.
void reproduce_right_hand_side(const ElasticSystem& sys, Vec x, Vec b) {
  const auto u = sys.owned_displacements();
  PetscScalar* xa = nullptr;
  LEM_PETSC(VecGetArray(x, &xa));
  for (std::size_t n = 0; n < u.size(); ++n)
    for (std::size_t a = 0; a < 3; ++a) xa[3 * n + a] = u[n][a];
  LEM_PETSC(VecRestoreArray(x, &xa));
  LEM_PETSC(MatMult(sys.matrix(), x, b));
}

// The repeated assembly, preconditioner set-up and solve of b from zero.
struct Repeats {
  std::vector<double> assembly_s, setup_s, solve_s, its;
};

Repeats repeat_solves(MPI_Comm comm, ElasticSystem& sys, Vec x, Vec b, std::int64_t repeat) {
  const KSP ksp = sys.ksp();
  PC pc;
  LEM_PETSC(KSPGetPC(ksp, &pc));
  Repeats out;
  for (std::int64_t r = 0; r < repeat; ++r) {
    out.assembly_s.push_back(timed(comm, [&] { sys.assemble(); }));
    // KSPSetUp alone does not rebuild the PC after a change of matrix values
    // (KSPSolve would, inside the solve timing): call PCSetUp explicitly.
    out.setup_s.push_back(timed(comm, [&] {
      LEM_PETSC(KSPSetUp(ksp));
      LEM_PETSC(PCSetUp(pc));
    }));
    LEM_PETSC(VecZeroEntries(x));
    out.solve_s.push_back(timed(comm, [&] { LEM_PETSC(KSPSolve(ksp, b, x)); }));
    PetscInt n = 0;
    KSPConvergedReason reason;
    LEM_PETSC(KSPGetIterationNumber(ksp, &n));
    LEM_PETSC(KSPGetConvergedReason(ksp, &reason));
    if (reason < 0) throw NumericalError("repeated solve diverged");
    out.its.push_back(static_cast<double>(n));
  }
  return out;
}

// The preconditioner of the last repeat applied to one random column and
// to `columns` at once (PCMatApply: one MatMatSolve for a factorization,
// column by column otherwise): the cost of a column of a low-rank update
// to a factorization against a solve with it (docs/benchmarks-solver.md).
struct BlockApply {
  std::int64_t columns = 0;
  double one_s = 0, block_s = 0;
};

BlockApply measure_block_apply(MPI_Comm comm, KSP ksp, Mat K, std::int64_t columns) {
  BlockApply out;
  out.columns = columns;
  if (columns <= 0) return out;
  PC pc;
  LEM_PETSC(KSPGetPC(ksp, &pc));
  PetscInt rows = 0;
  LEM_PETSC(MatGetLocalSize(K, &rows, nullptr));
  MatHandle B, X;
  LEM_PETSC(MatCreateDense(comm, rows, PETSC_DECIDE, PETSC_DETERMINE,
                           static_cast<PetscInt>(columns), nullptr, B.replace()));
  LEM_PETSC(MatSetRandom(B, nullptr));
  LEM_PETSC(MatDuplicate(B, MAT_DO_NOT_COPY_VALUES, X.replace()));
  VecHandle b, x;
  LEM_PETSC(MatCreateVecs(K, x.replace(), b.replace()));
  LEM_PETSC(VecSetRandom(b, nullptr));
  out.one_s = timed(comm, [&] { LEM_PETSC(PCApply(pc, b, x)); });
  out.block_s = timed(comm, [&] { LEM_PETSC(PCMatApply(pc, B, X)); });
  return out;
}

// The time of one product y = A x, the mean of `count`.
double product_seconds(MPI_Comm comm, Mat A, Vec x, Vec y, std::int64_t count) {
  return timed(comm,
               [&] {
                 for (std::int64_t k = 0; k < count; ++k) LEM_PETSC(MatMult(A, x, y));
               }) /
         static_cast<double>(count);
}

// One fine-level MatMult of the assembled K: time, bytes (values + column
// indices + row starts + x read + y written; ghost exchange not counted).
struct AssembledProduct {
  double seconds = 0, bytes = 0, nonzeros = 0;
  std::string type;
};

AssembledProduct measure_assembled(MPI_Comm comm, Mat K, Vec x, Vec b, std::int64_t count) {
  AssembledProduct out;
  out.seconds = product_seconds(comm, K, x, b, count);
  MatInfo info;
  PetscInt rows = 0, bs = 1;
  MatType type;
  LEM_PETSC(MatGetInfo(K, MAT_GLOBAL_SUM, &info));
  LEM_PETSC(MatGetSize(K, &rows, nullptr));
  LEM_PETSC(MatGetBlockSize(K, &bs));
  LEM_PETSC(MatGetType(K, &type));
  const bool blocked = std::strstr(type, "baij") != nullptr;
  const double index_rows = blocked ? static_cast<double>(rows) / bs : static_cast<double>(rows);
  out.bytes = info.nz_used * (sizeof(PetscScalar) + sizeof(PetscInt) / (blocked ? bs * bs : 1.0)) +
              index_rows * sizeof(PetscInt) + 2.0 * rows * sizeof(PetscScalar);
  out.nonzeros = info.nz_used;
  out.type = type;
  return out;
}

// The bond operator on the same x: its product's time and bytes, and its
// largest difference from K x relative to the largest entry of K x.
struct BondProduct {
  double seconds = 0, bytes = 0, difference = 0;
};

BondProduct measure_bond_operator(MPI_Comm comm, const ElasticSystem& sys, Mat K, Mat B, Vec x,
                                  Vec b, std::int64_t count) {
  BondProduct out;
  VecHandle y;
  LEM_PETSC(VecDuplicate(b, y.replace()));
  LEM_PETSC(MatMult(K, x, b));
  LEM_PETSC(MatMult(B, x, y));
  PetscReal norm_b = 0, norm_d = 0;
  LEM_PETSC(VecNorm(b, NORM_INFINITY, &norm_b));
  LEM_PETSC(VecAXPY(y, -1.0, b));
  LEM_PETSC(VecNorm(y, NORM_INFINITY, &norm_d));
  out.difference = norm_d / norm_b;
  out.seconds = product_seconds(comm, B, x, b, count);
  const double local = sys.bond_operator_bytes();
  MPI_Allreduce(&local, &out.bytes, 1, MPI_DOUBLE, MPI_SUM, comm);
  return out;
}

// The same solve with each operator in turn (0 assembled, 1 bonds), both
// with the preconditioner built from K: ms per CG iteration and iterations.
struct SideBySide {
  std::vector<double> cg_ms[2], cg_its[2];
};

SideBySide solve_with_each_operator(MPI_Comm comm, KSP ksp, Mat K, Mat B, Vec x, Vec b,
                                    std::int64_t repeat) {
  SideBySide out;
  for (std::int64_t r = 0; r < std::max<std::int64_t>(repeat, 1); ++r)
    for (int o = 0; o < 2; ++o) {
      use_fine_operator(ksp, o ? B : K, K);
      LEM_PETSC(VecZeroEntries(x));
      const double t = timed(comm, [&] { LEM_PETSC(KSPSolve(ksp, b, x)); });
      PetscInt n = 0;
      LEM_PETSC(KSPGetIterationNumber(ksp, &n));
      out.cg_ms[o].push_back(1e3 * t / static_cast<double>(n));
      out.cg_its[o].push_back(static_cast<double>(n));
    }
  return out;
}

// What one CG iteration sends and reduces on each rank ({mean, max} over
// the ranks; the input of the scaling projection, docs/scaling.md).
struct MessageCounts {
  std::array<double, 2> messages{}, bytes{}, reductions{};
};

MessageCounts count_messages(MPI_Comm comm, KSP ksp, Vec x, Vec b) {
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
  MessageCounts out;
  out.messages = mean_and_max(comm, perf.numMessages * per_iteration);
  out.bytes = mean_and_max(comm, perf.messageLength * per_iteration);
  out.reductions = mean_and_max(comm, perf.numReductions * per_iteration);
  return out;
}

// Every figure of the tension benchmark, for the printout.
struct Figures {
  int ranks = 1;
  std::int64_t repeat = 0;
  bool morton = true;
  double stream_mb = 0;
  SetupReport setup;
  std::vector<double> rss_setup, rss;
  double t_create = 0, t_asm = 0;
  SolveReport first;
  Repeats repeats;
  AssembledProduct assembled;
  BondProduct bonds;
  SideBySide cg;
  MessageCounts messages;
  BlockApply block;
  double stream = 0;
};

// The figures derived from the measured ones.
struct Derived {
  double pcsetup_rep = 0, solve_rep = 0, its_rep = 0;  // medians of the repeats
  double per_it = 0;                                   // seconds per CG iteration
  double mm_stream = 0;                                // MatMult time at the STREAM bound
  double mem_max = 0;                                  // the largest peak RSS, MB
};

Derived derived(const Figures& f) {
  Derived d;
  d.pcsetup_rep = median(f.repeats.setup_s);
  d.solve_rep = median(f.repeats.solve_s);
  d.its_rep = median(f.repeats.its);
  d.per_it = f.repeat ? d.solve_rep / d.its_rep : f.first.solve_seconds / f.first.iterations;
  d.mm_stream = f.assembled.bytes / (f.stream * 1e9);
  d.mem_max = *std::max_element(f.rss.begin(), f.rss.end());
  return d;
}

// The figures for the reader: one line a stage.
void print_figures(const Figures& f) {
  const SetupReport& setup = f.setup;
  const AssembledProduct& mm = f.assembled;
  const Derived d = derived(f);
  const double per_it = d.per_it, mm_stream = d.mm_stream;
  say("set-up:   generation %.2f s, constraints %.2f s, partition %.2f s, distribution "
      "%.2f s\n",
      setup.seconds_build, setup.seconds_constraints, setup.seconds_partition,
      setup.seconds_distribute);
  say("system:   create+preallocate %.3f s, assembly %.3f s (repeats: median %.3f s)\n", f.t_create,
      f.t_asm, median(f.repeats.assembly_s));
  say("first:    PC setup %.3f s, solve %.3f s, %d CG its (affine initial guess)\n",
      f.first.setup_seconds, f.first.solve_seconds, f.first.iterations);
  say("repeat:   PC setup median %.3f s, solve median %.3f s, %.0f CG its (zero initial "
      "guess, %d repeats)\n",
      d.pcsetup_rep, d.solve_rep, d.its_rep, static_cast<int>(f.repeat));
  say("per CG iteration %.2f ms = %.1f measured fine MatMults = %.1f STREAM-bound MatMults\n",
      1e3 * per_it, per_it / mm.seconds, per_it / mm_stream);
  say("MatMult (%s): %.2f ms, %.3g MB moved (nnz %.4g), %.2f GB/s = %.0f%% of STREAM\n",
      mm.type.c_str(), 1e3 * mm.seconds, mm.bytes / 1e6, mm.nonzeros, mm.bytes / mm.seconds / 1e9,
      100.0 * mm_stream / mm.seconds);
  const auto& cg = f.cg;
  const BondProduct& bo = f.bonds;
  say("operators side by side (same x, same preconditioner, %d solves each):\n",
      static_cast<int>(cg.cg_its[0].size()));
  say("  assembled (%s): %.2f ms per product, %.3g MB, %.0f%% of STREAM; CG %.2f ms per "
      "iteration, %.0f its\n",
      mm.type.c_str(), 1e3 * mm.seconds, mm.bytes / 1e6, 100.0 * mm_stream / mm.seconds,
      median(cg.cg_ms[0]), median(cg.cg_its[0]));
  say("  bonds:     %.2f ms per product, %.3g MB (%.1f B per bond), %.0f%% of STREAM; CG "
      "%.2f ms per iteration, %.0f its; max |K_bonds x - K x| / max |K x| = %.1e\n",
      1e3 * bo.seconds, bo.bytes / 1e6, bo.bytes / static_cast<double>(setup.active_bonds),
      100.0 * bo.bytes / (f.stream * 1e9) / bo.seconds, median(cg.cg_ms[1]), median(cg.cg_its[1]),
      bo.difference);
  say("  ratio assembled/bonds: product %.2f, CG iteration %.2f\n", mm.seconds / bo.seconds,
      median(cg.cg_ms[0]) / median(cg.cg_ms[1]));
  say("STREAM triad: %.2f GB/s aggregate over %d ranks (3 x %.0f MB per rank)\n", f.stream, f.ranks,
      f.stream_mb);
  if (f.block.columns > 0)
    say("block apply (PCMatApply): %lld columns at once %.3f s, %.4f s a column, against "
        "%.4f s for one application: a column costs 1/%.1f of it\n",
        static_cast<long long>(f.block.columns), f.block.block_s,
        f.block.block_s / static_cast<double>(f.block.columns), f.block.one_s,
        f.block.one_s * static_cast<double>(f.block.columns) / f.block.block_s);
  const MessageCounts& m = f.messages;
  say("per CG iteration and rank: %.1f messages (max %.1f), %.3g bytes sent (max %.3g), "
      "%.1f reductions\n",
      m.messages[0], m.messages[1], m.bytes[0], m.bytes[1], m.reductions[1]);
  say("peak RSS MB: max %.0f; per rank after set-up [%s], at end [%s]\n", d.mem_max,
      list(f.rss_setup).c_str(), list(f.rss).c_str());
}

// The figures as the machine-read rows MESSAGES and BENCH.
void print_rows(const Figures& f) {
  const SetupReport& setup = f.setup;
  const AssembledProduct& mm = f.assembled;
  const long long nodes = setup.sample.stats.nodes, nbonds = setup.sample.stats.bonds;
  const Derived d = derived(f);
  const MessageCounts& m = f.messages;
  say("# MESSAGES columns: ranks,bonds,messages_mean,messages_max,bytes_mean,bytes_max,"
      "reductions (per CG iteration and rank)\n");
  say("MESSAGES,%d,%lld,%.2f,%.2f,%.4g,%.4g,%.2f\n", f.ranks, nbonds, m.messages[0], m.messages[1],
      m.bytes[0], m.bytes[1], m.reductions[1]);
  say("# BENCH columns: ranks,bonds,nodes,gen_s,partition_s,distribute_s,assembly_s,"
      "pcsetup_s,solve_s,its,mem_max_MB,stream_GBs,constraints_s,morton,pcsetup_rep_s,"
      "solve_rep_s,its_rep,ms_per_it,matmult_ms,matmult_MB,matmult_GBs,it_in_matmults,"
      "stream_fraction_matmult\n");
  say("BENCH,%d,%lld,%lld,%.3f,%.3f,%.3f,%.4f,%.4f,%.4f,%d,%.0f,%.2f,%.3f,%d,%.4f,%.4f,%.0f,"
      "%.3f,%.3f,%.1f,%.2f,%.2f,%.3f\n",
      f.ranks, nbonds, nodes, setup.seconds_build, setup.seconds_partition,
      setup.seconds_distribute, f.t_asm, f.first.setup_seconds, f.first.solve_seconds,
      f.first.iterations, d.mem_max, f.stream, setup.seconds_constraints, f.morton ? 1 : 0,
      d.pcsetup_rep, d.solve_rep, d.its_rep, 1e3 * d.per_it, 1e3 * mm.seconds, mm.bytes / 1e6,
      mm.bytes / mm.seconds / 1e9, d.per_it / mm.seconds, d.mm_stream / mm.seconds);
}

// The lattice of the benchmark, set up and described: -bench_morton for
// the serial set-up; the parallel one (a sample file with -sample_parallel,
// the cells generator) numbers along the Morton curve inside its cell
// partition.
DistributedLattice set_up_lattice(MPI_Comm comm, const SampleOptions& sample, Figures& f) {
  SetupReport& setup = f.setup;
  const bool serial = !sample.parallel && sample.generator == LatticeGenerator::serial;
  const double t_setup = MPI_Wtime();
  auto lattice = !serial ? setup_sample_lattice(comm, sample, setup)
                         : setup_tension_lattice(
                               comm, [&](SampleInfo& info) { return build_sample(sample, info); },
                               setup, f.morton);
  const double seconds_setup = MPI_Wtime() - t_setup;
  f.rss_setup = peak_memory_per_rank_mb(comm);
  say("lattice: %lld nodes, %lld bonds (%lld active), %d ranks, %s, edge cut %lld\n",
      static_cast<long long>(setup.sample.stats.nodes),
      static_cast<long long>(setup.sample.stats.bonds), static_cast<long long>(setup.active_bonds),
      f.ranks, serial ? (f.morton ? "Morton order" : "METIS order") : "set up in parallel (cells)",
      static_cast<long long>(setup.edge_cut));
  say("balance:  owned nodes max/mean %.3f, bonds held max/mean %.3f; set-up %.2f s\n",
      max_over_mean(comm, lattice.owned), max_over_mean(comm, lattice.local_bonds()),
      seconds_setup);
  return lattice;
}

}  // namespace

void run_voronoi_benchmark(MPI_Comm comm, SampleOptions sample, const BenchOptions& bench) {
  sample.random.nodes = bench.voronoi_nodes;
  sample.random.bonds = 0;
  bench_voronoi(comm, sample.random, bench.repeat);
}

void run_tension_benchmark(MPI_Comm comm, SampleOptions sample, const BenchOptions& bench,
                           const SolverOptions& solver) {
  Figures f;
  f.repeat = bench.repeat;
  f.morton = bench.morton;
  f.stream_mb = bench.stream_mb;
  MPI_Comm_size(comm, &f.ranks);
  sample.random.nodes = 0;
  sample.random.bonds = bench.bonds;
  DistributedLattice lattice = set_up_lattice(comm, sample, f);

  const double delta = 3e-4 * lattice.mean_bond_length;
  log_multigrid_levels();
  ElasticSystem* created = nullptr;
  f.t_create = timed(comm, [&] { created = new ElasticSystem(lattice, solver); });
  std::unique_ptr<ElasticSystem> sys(created);
  check_unused_options(SolverStage::created);
  // The figures up to the per-level accounting are those of the double
  // cycle, as they were before the single cycle became the default (its
  // float copies are still made at the build, so they count in the set-up).
  if (SingleCycle* cycle = SingleCycle::of(sys->ksp())) cycle->use_single(false);
  f.t_asm = timed(comm, [&] { sys->assemble(); });
  f.first = sys->solve(delta);
  check_unused_options();
  const Mat K = sys->matrix();
  const KSP ksp = sys->ksp();
  print_levels(ksp);

  VecHandle x, b;
  LEM_PETSC(MatCreateVecs(K, x.replace(), b.replace()));
  reproduce_right_hand_side(*sys, x, b);
  f.repeats = repeat_solves(comm, *sys, x, b, bench.repeat);
  f.block = measure_block_apply(comm, ksp, K, bench.block_columns);
  f.assembled = measure_assembled(comm, K, x, b, bench.matmults);
  // The bond operator on the same x, and the same solve with each operator
  // in turn, both with the preconditioner of the last repeat (not rebuilt:
  // the preconditioner matrix is the same K).
  sys->set_operator(SolverOperator::bonds);
  const Mat B = sys->operator_matrix();
  f.bonds = measure_bond_operator(comm, *sys, K, B, x, b, bench.matmults);
  LEM_PETSC(MatMult(K, x, b));  // the right-hand side again
  f.cg = solve_with_each_operator(comm, ksp, K, B, x, b, bench.repeat);
  f.messages = count_messages(comm, ksp, x, b);  // with the default bond operator
  account_levels(comm, *sys, lattice, solver, b, delta, bench.cycle_repeat);
  x.reset();
  b.reset();

  f.rss = peak_memory_per_rank_mb(comm);
  f.stream = stream_triad_gbs(comm, bench.stream_mb);
  print_figures(f);
  print_rows(f);
}

}  // namespace lem
