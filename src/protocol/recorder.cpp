#include "lem/protocol/recorder.hpp"

#include "lem/base/log.hpp"
#include "lem/base/error.hpp"
#include "lem/base/files.hpp"
#include "lem/io/hdf5_util.hpp"
#include "lem/system/node_stress.hpp"
#include "lem/base/summary.hpp"
#include "lem/fields/tension_output.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdarg>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <unistd.h>

namespace lem {

FractureRecorder::FractureRecorder(const DistributedLattice& lattice, const ElasticSystem& system,
                                   const FractureOutput& output, const Provenance& provenance)
    : lattice_(lattice), system_(system), output_(output), provenance_(provenance) {
  MPI_Comm_rank(lattice.comm, &rank_);
  curve_.final_path = output.dir + "/curve.csv";
  broken_.final_path = output.dir + "/broken.csv";
}

void FractureRecorder::Stream::open(const char* mode) {
  file.reset(std::fopen(part().c_str(), mode));
  if (!file) throw IoError("cannot open '" + part() + "': " + std::strerror(errno));
  error.clear();
  crc = 0;
}

void FractureRecorder::Stream::print(const char* format, ...) {
  // After a failure nothing more is written: a full disk that frees again
  // must not splice rows together.
  if (!file || !error.empty()) return;
  // Formatted here first, so that the checksum sees the bytes written.
  char row[512];
  std::string longer;
  va_list args, again;
  va_start(args, format);
  va_copy(again, args);
  const int n = std::vsnprintf(row, sizeof row, format, args);
  va_end(args);
  const char* text = row;
  if (n >= static_cast<int>(sizeof row)) {
    longer.resize(static_cast<std::size_t>(n) + 1);
    std::vsnprintf(longer.data(), longer.size(), format, again);
    text = longer.data();
  }
  va_end(again);
  if (n < 0) {
    error = std::strerror(errno);
    return;
  }
  const auto size = static_cast<std::size_t>(n);
  if (std::fwrite(text, 1, size, file.get()) != size) {
    error = std::strerror(errno);
    return;
  }
  crc = crc32(text, size, crc);
}

void FractureRecorder::Stream::flush() {
  if (file && error.empty() && std::fflush(file.get()) != 0) error = std::strerror(errno);
}

void FractureRecorder::Stream::check() {
  flush();
  // stdio's error flag is sticky: it also catches a failed implicit flush.
  if (file && error.empty() && std::ferror(file.get())) error = "a write failed";
  if (!error.empty())
    throw IoError("cannot write '" + part() + "': " + error +
                  " (the results are incomplete; "
                  "nothing was renamed)");
}

void FractureRecorder::Stream::sync() {
  check();
  if (::fsync(fileno(file.get())) != 0)
    throw IoError("cannot sync '" + part() + "': " + std::strerror(errno));
}

void FractureRecorder::Stream::close() {
  sync();
  if (std::fclose(file.release()) != 0)
    throw IoError("cannot close '" + part() + "': " + std::strerror(errno));
}

namespace {

// The columns of curve.csv with their unit or normalisation (curve.json).
struct CurveColumn {
  const char *name, *meaning;
};
const CurveColumn kCurveColumns[] = {
    {"step", "load step (count)"},
    {"strain", "epsilon_zz (dimensionless)"},
    {"displacement_over_a", "top displacement / mean bond length a"},
    {"stress_before_norm", "sigma_zz before the step's ruptures / sigma_unit"},
    {"stress_norm", "sigma_zz at equilibrium / sigma_unit"},
    {"stress", "sigma_zz at equilibrium (E^phase units)"},
    {"broken", "broken bonds so far (count)"},
    {"broken_p", "broken particle bonds (count)"},
    {"broken_m", "broken matrix bonds (count)"},
    {"broken_pp", "broken particle-particle contacts (count)"},
    {"broken_pm", "broken particle-matrix interface bonds (count)"},
    {"n_b", "particle damage n_b: broken particle bonds / broken bonds"},
    {"cycles", "relaxation cycles of the step (count)"},
    {"loose_nodes", "pinned nodes: cut loose from the loaded pieces (count)"},
    {"solves", "linear solves so far (count)"},
    {"iterations", "Krylov iterations so far (count)"},
    {"pc_builds", "preconditioner builds so far (count)"},
    {"work", "external work (lattice units k a^2)"},
    {"stored_energy", "elastic energy of the bonds (lattice units k a^2)"},
    {"released_energy", "energy released by the relaxations, bonds and ground springs "
                        "(lattice units k a^2)"},
    {"ground_energy", "energy of the ground springs (lattice units k a^2); "
                      "work = stored + released + ground"},
    {"idle", "1 for an idle step (scaled, no solve), 0 for an evaluated one"},
    {"elapsed_s", "wall time since the start (s)"},
};

// The step of a snapshot file as the recorder names it (snapshot_<step>.h5,
// .xmf, _nodes.xmf, also under a temporary .tmp name), or -1 for any other
// name: a user's snapshot_notes.txt is left alone.
std::int64_t snapshot_step(std::string name) {
  const std::string prefix = "snapshot_";
  if (name.size() > 4 && name.compare(name.size() - 4, 4, ".tmp") == 0)
    name.resize(name.size() - 4);
  if (name.rfind(prefix, 0) != 0) return -1;
  std::size_t end = prefix.size();
  while (end < name.size() && name[end] >= '0' && name[end] <= '9') ++end;
  const std::string rest = name.substr(end);
  if (end - prefix.size() < 7 || (rest != ".h5" && rest != ".xmf" && rest != "_nodes.xmf"))
    return -1;
  return std::stoll(name.substr(prefix.size(), end - prefix.size()));
}

// snapshot_<step>.xmf (the bonds grid), not snapshot_<step>_nodes.xmf.
bool is_snapshot_grid(const std::string& name) {
  return snapshot_step(name) >= 0 && name.size() > 4 &&
         name.compare(name.size() - 4, 4, ".xmf") == 0 &&
         name.find("_nodes.xmf") == std::string::npos;
}

// Rank 0: remove the snapshots of `dir` after load step `last` (all: -1),
// and their series, which finish() writes again.
void remove_snapshots_after(const std::string& dir, std::int64_t last) {
  std::error_code ec;
  std::vector<std::filesystem::path> stale;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (snapshot_step(name) > last || name == "snapshots.xmf") stale.push_back(entry.path());
  }
  for (const auto& path : stale) std::filesystem::remove(path, ec);
}

// The load step of the last row of a curve file cut back to its checkpoint
// (0 when it holds the header only).
std::int64_t last_curve_step(const std::string& path) {
  std::ifstream in(path);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  long long step = 0;
  return std::sscanf(last.c_str(), "%lld,", &step) == 1 ? step : 0;
}

}  // namespace

std::string FractureRecorder::curve_header() {
  std::string header;
  for (const CurveColumn& c : kCurveColumns) {
    if (!header.empty()) header += ',';
    header += c.name;
  }
  return header;
}

std::string FractureRecorder::curve_sidecar() const {
  Summary s;
  s.add("file", std::string("curve.csv"));
  s.add("description", std::string("stress-strain curve of lem_fracture, one row per evaluated "
                                   "load step"));
  s.add("sigma_unit", output_.strength_unit, "E^phase");
  for (const CurveColumn& c : kCurveColumns) s.add(c.name, std::string(c.meaning));
  s.add_provenance(provenance_);
  return s.json();
}

void FractureRecorder::open_new() {
  run_on_root(lattice_.comm, [&] {
    curve_.open("wb");
    broken_.open("wb");
    // Snapshots of an earlier run would mix with this run's.
    remove_snapshots_after(output_.dir, -1);
    // The header row comes first, so that any CSV reader takes the file as
    // it is; units and the normalisation go to the sidecar curve.json.
    curve_.print("%s\n", curve_header().c_str());
    broken_.print("step,cycle,strain,bond_id,phase,x,y,z,force,threshold\n");
    curve_.check();
    broken_.check();
    write_text_file_atomically(output_.dir + "/curve.json", curve_sidecar());
  });
}

// Rank 0 of a resumed run: the log of `stream`, taken back from its final
// name if the run was killed after renaming it, must begin with what the
// checkpoint recorded: `bytes` bytes of CRC-32 `crc`.
void FractureRecorder::take_back(const Stream& stream, std::int64_t bytes, std::uint32_t crc) {
  namespace fs = std::filesystem;
  const std::string part = stream.part(), final_path = stream.final_path;
  std::error_code ec;
  // A run killed after renaming its logs but before committing them
  // (no manifest): they are still this run's, so take them back.
  if (!fs::exists(part, ec) && fs::exists(final_path, ec)) {
    if (std::rename(final_path.c_str(), part.c_str()) != 0)
      throw IoError("cannot resume: renaming '" + final_path + "' back to '" + part +
                    "' failed: " + std::strerror(errno));
    sync_directory(output_.dir);
  }
  const auto actual = fs::file_size(part, ec);
  if (ec)
    throw InputError("cannot resume: '" + part + "' is missing (" + ec.message() +
                     "); remove the checkpoint to start over");
  // Padding it would put NUL bytes in the results.
  if (static_cast<std::int64_t>(actual) < bytes)
    throw InputError("cannot resume: '" + part + "' has " + std::to_string(actual) +
                     " bytes, fewer than the " + std::to_string(bytes) +
                     " the checkpoint "
                     "records (damaged or replaced); remove the checkpoint to start over");
  // An edit would otherwise be sealed into the result with a fresh checksum.
  const std::uint32_t found = file_prefix_crc32(part, static_cast<std::uint64_t>(bytes));
  if (found != crc)
    throw InputError("cannot resume: '" + part +
                     "' has other content than the checkpoint recorded (checksum " +
                     crc32_text(found) + " of its first " + std::to_string(bytes) +
                     " bytes, the checkpoint says " + crc32_text(crc) +
                     "); remove the checkpoint to start over");
}

void FractureRecorder::reopen(const ResultFileMarks& marks) {
  run_on_root(lattice_.comm, [&] {
    take_back(curve_, marks.curve_bytes, marks.curve_crc);
    take_back(broken_, marks.broken_bytes, marks.broken_crc);
    // Both checked: drop the rows written after the checkpoint.
    for (const auto& [stream, bytes] :
         {std::pair{&curve_, marks.curve_bytes}, std::pair{&broken_, marks.broken_bytes}})
      if (::truncate(stream->part().c_str(), static_cast<off_t>(bytes)) != 0)
        throw IoError("cannot resume: '" + stream->part() + "' is unwritable (" +
                      std::strerror(errno) + "); remove the checkpoint to start over");
    // Snapshots written after the checkpoint: the resumed run writes those it
    // reaches again, and one it does not reach (a lower -fracture_max_steps)
    // is not part of its result.
    remove_snapshots_after(output_.dir, last_curve_step(curve_.part()));
    curve_.open("ab");
    broken_.open("ab");
    curve_.crc = marks.curve_crc;
    broken_.crc = marks.broken_crc;
    // ftell() of a fresh append stream may say 0 until the first write.
    std::fseek(curve_.file.get(), 0, SEEK_END);
    std::fseek(broken_.file.get(), 0, SEEK_END);
  });
}

void FractureRecorder::curve_row(std::int64_t step, const TensionResponse& r, double stress_before,
                                 int cycles, bool idle, const FractureTally& t, double elapsed) {
  if (rank_ != 0) return;
  const double su = output_.stress_unit, norm = su / output_.strength_unit;
  curve_.print("%lld,%.12e,%.12e,%.12e,%.12e,%.12e,%lld,%lld,%lld,%lld,%lld,%.6f,%d,%lld,%lld,"
               "%lld,%lld,%.12e,%.12e,%.12e,%.12e,%d,%.3f\n",
               (long long)step, r.strain_zz, r.top_displacement / lattice_.mean_bond_length,
               stress_before * norm, r.stress_zz * norm, r.stress_zz * su,
               (long long)t.broken_total(), (long long)t.broken[0], (long long)t.broken[1],
               (long long)t.broken[3], (long long)t.broken[4], t.particle_damage(), cycles,
               (long long)t.pinned_nodes, (long long)t.solves, (long long)t.iterations,
               (long long)t.preconditioner_builds, t.work, r.stored_energy, t.released_energy,
               r.ground_energy, idle ? 1 : 0, elapsed);
  curve_.flush();
}

void FractureRecorder::rupture(std::int64_t step, int cycle, double strain, const Rupture& x) {
  if (rank_ != 0) return;
  broken_.print("%lld,%d,%.12e,%lld,%s,%.9g,%.9g,%.9g,%.12e,%.12e\n", (long long)step, cycle,
                strain, (long long)x.id, kPhaseNames[x.phase], x.x, x.y, x.z, x.force, x.threshold);
}

void FractureRecorder::flush_ruptures() {
  if (rank_ == 0) broken_.flush();
}

ResultFileMarks FractureRecorder::marks() {
  ResultFileMarks m;
  run_on_root(lattice_.comm, [&] {
    curve_.check();
    broken_.check();
    m.curve_bytes = std::ftell(curve_.file.get());
    m.broken_bytes = std::ftell(broken_.file.get());
    m.curve_crc = curve_.crc;
    m.broken_crc = broken_.crc;
  });
  MPI_Bcast(&m, sizeof(m), MPI_BYTE, 0, lattice_.comm);
  return m;
}

void FractureRecorder::sync() {
  run_on_root(lattice_.comm, [&] {
    curve_.sync();
    broken_.sync();
  });
}

bool FractureRecorder::snapshot_due(std::int64_t step, std::int64_t previous_step) const {
  const std::int64_t every = output_.snapshot_steps;
  return every > 0 && step / every != previous_step / every;
}

void FractureRecorder::snapshot_if_due(std::int64_t step, std::int64_t previous_step,
                                       const TensionResponse& r) {
  if (!snapshot_due(step, previous_step)) return;
  // Zero-padded names: ParaView opens the series as one time-dependent set.
  char stem[32];
  std::snprintf(stem, sizeof(stem), "/snapshot_%07lld", static_cast<long long>(step));
  Summary s;
  s.add("step", static_cast<long long>(step));
  s.add("strain", r.strain_zz);
  s.add("stress_norm", r.stress_zz * output_.stress_unit / output_.strength_unit);
  write_tension_fields(output_.dir + stem, lattice_, system_, provenance_, s);
}

void FractureRecorder::elastic_fields(const TensionResponse& r) {
  // The first equilibrium: bare contacts in tension have opened, nothing
  // else has broken.  Scaled by the applied stress, its node stresses are
  // those of every load before the first rupture (paper figs. 7, 8).
  Summary s;
  s.add("step", 1LL);
  s.add("strain", r.strain_zz);
  s.add("applied_stress", r.stress_zz);
  s.add("stress_norm", r.stress_zz * output_.stress_unit / output_.strength_unit);
  const auto mean =
      write_tension_fields(output_.dir + "/elastic", lattice_, system_, provenance_, s);
  if (mean)
    say("node stresses at the first equilibrium: volume average of sigma_zz = %.10g, applied "
        "%.10g (relative gap %.1e)\n",
        (*mean)[kZZ], r.stress_zz, std::fabs((*mean)[kZZ] / r.stress_zz - 1));
}

void FractureRecorder::finish() {
  run_on_root(lattice_.comm, [&] {
    // Every snapshot of the run (those of a resumed run's first part too),
    // as one series in time, the strain: once, at the end.
    if (output_.snapshot_steps > 0) {
      std::vector<std::string> grids;
      std::error_code ec;
      for (const auto& entry : std::filesystem::directory_iterator(output_.dir, ec))
        if (is_snapshot_grid(entry.path().filename().string()))
          grids.push_back(entry.path().string());
      std::sort(grids.begin(), grids.end());  // zero-padded steps: in time order
      write_xdmf_series(output_.dir + "/snapshots.xmf", grids, "strain");
    }
    // Both closed and synced before either is renamed: a failure renames
    // nothing.
    curve_.close();
    broken_.close();
    for (Stream* stream : {&curve_, &broken_}) {
      if (std::rename(stream->part().c_str(), stream->final_path.c_str()) != 0)
        throw IoError("cannot move '" + stream->part() + "' to '" + stream->final_path +
                      "': " + std::strerror(errno));
      if (stream == &curve_) fault_point("between_renames");
    }
    sync_directory(output_.dir);
  });
}

}  // namespace lem
