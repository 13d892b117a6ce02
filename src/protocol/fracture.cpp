#include "lem/fracture.hpp"

#include "lem/driver.hpp"
#include "lem/error.hpp"
#include "lem/options.hpp"
#include "lem/pieces.hpp"
#include "lem/tension_output.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <deque>
#include <fcntl.h>
#include <filesystem>
#include <limits>
#include <sstream>
#include <unistd.h>
#include <unordered_map>

namespace lem {

// ---------------------------------------------------------------- options

FractureOptions read_fracture_options(MPI_Comm comm) {
  FractureOptions o;
  {
    OptionGroup g(comm, "Fracture protocol (paper sect. 2.3, appendix A)");
    o.increment = g.real("-fracture_increment", "Top displacement added per load step, in "
                         "units of the mean bond length a (paper: 3e-4)", o.increment, 0.0,
                         0.01, true);
    o.break_all = g.choice("-fracture_break_rule", "Which critical bonds break in a relaxation "
                           "cycle: all (paper) or the most critical only",
                           {"all", "most_critical"}, "all") == "all";
    o.skip_idle = g.flag("-fracture_skip_idle", "Jump over load steps at which no bond breaks "
                         "(exact: the system is linear between ruptures)", o.skip_idle);
    o.stop_fraction = g.real("-fracture_stop_fraction", "End the run once the stress has "
                             "fallen below this fraction of the peak", o.stop_fraction, 0.0,
                             1.0, true, true);
    o.max_strain_ratio = g.real("-fracture_max_strain_ratio", "End the run once the strain "
                                "exceeds this multiple of the strain at the peak (the slow "
                                "post-failure tail; 0: no limit)", o.max_strain_ratio, 0.0, 1e9);
    o.max_steps = g.integer("-fracture_max_steps", "Largest load step (the run ends there)",
                            o.max_steps, 1, 1'000'000'000);
    o.rebuild_after_ruptures = g.integer(
        "-fracture_pc_rebuild_ruptures", "Rebuild the preconditioner after this many ruptures "
        "since the last build (0: never for this reason)", o.rebuild_after_ruptures, 0,
        1'000'000'000);
    o.rebuild_iteration_growth = g.real(
        "-fracture_pc_rebuild_growth", "Rebuild the preconditioner when a relaxation solve "
        "takes more than this times the iterations of the first one after the last build (0: "
        "never for this reason)", o.rebuild_iteration_growth, 0.0, 1e6);
  }
  {
    OptionGroup g(comm, "Threshold disorder (seeded; the same on any rank count)");
    o.disorder = g.choice("-strength_disorder", "Random factor on the breaking thresholds",
                          {"none", "uniform", "weibull"}, "none");
    o.disorder_width = g.real("-strength_disorder_width", "uniform: factor drawn in "
                              "[1 - w, 1 + w]", 0.2, 0.0, 1.0, false, true);
    o.weibull_modulus = g.real("-strength_weibull_modulus", "weibull: shape m of the "
                               "mean-one Weibull factor", o.weibull_modulus, 0.0, 1000.0, true);
    o.disorder_seed = static_cast<std::uint64_t>(
        g.integer("-strength_disorder_seed", "Seed of the threshold factors", 1, 0,
                  PETSC_MAX_INT));
    const std::string phases = g.string("-strength_disorder_phases", "Comma-separated bond "
                                        "phases that get the factor (p, m, pp, pm)",
                                        "p,m,pp,pm");
    const char* names[kBondPhases] = {"p", "m", "v", "pp", "pm"};
    o.disorder_phases.fill(false);
    std::stringstream list(phases);
    for (std::string item; std::getline(list, item, ',');) {
      int found = -1;
      for (int k = 0; k < kBondPhases; ++k)
        if (item == names[k] && k != 2) found = k;
      if (found < 0)
        throw InputError("option -strength_disorder_phases: '" + item + "' is not a bond "
                         "phase; allowed: p, m, pp, pm");
      o.disorder_phases[found] = true;
    }
  }
  {
    OptionGroup g(comm, "Checkpoint and restart");
    o.checkpoint_steps = g.integer("-checkpoint_steps", "Write a checkpoint every this many "
                                   "load steps (0: not by steps)", 0, 0, 1'000'000'000);
    o.checkpoint_seconds = g.real("-checkpoint_seconds", "Write a checkpoint when this much "
                                  "wall time has passed since the last one (0: not by time); "
                                  "SIGTERM or SIGUSR1 also write one and stop the run", 600.0,
                                  0.0, 1e9);
    o.resume = g.flag("-checkpoint_resume", "Resume from the checkpoint in -output_dir if there "
                      "is one (false: start over and overwrite it)", true);
  }
  return o;
}

// --------------------------------------------------------------- disorder

namespace {

std::uint64_t mix64(std::uint64_t x) {  // splitmix64 finaliser
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

double unit_uniform(std::uint64_t seed, std::int64_t id) {  // in (0, 1)
  const std::uint64_t h = mix64(mix64(seed) ^ static_cast<std::uint64_t>(id));
  return (static_cast<double>(h >> 11) + 0.5) * 0x1.0p-53;
}

int phase_of(const DistributedLattice& l, int bond) {
  return l.bond_tag.empty() ? 0 : static_cast<int>(l.bond_tag[bond]);
}

}  // namespace

void apply_strength_disorder(DistributedLattice& l, const FractureOptions& o) {
  if (o.disorder == "none") return;
  const double weibull_mean = std::tgamma(1.0 + 1.0 / o.weibull_modulus);
  for (int b = 0; b < l.local_bonds(); ++b) {
    if (!o.disorder_phases[phase_of(l, b)]) continue;
    const double u = unit_uniform(o.disorder_seed, l.bond_id[b]);
    const double factor = o.disorder == "uniform"
                              ? 1.0 + o.disorder_width * (2.0 * u - 1.0)
                              : std::pow(-std::log1p(-u), 1.0 / o.weibull_modulus) / weibull_mean;
    l.bond_strength[b] *= factor;
  }
}

std::int64_t FractureResult::broken_total() const {
  std::int64_t n = 0;
  for (auto b : broken) n += b;
  return n;
}

double FractureResult::particle_damage() const {
  const auto total = broken_total();
  return total > 0 ? static_cast<double>(broken[0]) / static_cast<double>(total) : 0.0;
}

// ------------------------------------------------------------- signals

namespace {

volatile std::sig_atomic_t g_stop_signal = 0;
extern "C" void remember_signal(int signal) { g_stop_signal = signal; }

class SignalGuard {  // SIGTERM / SIGUSR1 set a flag while the protocol runs
 public:
  SignalGuard() {
    struct sigaction action {};
    action.sa_handler = remember_signal;
    sigemptyset(&action.sa_mask);
    sigaction(SIGTERM, &action, &old_term_);
    sigaction(SIGUSR1, &action, &old_usr1_);
  }
  ~SignalGuard() {
    sigaction(SIGTERM, &old_term_, nullptr);
    sigaction(SIGUSR1, &old_usr1_, nullptr);
  }

 private:
  struct sigaction old_term_ {}, old_usr1_ {};
};

// ---------------------------------------------------------- checkpoint

constexpr char kCheckpointMagic[8] = {'L', 'E', 'M', 'C', 'K', 'P', 'T', '1'};

// Everything scalar the protocol needs to continue; trivially copyable.
struct Counters {
  std::int64_t step = 0;            // last load step reached
  std::int64_t batches = 0;         // batches of matrix changes so far
  std::int64_t ruptures_since_build = 0;
  std::int64_t baseline_iterations = 0;  // first relaxation solve after the last build
  std::int64_t next_checkpoint_step = 0;
  std::int64_t curve_bytes = 0, log_bytes = 0;
  double reaction = 0;              // at the current equilibrium
  double seconds_before = 0;        // wall time of earlier sessions
  double young_modulus = 0, peak_stress = 0, strain_at_peak = 0;
  std::int64_t visited_steps = 0, solves = 0, iterations = 0, builds = 0;
  std::int64_t rupture_steps = 0, cycles = 0, detached = 0, pinned = 0;
  std::int64_t broken[kBondPhases] = {};
  double work = 0, released = 0;
  std::int64_t pieces = 1;
  std::int64_t fallbacks = 0;       // solves finished by the Jacobi-CG fallback
  std::int64_t rebuild_pending = 0; // the next solve must build a new preconditioner
};

struct Checkpoint {
  Counters counters;
  std::string fingerprint;
  std::vector<std::int64_t> bond_events, bond_batches;  // broken bonds, in order
  std::vector<std::int64_t> node_events, node_batches;  // pinned nodes, in order
  std::vector<std::int64_t> build_batches;  // every preconditioner build, after which batch
  std::vector<double> displacement;                     // 3 per lattice node id
};

std::uint64_t fnv1a(const char* data, std::size_t n, std::uint64_t h = 1469598103934665603ULL) {
  for (std::size_t i = 0; i < n; ++i) h = (h ^ static_cast<unsigned char>(data[i])) * 1099511628211ULL;
  return h;
}

class ByteWriter {
 public:
  template <class T>
  void pod(const T& v) { raw(&v, sizeof(T)); }
  template <class T>
  void vec(const std::vector<T>& v) {
    pod(static_cast<std::uint64_t>(v.size()));
    raw(v.data(), v.size() * sizeof(T));
  }
  void str(const std::string& s) { vec(std::vector<char>(s.begin(), s.end())); }
  void raw(const void* p, std::size_t n) {
    bytes.insert(bytes.end(), static_cast<const char*>(p), static_cast<const char*>(p) + n);
  }
  std::vector<char> bytes;
};

class ByteReader {
 public:
  ByteReader(const std::vector<char>& b, std::size_t end) : b_(b), end_(end) {}
  template <class T>
  void pod(T& v) { raw(&v, sizeof(T)); }
  template <class T>
  void vec(std::vector<T>& v) {
    std::uint64_t n = 0;
    pod(n);
    if (n > (end_ - pos_) / std::max<std::size_t>(1, sizeof(T))) throw std::runtime_error("size");
    v.resize(n);
    raw(v.data(), n * sizeof(T));
  }
  void str(std::string& s) {
    std::vector<char> c;
    vec(c);
    s.assign(c.begin(), c.end());
  }
  void raw(void* p, std::size_t n) {
    if (n > end_ - pos_) throw std::runtime_error("short");
    std::memcpy(p, b_.data() + pos_, n);
    pos_ += n;
  }
  bool at_end() const { return pos_ == end_; }

 private:
  const std::vector<char>& b_;
  std::size_t end_, pos_ = 0;
};

void fsync_path(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
}

// Rank 0 only.
void write_checkpoint_file(const std::string& path, const Checkpoint& c) {
  ByteWriter w;
  w.raw(kCheckpointMagic, sizeof(kCheckpointMagic));
  w.pod(static_cast<std::uint64_t>(sizeof(Counters)));
  w.pod(c.counters);
  w.str(c.fingerprint);
  w.vec(c.bond_events), w.vec(c.bond_batches), w.vec(c.node_events), w.vec(c.node_batches);
  w.vec(c.build_batches);
  w.vec(c.displacement);
  const std::uint64_t sum = fnv1a(w.bytes.data(), w.bytes.size());
  w.pod(sum);
  const std::string tmp = path + ".tmp";
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) throw InputError("cannot write the checkpoint '" + tmp + "': " + std::strerror(errno));
  const bool ok = std::fwrite(w.bytes.data(), 1, w.bytes.size(), f) == w.bytes.size();
  if (std::fclose(f) != 0 || !ok)
    throw InputError("cannot write the checkpoint '" + tmp + "' (disk full?)");
  fsync_path(tmp);
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
    throw InputError("cannot rename the checkpoint into '" + path + "': " + std::strerror(errno));
}

// Rank 0 only.  Throws InputError naming the file when it is not a valid checkpoint.
Checkpoint read_checkpoint_file(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw InputError("cannot open the checkpoint '" + path + "'");
  std::vector<char> bytes;
  char buffer[1 << 16];
  for (std::size_t n; (n = std::fread(buffer, 1, sizeof(buffer), f)) > 0;)
    bytes.insert(bytes.end(), buffer, buffer + n);
  std::fclose(f);
  const std::string bad = "the checkpoint '" + path + "' is not a valid lem checkpoint (";
  if (bytes.size() < sizeof(kCheckpointMagic) + 16 ||
      std::memcmp(bytes.data(), kCheckpointMagic, sizeof(kCheckpointMagic)) != 0)
    throw InputError(bad + "wrong header); remove it or pass -checkpoint_resume false");
  std::uint64_t stored = 0;
  std::memcpy(&stored, bytes.data() + bytes.size() - 8, 8);
  if (fnv1a(bytes.data(), bytes.size() - 8) != stored)
    throw InputError(bad + "checksum mismatch: truncated or corrupt); remove it or pass "
                     "-checkpoint_resume false");
  Checkpoint c;
  try {
    ByteReader r(bytes, bytes.size() - 8);
    char magic[8];
    r.raw(magic, 8);
    std::uint64_t counter_size = 0;
    r.pod(counter_size);
    if (counter_size != sizeof(Counters)) throw std::runtime_error("version");
    r.pod(c.counters);
    r.str(c.fingerprint);
    r.vec(c.bond_events), r.vec(c.bond_batches), r.vec(c.node_events), r.vec(c.node_batches);
    r.vec(c.build_batches);
    r.vec(c.displacement);
    if (!r.at_end() || c.bond_events.size() != c.bond_batches.size() ||
        c.node_events.size() != c.node_batches.size())
      throw std::runtime_error("layout");
  } catch (const std::runtime_error& e) {
    throw InputError(bad + "written by another version of the code: " + e.what() + ")");
  }
  return c;
}

// ---------------------------------------------------------------- records

struct Rupture {
  std::int64_t id;
  double ratio;  // force / threshold (infinite for a zero threshold)
  double force, threshold;
  double x, y, z;
  std::int32_t phase, pad;
};

template <class T>
std::vector<T> allgather(MPI_Comm comm, const std::vector<T>& mine) {
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  const int bytes = static_cast<int>(mine.size() * sizeof(T));
  std::vector<int> counts(ranks), offsets(ranks + 1, 0);
  MPI_Allgather(&bytes, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
  for (int r = 0; r < ranks; ++r) offsets[r + 1] = offsets[r] + counts[r];
  std::vector<T> all(offsets[ranks] / sizeof(T));
  MPI_Allgatherv(mine.data(), bytes, MPI_BYTE, all.data(), counts.data(), offsets.data(),
                 MPI_BYTE, comm);
  return all;
}

const char* const kPhaseNames[kBondPhases] = {"p", "m", "v", "pp", "pm"};

// ---------------------------------------------------------------- protocol

class Protocol {
 public:
  Protocol(DistributedLattice& l, ElasticSystem& s, const FractureOptions& o,
           const Provenance& provenance)
      : l_(l), system_(s), o_(o), provenance_(provenance), pieces_(l) {
    MPI_Comm_rank(l.comm, &rank_);
    MPI_Comm_size(l.comm, &ranks_);
    for (int b = 0; b < l.local_bonds(); ++b) local_bond_[l.bond_id[b]].push_back(b);
    for (int n = 0; n < l.local_nodes(); ++n) local_node_[l.node_id[n]] = n;
    fingerprint_ = make_fingerprint();
    // Forces below this are solver noise: a bond with a zero threshold (bare
    // contacts, sigma^pp = 0) breaks only on a tension above it.
    double sums[2] = {0, 0}, totals[2];
    for (int b = 0; b < l.local_bonds(); ++b)
      if (l.bond_reported[b] && !l.bond_strength.empty() && l.bond_strength[b] > 0)
        sums[0] += l.bond_strength[b], sums[1] += 1;
    MPI_Allreduce(sums, totals, 2, MPI_DOUBLE, MPI_SUM, l.comm);
    force_floor_ = totals[1] > 0 ? 1e-6 * totals[0] / totals[1] : 0.0;
    checkpoint_path_ = o.output_dir + "/checkpoint.bin";
    curve_path_ = o.output_dir + "/curve.csv";
    log_path_ = o.output_dir + "/broken.csv";
  }
  ~Protocol() {
    if (curve_) std::fclose(curve_);
    if (log_) std::fclose(log_);
  }

  FractureResult run();

 private:
  double step_displacement(std::int64_t step) const {
    return static_cast<double>(step) * o_.increment * l_.mean_bond_length;
  }
  double strain_of(std::int64_t step) const { return step_displacement(step) / l_.box.length(2); }
  std::string make_fingerprint() const;
  bool try_resume();
  void open_results(bool resumed);
  void write_checkpoint();
  void apply_batch(const std::vector<std::int64_t>& bonds, const std::vector<std::int64_t>& nodes);
  std::vector<Rupture> find_critical() const;
  std::int64_t next_critical_step() const;
  void account(const SolveReport& report, bool relaxation);
  void visit(std::int64_t step, bool first);
  void visit_idle(std::int64_t step);
  void write_row(std::int64_t step, const TensionResponse& r, double stress_before, int cycles,
                 bool idle);
  bool stop_requested();
  void progress(std::int64_t step, double stress, std::int64_t new_breaks, int cycles);
  void write_elastic_fields() const;
  void check_first_increment() const;

  DistributedLattice& l_;
  ElasticSystem& system_;
  const FractureOptions& o_;
  const Provenance& provenance_;
  PieceFinder pieces_;
  int rank_ = 0, ranks_ = 1;
  std::unordered_map<std::int64_t, std::vector<int>> local_bond_;
  std::unordered_map<std::int64_t, int> local_node_;
  std::string fingerprint_, checkpoint_path_, curve_path_, log_path_;
  std::FILE* curve_ = nullptr;
  std::FILE* log_ = nullptr;
  Counters c_;
  Checkpoint events_;  // the event lists (counters and displacement unused)
  // The last equilibrium, written as the checkpoint if a solve fails.
  struct Snapshot {
    Counters counters;
    std::size_t bond_events = 0, node_events = 0, builds = 0;
    std::vector<double> u;
  } last_;
  void take_snapshot();
  bool disconnected_ = false, resumed_ = false;
  double force_floor_ = 0;  // 1e-6 of the mean positive threshold
  std::int64_t last_snapshot_ = 0;  // step of the previous visit
  double start_ = 0, last_checkpoint_time_ = 0, last_progress_ = 0;
  struct ProgressPoint {
    double seconds, stress, strain;
  };
  std::deque<ProgressPoint> recent_;  // after the peak, for the time-left estimate
  double tail_start_ = 0;             // time of the first progress line after the peak
};

std::string Protocol::make_fingerprint() const {
  // The intact sample (ids, stiffnesses, thresholds after disorder), hashed
  // in an order-free way, and every option that changes the results.
  std::uint64_t sum = 0;
  for (int b = 0; b < l_.local_bonds(); ++b) {
    if (!l_.bond_reported[b]) continue;
    std::uint64_t k = 0, f = 0;
    std::memcpy(&k, &l_.bond_stiffness[b], 8);
    if (!l_.bond_strength.empty()) std::memcpy(&f, &l_.bond_strength[b], 8);
    sum += mix64(static_cast<std::uint64_t>(l_.bond_id[b]) ^ mix64(k ^ mix64(f)));
  }
  std::uint64_t total = 0;
  MPI_Allreduce(&sum, &total, 1, MPI_UINT64_T, MPI_SUM, l_.comm);
  std::ostringstream s;
  s.precision(17);
  s << "ranks=" << ranks_ << "\nnodes=" << l_.global_nodes << "\nbonds=" << l_.global_bonds
    << "\nsample_checksum=" << total << "\nincrement=" << o_.increment
    << "\nbreak_rule=" << (o_.break_all ? "all" : "most_critical")
    << "\nskip_idle=" << o_.skip_idle
    << "\npc_rebuild_ruptures=" << o_.rebuild_after_ruptures
    << "\npc_rebuild_growth=" << o_.rebuild_iteration_growth << "\n";
  // Solver options are left out on purpose: a run stopped by a failed solve
  // may be resumed with others (then equal to the tolerance, not bitwise).
  return s.str();
}

bool Protocol::try_resume() {
  int exists = 0;
  if (rank_ == 0) exists = ::access(checkpoint_path_.c_str(), F_OK) == 0;
  MPI_Bcast(&exists, 1, MPI_INT, 0, l_.comm);
  if (!exists || !o_.resume) return false;
  Checkpoint c;
  int other_ranks = 0;  // rank count of a checkpoint written by another one
  run_on_root(l_.comm, [&] {
    c = read_checkpoint_file(checkpoint_path_);
    // Name what differs.  The rank count may differ: everything in the
    // checkpoint is by lattice id, so another partition can take it over.
    auto lines = [](const std::string& text) {
      std::vector<std::string> out;
      std::istringstream in(text);
      for (std::string line; std::getline(in, line);) out.push_back(line);
      return out;
    };
    const auto theirs = lines(c.fingerprint), ours = lines(fingerprint_);
    std::string differs;
    if (theirs.size() != ours.size()) differs = "\n  (a different option set)";
    for (std::size_t i = 0; differs.empty() && i < ours.size(); ++i) {
      if (theirs[i] == ours[i]) continue;
      if (theirs[i].rfind("ranks=", 0) == 0 && ours[i].rfind("ranks=", 0) == 0)
        other_ranks = std::stoi(theirs[i].substr(6));
      else
        differs += "\n  checkpoint: " + theirs[i] + "   this run: " + ours[i];
    }
    if (!differs.empty())
      throw InputError("the checkpoint '" + checkpoint_path_ + "' belongs to a different run "
                       "(sample or options):" + differs + "\nresume with the same command, or "
                       "pass -checkpoint_resume false to start over");
  });
  MPI_Bcast(&other_ranks, 1, MPI_INT, 0, l_.comm);
  if (other_ranks > 0)
    say("resuming a checkpoint written on %d ranks on %d: the preconditioner differs, so the "
        "rest of the run agrees with an uninterrupted one to the solver tolerance, not bit for "
        "bit\n", other_ranks, ranks_);
  // Share it: counters, events, displacements.
  MPI_Bcast(&c.counters, sizeof(Counters), MPI_BYTE, 0, l_.comm);
  auto share = [&](auto& v) {
    std::uint64_t n = v.size();
    MPI_Bcast(&n, 1, MPI_UINT64_T, 0, l_.comm);
    v.resize(n);
    using T = typename std::decay_t<decltype(v)>::value_type;
    MPI_Bcast(v.data(), static_cast<int>(n * sizeof(T)), MPI_BYTE, 0, l_.comm);
  };
  share(c.bond_events), share(c.bond_batches), share(c.node_events), share(c.node_batches);
  share(c.build_batches);
  share(c.displacement);

  // Replay the matrix changes batch by batch and every preconditioner build
  // after the same batch as the interrupted run: PETSc's multigrid set-up
  // draws random numbers whose stream continues from one build to the next,
  // so only the whole sequence gives the same preconditioner.
  std::size_t ib = 0, in = 0, ip = 0;
  auto builds_after = [&](std::int64_t batch) {
    for (; ip < c.build_batches.size() && c.build_batches[ip] == batch; ++ip)
      system_.build_preconditioner();
  };
  builds_after(0);
  for (std::int64_t batch = 1; batch <= c.counters.batches; ++batch) {
    std::vector<std::int64_t> bonds, nodes;
    for (; ib < c.bond_events.size() && c.bond_batches[ib] == batch; ++ib)
      bonds.push_back(c.bond_events[ib]);
    for (; in < c.node_events.size() && c.node_batches[in] == batch; ++in)
      nodes.push_back(c.node_events[in]);
    apply_batch(bonds, nodes);
    system_.finish_updates();
    builds_after(batch);
  }
  events_.bond_events = std::move(c.bond_events);
  events_.bond_batches = std::move(c.bond_batches);
  events_.node_events = std::move(c.node_events);
  events_.node_batches = std::move(c.node_batches);
  events_.build_batches = std::move(c.build_batches);
  std::vector<double> owned(3 * static_cast<std::size_t>(l_.owned));
  for (int n = 0; n < l_.owned; ++n)
    for (int a = 0; a < 3; ++a) owned[3 * n + a] = c.displacement[3 * l_.node_id[n] + a];
  system_.set_state(owned, step_displacement(c.counters.step));
  // A rebuild asked for before the checkpoint (iteration growth, fallback).
  if (c.counters.rebuild_pending) system_.rebuild_preconditioner();
  c_ = c.counters;
  return true;
}

void Protocol::open_results(bool resumed) {
  run_on_root(l_.comm, [&] {
    const std::string curve_part = curve_path_ + ".part", log_part = log_path_ + ".part";
    if (resumed) {
      // Drop the rows written after the checkpoint.
      for (auto [path, size] : {std::pair{curve_part, c_.curve_bytes},
                                std::pair{log_part, c_.log_bytes}}) {
        if (::truncate(path.c_str(), static_cast<off_t>(size)) != 0)
          throw InputError("cannot resume: '" + path + "' is missing or unwritable (" +
                           std::strerror(errno) + "); remove the checkpoint to start over");
      }
      curve_ = std::fopen(curve_part.c_str(), "ab");
      log_ = std::fopen(log_part.c_str(), "ab");
      // ftell() of a fresh append stream may say 0 until the first write.
      if (curve_) std::fseek(curve_, 0, SEEK_END);
      if (log_) std::fseek(log_, 0, SEEK_END);
    } else {
      curve_ = std::fopen(curve_part.c_str(), "wb");
      log_ = std::fopen(log_part.c_str(), "wb");
      // Snapshots of an earlier run would mix with this run's.
      std::error_code ec;
      for (const auto& entry : std::filesystem::directory_iterator(o_.output_dir, ec))
        if (entry.path().filename().string().rfind("snapshot_", 0) == 0)
          std::filesystem::remove(entry.path(), ec);
    }
    if (!curve_ || !log_)
      throw InputError("cannot write the results in '" + o_.output_dir + "': " +
                       std::strerror(errno));
    if (!resumed) {
      std::fprintf(curve_,
                   "# stress-strain curve of lem_fracture; sigma columns normalised by "
                   "sigma_unit = %.10g (E^phase units), raw stress in E^phase units, energies in "
                   "lattice units (k a^2)\n"
                   "step,strain,displacement_over_a,stress_before_norm,stress_norm,stress,"
                   "broken,broken_p,broken_m,broken_pp,broken_pm,n_b,cycles,loose_nodes,"
                   "solves,iterations,pc_builds,work,stored_energy,released_energy,idle,"
                   "elapsed_s\n",
                   o_.strength_unit);
      std::fprintf(log_, "step,cycle,strain,bond_id,phase,x,y,z,force,threshold\n");
      std::fflush(curve_);
      std::fflush(log_);
    }
  });
}

void Protocol::apply_batch(const std::vector<std::int64_t>& bonds,
                           const std::vector<std::int64_t>& nodes) {
  for (std::int64_t id : bonds) {
    const auto it = local_bond_.find(id);
    if (it == local_bond_.end()) continue;
    for (int b : it->second) system_.set_bond_stiffness(b, 0.0);
  }
  if (nodes.empty()) return;
  std::vector<char> pin(l_.local_nodes(), 0);
  std::vector<int> local;
  for (std::int64_t id : nodes) {
    const auto it = local_node_.find(id);
    if (it == local_node_.end()) continue;
    pin[it->second] = 1;
    local.push_back(it->second);
  }
  std::sort(local.begin(), local.end());
  // Detach the bonds of the pinned pieces (no load: not counted as broken).
  for (int b = 0; b < l_.local_bonds(); ++b) {
    const auto [p, q] = l_.bond_ends[b];
    if (l_.bond_stiffness[b] > 0 && (pin[p] || pin[q])) system_.set_bond_stiffness(b, 0.0);
  }
  system_.pin_nodes(local);
}

std::vector<Rupture> Protocol::find_critical() const {
  const std::vector<double> tension = system_.bond_tensions();
  std::int64_t bad = -1, worst = -1;
  for (int b = 0; b < l_.local_bonds() && bad < 0; ++b)
    if (!std::isfinite(tension[b])) bad = l_.bond_id[b];
  MPI_Allreduce(&bad, &worst, 1, MPI_INT64_T, MPI_MAX, l_.comm);  // every rank decides alike
  if (worst >= 0)
    throw NumericalError("bond " + std::to_string(worst) + " has a non-finite force");
  std::vector<Rupture> mine;
  for (int b = 0; b < l_.local_bonds(); ++b) {
    if (!l_.bond_reported[b] || l_.bond_stiffness[b] <= 0) continue;
    const double t = tension[b], f = l_.bond_strength[b];
    if (!(t > f) || t <= force_floor_) continue;
    const auto [p, q] = l_.bond_ends[b];
    Rupture r{};
    r.id = l_.bond_id[b];
    r.ratio = f > 0 ? t / f : std::numeric_limits<double>::infinity();
    r.force = t;
    r.threshold = f;
    r.x = 0.5 * (l_.coords[p][0] + l_.coords[q][0]);
    r.y = 0.5 * (l_.coords[p][1] + l_.coords[q][1]);
    r.z = 0.5 * (l_.coords[p][2] + l_.coords[q][2]);
    r.phase = phase_of(l_, b);
    mine.push_back(r);
  }
  if (!o_.break_all) {
    // The most critical bond: largest ratio, then smallest id (rank-independent).
    auto better = [](const Rupture& a, const Rupture& b) {
      return a.ratio > b.ratio || (a.ratio == b.ratio && a.id < b.id);
    };
    if (!mine.empty()) mine = {*std::min_element(mine.begin(), mine.end(), better)};
    auto all = allgather(l_.comm, mine);
    if (!all.empty()) all = {*std::min_element(all.begin(), all.end(), better)};
    return all;
  }
  auto all = allgather(l_.comm, mine);
  std::sort(all.begin(), all.end(), [](const Rupture& a, const Rupture& b) { return a.id < b.id; });
  return all;
}

std::int64_t Protocol::next_critical_step() const {
  // Bond b breaks at step m when m * t_b / n > f_b (t_b its tension now, at
  // step n): the first such m is floor(n f_b / t_b) + 1.
  const std::vector<double> tension = system_.bond_tensions();
  const double n = static_cast<double>(c_.step);
  double first = std::numeric_limits<double>::infinity();
  for (int b = 0; b < l_.local_bonds(); ++b) {
    if (!l_.bond_reported[b] || l_.bond_stiffness[b] <= 0 || !(tension[b] > 0)) continue;
    const double f = std::max(l_.bond_strength[b], force_floor_);
    first = std::min(first, std::floor(n * f / tension[b]) + 1.0);
  }
  double global = 0;
  MPI_Allreduce(&first, &global, 1, MPI_DOUBLE, MPI_MIN, l_.comm);
  // Progress is guaranteed; rounding at most costs an idle evaluation.
  const double cap = static_cast<double>(o_.max_steps) + 1.0;
  return static_cast<std::int64_t>(std::max(n + 1.0, std::min(global, cap)));
}

void Protocol::account(const SolveReport& report, bool relaxation) {
  c_.solves += 1;
  c_.iterations += report.iterations;
  c_.fallbacks += report.used_fallback;
  if (report.preconditioner_built) {
    c_.builds += 1;
    events_.build_batches.push_back(c_.batches);
    c_.ruptures_since_build = 0;
    c_.baseline_iterations = 0;
  }
  if (!relaxation) return;
  if (c_.baseline_iterations == 0) {
    c_.baseline_iterations = std::max(1, report.iterations);
  } else if (o_.rebuild_iteration_growth > 0 &&
             report.iterations > o_.rebuild_iteration_growth * static_cast<double>(c_.baseline_iterations)) {
    system_.rebuild_preconditioner();
  }
}

void Protocol::write_row(std::int64_t step, const TensionResponse& r, double stress_before,
                         int cycles, bool idle) {
  if (rank_ != 0) return;
  const double su = o_.stress_unit;
  FractureResult tmp;
  std::copy(std::begin(c_.broken), std::end(c_.broken), tmp.broken.begin());
  std::fprintf(curve_,
               "%lld,%.12e,%.12e,%.12e,%.12e,%.12e,%lld,%lld,%lld,%lld,%lld,%.6f,%d,%lld,%lld,"
               "%lld,%lld,%.12e,%.12e,%.12e,%d,%.3f\n",
               (long long)step, r.strain_zz, r.top_displacement / l_.mean_bond_length,
               stress_before * su / o_.strength_unit, r.stress_zz * su / o_.strength_unit,
               r.stress_zz * su, (long long)tmp.broken_total(), (long long)c_.broken[0],
               (long long)c_.broken[1], (long long)c_.broken[3], (long long)c_.broken[4],
               tmp.particle_damage(), cycles, (long long)c_.pinned, (long long)c_.solves,
               (long long)c_.iterations, (long long)c_.builds, c_.work, r.stored_energy,
               c_.released, idle ? 1 : 0, c_.seconds_before + MPI_Wtime() - start_);
  std::fflush(curve_);
}

void Protocol::visit_idle(std::int64_t step) {
  const double previous = system_.top_displacement();
  system_.rescale(step_displacement(step));
  const TensionResponse r = system_.response();
  c_.work += 0.5 * (c_.reaction + r.reaction) * (r.top_displacement - previous);
  c_.reaction = r.reaction;
  c_.step = step;
  c_.visited_steps += 1;
  if (r.stress_zz > c_.peak_stress) {
    c_.peak_stress = r.stress_zz;
    c_.strain_at_peak = r.strain_zz;
  }
  write_row(step, r, r.stress_zz, 0, true);
}

PetscLogStage rupture_stage() {
  static PetscLogStage stage = [] {
    PetscLogStage s;
    PetscLogStageRegister("Ruptures", &s);
    return s;
  }();
  return stage;
}

void Protocol::visit(std::int64_t step, bool first) {
  const double previous = system_.top_displacement();
  const double delta = step_displacement(step);
  if (first || !o_.skip_idle)
    account(system_.solve(delta), false);
  else
    system_.rescale(delta);
  TensionResponse r = system_.response();
  c_.work += 0.5 * (c_.reaction + r.reaction) * (delta - previous);
  const double stress_before = r.stress_zz, energy_before = r.stored_energy;
  if (first) check_first_increment();

  int cycles = 0;
  std::int64_t new_breaks = 0;
  for (;;) {
    LEM_PETSC(PetscLogStagePush(rupture_stage()));
    const std::vector<Rupture> critical = find_critical();
    if (critical.empty()) {
      LEM_PETSC(PetscLogStagePop());
      break;
    }
    c_.batches += 1;
    std::vector<std::int64_t> ids;
    ids.reserve(critical.size());
    for (const Rupture& x : critical) {
      ids.push_back(x.id);
      c_.broken[x.phase] += 1;
      events_.bond_events.push_back(x.id);
      events_.bond_batches.push_back(c_.batches);
      if (rank_ == 0)
        std::fprintf(log_, "%lld,%d,%.12e,%lld,%s,%.9g,%.9g,%.9g,%.12e,%.12e\n",
                     (long long)step, cycles, r.strain_zz, (long long)x.id,
                     kPhaseNames[x.phase], x.x, x.y, x.z, x.force, x.threshold);
    }
    new_breaks += static_cast<std::int64_t>(critical.size());
    apply_batch(ids, {});
    // Pieces cut loose by this batch: pin them.
    // Pinned rows trade their bonds for a diagonal of the same size: the
    // kept preconditioner stays usable (a failure would retry with a new one).
    const PieceReport pieces = pieces_.find();
    // Every rank must list the same nodes: gather the owned ones.
    std::vector<std::int64_t> owned_loose;
    for (int n : pieces.loose_nodes)
      if (n < l_.owned) owned_loose.push_back(l_.node_id[n]);
    std::vector<std::int64_t> loose = allgather(l_.comm, owned_loose);
    std::sort(loose.begin(), loose.end());
    if (!loose.empty()) {
      std::int64_t before = 0, after = 0;
      for (int b = 0; b < l_.local_bonds(); ++b) before += l_.bond_reported[b] && l_.bond_stiffness[b] > 0;
      apply_batch({}, loose);
      for (int b = 0; b < l_.local_bonds(); ++b) after += l_.bond_reported[b] && l_.bond_stiffness[b] > 0;
      std::int64_t detached = before - after, total = 0;
      MPI_Allreduce(&detached, &total, 1, MPI_INT64_T, MPI_SUM, l_.comm);
      c_.detached += total;
      c_.pinned += static_cast<std::int64_t>(loose.size());
      for (std::int64_t id : loose) {
        events_.node_events.push_back(id);
        events_.node_batches.push_back(c_.batches);
      }
    }
    c_.pieces = pieces.pieces;
    system_.finish_updates();
    LEM_PETSC(PetscLogStagePop());
    c_.ruptures_since_build += static_cast<std::int64_t>(critical.size());
    if (o_.rebuild_after_ruptures > 0 && c_.ruptures_since_build >= o_.rebuild_after_ruptures)
      system_.rebuild_preconditioner();
    account(system_.solve(delta), true);
    cycles += 1;
    if (MPI_Wtime() - last_progress_ >= 10.0) {  // a long avalanche: say it goes on
      last_progress_ = MPI_Wtime();
      say("step %7lld  relaxing: cycle %d, %lld bonds broken at this step so far, %.1f s\n",
          (long long)step, cycles, (long long)new_breaks,
          c_.seconds_before + last_progress_ - start_);
    }
    if (!pieces.faces_joined) {
      disconnected_ = true;
      break;
    }
    if (o_.stop_within_step &&
        system_.response().stress_zz < o_.stop_fraction * std::max(c_.peak_stress, stress_before))
      break;  // the run ends after this step (the stress check of run())
  }
  if (rank_ == 0 && new_breaks > 0) std::fflush(log_);
  r = system_.response();
  c_.released += energy_before - r.stored_energy;
  c_.reaction = r.reaction;
  c_.step = step;
  c_.visited_steps += 1;
  c_.cycles += cycles;
  if (new_breaks > 0) c_.rupture_steps += 1;
  if (first) c_.young_modulus = r.young_modulus;
  if (r.stress_zz > c_.peak_stress) {
    c_.peak_stress = r.stress_zz;
    c_.strain_at_peak = r.strain_zz;
  }
  write_row(step, r, stress_before, cycles, false);
  progress(step, r.stress_zz, new_breaks, cycles);
  if (o_.snapshot_steps > 0 && step / o_.snapshot_steps != last_snapshot_ / o_.snapshot_steps) {
    // Zero-padded names: ParaView opens the series as one time-dependent set.
    char stem[32];
    std::snprintf(stem, sizeof(stem), "/snapshot_%07lld", static_cast<long long>(step));
    Summary s;
    s.add("step", static_cast<long long>(step));
    s.add("strain", r.strain_zz);
    s.add("stress_norm", r.stress_zz * o_.stress_unit / o_.strength_unit);
    write_tension_fields(o_.output_dir + stem, l_, system_, provenance_, s);
  }
  last_snapshot_ = step;
}

void Protocol::write_elastic_fields() const {
  // The first equilibrium: bare contacts in tension have opened, nothing
  // else has broken.  Scaled by the applied stress, its node stresses are
  // those of every load before the first rupture (paper figs. 7, 8).
  const TensionResponse r = system_.response();
  Summary s;
  s.add("step", 1LL);
  s.add("strain", r.strain_zz);
  s.add("applied_stress", r.stress_zz);
  s.add("stress_norm", r.stress_zz * o_.stress_unit / o_.strength_unit);
  const auto mean = write_tension_fields(o_.output_dir + "/elastic", l_, system_, provenance_, s);
  if (mean)
    say("node stresses at the first equilibrium: volume average of sigma_zz = %.10g, applied "
        "%.10g (relative gap %.1e)\n",
        (*mean)[kZZ], r.stress_zz, std::fabs((*mean)[kZZ] / r.stress_zz - 1));
}

void Protocol::check_first_increment() const {
  // Bonds of positive threshold broken in bulk by the very first increment
  // mean the increment skips the whole elastic regime.
  const std::vector<double> tension = system_.bond_tensions();
  double local[2] = {0, 0}, global[2];  // count over threshold, largest force/threshold
  std::int64_t counted = 0, total = 0;
  for (int b = 0; b < l_.local_bonds(); ++b) {
    if (!l_.bond_reported[b] || l_.bond_stiffness[b] <= 0 || l_.bond_strength[b] <= 0) continue;
    ++counted;
    const double ratio = tension[b] / l_.bond_strength[b];
    if (ratio > 1) local[0] += 1;
    local[1] = std::max(local[1], ratio);
  }
  MPI_Allreduce(&local[0], &global[0], 1, MPI_DOUBLE, MPI_SUM, l_.comm);
  MPI_Allreduce(&local[1], &global[1], 1, MPI_DOUBLE, MPI_MAX, l_.comm);
  MPI_Allreduce(&counted, &total, 1, MPI_INT64_T, MPI_SUM, l_.comm);
  if (total > 0 && global[0] > 1e-3 * static_cast<double>(total)) {
    std::ostringstream m;
    m << "option -fracture_increment = " << o_.increment << " is too large for this sample: "
      << "the first increment already overloads " << static_cast<long long>(global[0])
      << " bonds (up to " << global[1] << " times their threshold); take it below "
      << o_.increment / (10 * global[1]) << " so that the elastic regime has a few steps";
    throw InputError(m.str());
  }
}

void Protocol::progress(std::int64_t step, double stress, std::int64_t new_breaks, int cycles) {
  const double now = MPI_Wtime();
  if (new_breaks == 0 && now - last_progress_ < 10.0) return;
  last_progress_ = now;
  const double elapsed = c_.seconds_before + now - start_;
  std::int64_t broken = 0;
  for (auto b : c_.broken) broken += b;
  // After the peak: extrapolate the recent rates (over the last quarter of
  // the time since the peak, the tail slows down) to whichever end comes
  // first, the stop level of the stress or the strain bound.
  std::string estimate = "before the peak";
  const double target = o_.stop_fraction * c_.peak_stress;
  const double strain = strain_of(step);
  if (stress >= c_.peak_stress || c_.peak_stress <= 0) {
    recent_.clear();
  } else {
    if (recent_.empty()) tail_start_ = elapsed;
    recent_.push_back({elapsed, stress, strain});
    const double since = std::max(10.0, 0.25 * (elapsed - tail_start_));
    while (recent_.size() > 2 && elapsed - recent_[1].seconds > since) recent_.pop_front();
    const ProgressPoint& old = recent_.front();
    const double dt = elapsed - old.seconds;
    double left = -1;
    if (dt > 0 && old.stress > stress) left = (stress - target) / ((old.stress - stress) / dt);
    if (dt > 0 && o_.max_strain_ratio > 0 && strain > old.strain) {
      const double to_bound = (o_.max_strain_ratio * c_.strain_at_peak - strain) /
                              ((strain - old.strain) / dt);
      left = left < 0 ? to_bound : std::min(left, to_bound);
    }
    estimate = left < 0 ? "after the peak" : "~" + std::to_string(static_cast<long long>(
                                                       std::max(0.0, left))) + " s left";
  }
  say("step %7lld  eps %.4e  sigma/sigma_u %.4f (peak %.4f)  broken %lld (+%lld in %d cycles)  "
      "loose nodes %lld  solves %lld  its %lld  PC builds %lld  %.1f s  %s\n",
      (long long)step, strain_of(step), stress * o_.stress_unit / o_.strength_unit,
      c_.peak_stress * o_.stress_unit / o_.strength_unit, (long long)broken,
      (long long)new_breaks, cycles, (long long)c_.pinned, (long long)c_.solves,
      (long long)c_.iterations, (long long)c_.builds, elapsed, estimate.c_str());
}

void Protocol::take_snapshot() {
  if (rank_ == 0) {
    std::fflush(curve_);
    std::fflush(log_);
    c_.curve_bytes = std::ftell(curve_);
    c_.log_bytes = std::ftell(log_);
  }
  MPI_Bcast(&c_.curve_bytes, 1, MPI_INT64_T, 0, l_.comm);
  MPI_Bcast(&c_.log_bytes, 1, MPI_INT64_T, 0, l_.comm);
  c_.rebuild_pending = system_.preconditioner_rebuild_pending();
  last_.counters = c_;
  last_.counters.seconds_before = c_.seconds_before + MPI_Wtime() - start_;
  last_.bond_events = events_.bond_events.size();
  last_.node_events = events_.node_events.size();
  last_.builds = events_.build_batches.size();
  last_.u = system_.solution();
}

void Protocol::write_checkpoint() {
  // The last equilibrium (take_snapshot), displacements by lattice node id.
  const std::vector<double>& u = last_.u;
  std::vector<std::int64_t> ids(l_.node_id.begin(), l_.node_id.begin() + l_.owned);
  const auto all_ids = allgather(l_.comm, ids);
  const auto all_u = allgather(l_.comm, u);
  if (rank_ == 0) {
    std::fflush(curve_);
    std::fflush(log_);
    ::fsync(fileno(curve_));
    ::fsync(fileno(log_));
  }
  run_on_root(l_.comm, [&] {
    Checkpoint c;
    c.counters = last_.counters;
    c.fingerprint = fingerprint_;
    const auto nb = static_cast<std::ptrdiff_t>(last_.bond_events);
    const auto nn = static_cast<std::ptrdiff_t>(last_.node_events);
    c.bond_events.assign(events_.bond_events.begin(), events_.bond_events.begin() + nb);
    c.bond_batches.assign(events_.bond_batches.begin(), events_.bond_batches.begin() + nb);
    c.node_events.assign(events_.node_events.begin(), events_.node_events.begin() + nn);
    c.node_batches.assign(events_.node_batches.begin(), events_.node_batches.begin() + nn);
    c.build_batches.assign(events_.build_batches.begin(),
                           events_.build_batches.begin() +
                               static_cast<std::ptrdiff_t>(last_.builds));
    c.displacement.assign(3 * static_cast<std::size_t>(l_.global_nodes), 0.0);
    for (std::size_t i = 0; i < all_ids.size(); ++i)
      for (int a = 0; a < 3; ++a) c.displacement[3 * all_ids[i] + a] = all_u[3 * i + a];
    write_checkpoint_file(checkpoint_path_, c);
  });
  last_checkpoint_time_ = MPI_Wtime();
}

bool Protocol::stop_requested() {
  int mine = g_stop_signal, any = 0;
  MPI_Allreduce(&mine, &any, 1, MPI_INT, MPI_MAX, l_.comm);
  return any != 0;
}

FractureResult Protocol::run() {
  SignalGuard guard;
  g_stop_signal = 0;
  start_ = last_checkpoint_time_ = MPI_Wtime();
  if (l_.bond_strength.empty())
    throw std::logic_error("run_fracture: the lattice has no breaking thresholds");
  system_.set_reuse_preconditioner(true);
  resumed_ = try_resume();
  open_results(resumed_);
  if (resumed_) {
    say("resumed from %s at step %lld (%lld bonds broken)\n", checkpoint_path_.c_str(),
        (long long)c_.step, (long long)events_.bond_events.size());
  } else {
    c_.next_checkpoint_step = o_.checkpoint_steps;
    visit(1, true);
    if (o_.elastic_fields) write_elastic_fields();
  }
  if (o_.after_first_solve) o_.after_first_solve();
  std::string end;
  for (;;) {
    const double stop_level = o_.stop_fraction * c_.peak_stress;
    const std::int64_t broken = static_cast<std::int64_t>(events_.bond_events.size());
    if (disconnected_) end = "no piece joins the bottom to the top face";
    else if (broken > 0 && c_.reaction / (l_.box.length(0) * l_.box.length(1)) < stop_level)
      end = "stress below the stop fraction of the peak";
    else if (broken > 0 && o_.max_strain_ratio > 0 && c_.strain_at_peak > 0 &&
             strain_of(c_.step) > o_.max_strain_ratio * c_.strain_at_peak)
      end = "strain beyond -fracture_max_strain_ratio times the strain at the peak";
    else if (c_.step >= o_.max_steps) end = "reached -fracture_max_steps";
    if (!end.empty()) break;

    const bool signal = stop_requested();
    const double now = MPI_Wtime();
    double since = now - last_checkpoint_time_;
    MPI_Bcast(&since, 1, MPI_DOUBLE, 0, l_.comm);  // one decision for every rank
    const bool by_steps = o_.checkpoint_steps > 0 && c_.step >= c_.next_checkpoint_step;
    if (signal || by_steps || (o_.checkpoint_seconds > 0 && since >= o_.checkpoint_seconds)) {
      while (o_.checkpoint_steps > 0 && c_.next_checkpoint_step <= c_.step)
        c_.next_checkpoint_step += o_.checkpoint_steps;
      take_snapshot();
      write_checkpoint();
      if (signal)
        throw Interrupted("stopped by a signal at step " + std::to_string(c_.step) +
                          "; checkpoint written to " + checkpoint_path_ +
                          "; run the same command again to resume");
    }

    const std::int64_t next = o_.skip_idle ? next_critical_step() : c_.step + 1;
    if (next > o_.max_steps) {
      end = next == o_.max_steps + 1 && o_.skip_idle ? "no rupture before -fracture_max_steps"
                                                     : "reached -fracture_max_steps";
      break;
    }
    take_snapshot();
    try {
      if (next - 1 > c_.step) visit_idle(next - 1);
      visit(next, false);
    } catch (const NumericalError& e) {
      write_checkpoint();
      throw NumericalError(std::string(e.what()) + "; the state of step " +
                           std::to_string(last_.counters.step) + " is saved in " +
                           checkpoint_path_ + ": rerun (e.g. with other -ksp_/-pc_ options) "
                           "to resume from it");
    }
  }

  // Complete: move the results into place, drop the checkpoint.
  run_on_root(l_.comm, [&] {
    std::fclose(curve_);
    std::fclose(log_);
    curve_ = log_ = nullptr;
    for (const std::string& path : {curve_path_, log_path_})
      if (std::rename((path + ".part").c_str(), path.c_str()) != 0)
        throw InputError("cannot rename '" + path + ".part': " + std::strerror(errno));
    std::remove(checkpoint_path_.c_str());
  });

  const TensionResponse r = system_.response();
  FractureResult result;
  result.young_modulus = c_.young_modulus;
  result.peak_stress = c_.peak_stress;
  result.strain_at_peak = c_.strain_at_peak;
  result.final_stress = r.stress_zz;
  result.final_strain = r.strain_zz;
  result.steps = c_.step;
  result.visited_steps = c_.visited_steps;
  result.solves = c_.solves;
  result.iterations = c_.iterations;
  result.preconditioner_builds = c_.builds;
  result.fallback_solves = c_.fallbacks;
  result.rupture_steps = c_.rupture_steps;
  result.relaxation_cycles = c_.cycles;
  std::copy(std::begin(c_.broken), std::end(c_.broken), result.broken.begin());
  result.detached_bonds = c_.detached;
  result.pinned_nodes = c_.pinned;
  result.work = c_.work;
  result.stored_energy = r.stored_energy;
  result.released_energy = c_.released;
  result.energy_balance_error =
      c_.work > 0 ? std::fabs(c_.work - r.stored_energy - c_.released) / c_.work : 0.0;
  result.end_reason = end;
  result.seconds = c_.seconds_before + MPI_Wtime() - start_;
  result.resumed = resumed_;
  return result;
}

}  // namespace

FractureResult run_fracture(DistributedLattice& lattice, ElasticSystem& system,
                            const FractureOptions& options, const Provenance& provenance) {
  Protocol protocol(lattice, system, options, provenance);
  return protocol.run();
}

}  // namespace lem
