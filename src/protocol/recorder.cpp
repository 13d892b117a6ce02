#include "lem/protocol/recorder.hpp"

#include "lem/driver.hpp"
#include "lem/error.hpp"
#include "lem/files.hpp"
#include "lem/node_stress.hpp"
#include "lem/summary.hpp"
#include "lem/tension_output.hpp"

#include <cerrno>
#include <cstdarg>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <unistd.h>

namespace lem {

FractureRecorder::FractureRecorder(const DistributedLattice& lattice, const ElasticSystem& system,
                                   const FractureOptions& options, const Provenance& provenance)
    : lattice_(lattice), system_(system), options_(options), provenance_(provenance) {
  MPI_Comm_rank(lattice.comm, &rank_);
  curve_.final_path = options.output_dir + "/curve.csv";
  broken_.final_path = options.output_dir + "/broken.csv";
}

void FractureRecorder::Stream::open(const char* mode) {
  file.reset(std::fopen(part().c_str(), mode));
  if (!file) throw IoError("cannot open '" + part() + "': " + std::strerror(errno));
  error.clear();
}

void FractureRecorder::Stream::print(const char* format, ...) {
  // After a failure nothing more is written: a full disk that frees again
  // must not splice rows together.
  if (!file || !error.empty()) return;
  va_list args;
  va_start(args, format);
  const int n = std::vfprintf(file.get(), format, args);
  va_end(args);
  if (n < 0) error = std::strerror(errno);
}

void FractureRecorder::Stream::flush() {
  if (file && error.empty() && std::fflush(file.get()) != 0) error = std::strerror(errno);
}

void FractureRecorder::Stream::check() {
  flush();
  // stdio's error flag is sticky: it also catches a failed implicit flush.
  if (file && error.empty() && std::ferror(file.get())) error = "a write failed";
  if (!error.empty())
    throw IoError("cannot write '" + part() + "': " + error + " (the results are incomplete; "
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

void FractureRecorder::open_new() {
  run_on_root(lattice_.comm, [&] {
    curve_.open("wb");
    broken_.open("wb");
    // Snapshots of an earlier run would mix with this run's.
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(options_.output_dir, ec))
      if (entry.path().filename().string().rfind("snapshot_", 0) == 0)
        std::filesystem::remove(entry.path(), ec);
    curve_.print("# stress-strain curve of lem_fracture; sigma columns normalised by "
                 "sigma_unit = %.10g (E^phase units), raw stress in E^phase units, energies in "
                 "lattice units (k a^2)\n"
                 "step,strain,displacement_over_a,stress_before_norm,stress_norm,stress,"
                 "broken,broken_p,broken_m,broken_pp,broken_pm,n_b,cycles,loose_nodes,"
                 "solves,iterations,pc_builds,work,stored_energy,released_energy,idle,"
                 "elapsed_s\n",
                 options_.strength_unit);
    broken_.print("step,cycle,strain,bond_id,phase,x,y,z,force,threshold\n");
    curve_.check();
    broken_.check();
  });
}

void FractureRecorder::reopen(const ResultFileMarks& marks) {
  run_on_root(lattice_.comm, [&] {
    namespace fs = std::filesystem;
    for (auto [stream, size] : {std::pair{&curve_, marks.curve_bytes},
                                std::pair{&broken_, marks.broken_bytes}}) {
      const std::string part = stream->part(), final_path = stream->final_path;
      std::error_code ec;
      // A run killed after renaming its logs but before committing them
      // (no manifest): they are still this run's, so take them back.
      if (!fs::exists(part, ec) && fs::exists(final_path, ec)) {
        if (std::rename(final_path.c_str(), part.c_str()) != 0)
          throw IoError("cannot resume: renaming '" + final_path + "' back to '" + part +
                        "' failed: " + std::strerror(errno));
        sync_directory(options_.output_dir);
      }
      const auto actual = fs::file_size(part, ec);
      if (ec)
        throw InputError("cannot resume: '" + part + "' is missing (" + ec.message() +
                         "); remove the checkpoint to start over");
      // Padding it would put NUL bytes in the results.
      if (static_cast<std::int64_t>(actual) < size)
        throw InputError("cannot resume: '" + part + "' has " + std::to_string(actual) +
                         " bytes, fewer than the " + std::to_string(size) + " the checkpoint "
                         "records (damaged or replaced); remove the checkpoint to start over");
      // Drop the rows written after the checkpoint.
      if (::truncate(part.c_str(), static_cast<off_t>(size)) != 0)
        throw IoError("cannot resume: '" + part + "' is unwritable (" + std::strerror(errno) +
                      "); remove the checkpoint to start over");
    }
    curve_.open("ab");
    broken_.open("ab");
    // ftell() of a fresh append stream may say 0 until the first write.
    std::fseek(curve_.file.get(), 0, SEEK_END);
    std::fseek(broken_.file.get(), 0, SEEK_END);
  });
}

void FractureRecorder::curve_row(std::int64_t step, const TensionResponse& r,
                                 double stress_before, int cycles, bool idle,
                                 const FractureTally& t, double elapsed) {
  if (rank_ != 0) return;
  const double su = options_.stress_unit, norm = su / options_.strength_unit;
  curve_.print("%lld,%.12e,%.12e,%.12e,%.12e,%.12e,%lld,%lld,%lld,%lld,%lld,%.6f,%d,%lld,%lld,"
               "%lld,%lld,%.12e,%.12e,%.12e,%d,%.3f\n",
               (long long)step, r.strain_zz, r.top_displacement / lattice_.mean_bond_length,
               stress_before * norm, r.stress_zz * norm, r.stress_zz * su,
               (long long)t.broken_total(), (long long)t.broken[0], (long long)t.broken[1],
               (long long)t.broken[3], (long long)t.broken[4], t.particle_damage(), cycles,
               (long long)t.pinned_nodes, (long long)t.solves, (long long)t.iterations,
               (long long)t.preconditioner_builds, t.work, r.stored_energy, t.released_energy,
               idle ? 1 : 0, elapsed);
  curve_.flush();
}

void FractureRecorder::rupture(std::int64_t step, int cycle, double strain, const Rupture& x) {
  if (rank_ != 0) return;
  broken_.print("%lld,%d,%.12e,%lld,%s,%.9g,%.9g,%.9g,%.12e,%.12e\n", (long long)step, cycle,
                strain, (long long)x.id, kPhaseNames[x.phase], x.x, x.y, x.z, x.force,
                x.threshold);
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

void FractureRecorder::snapshot_if_due(std::int64_t step, std::int64_t previous_step,
                                       const TensionResponse& r) {
  const std::int64_t every = options_.snapshot_steps;
  if (every <= 0 || step / every == previous_step / every) return;
  // Zero-padded names: ParaView opens the series as one time-dependent set.
  char stem[32];
  std::snprintf(stem, sizeof(stem), "/snapshot_%07lld", static_cast<long long>(step));
  Summary s;
  s.add("step", static_cast<long long>(step));
  s.add("strain", r.strain_zz);
  s.add("stress_norm", r.stress_zz * options_.stress_unit / options_.strength_unit);
  write_tension_fields(options_.output_dir + stem, lattice_, system_, provenance_, s);
}

void FractureRecorder::elastic_fields(const TensionResponse& r) {
  // The first equilibrium: bare contacts in tension have opened, nothing
  // else has broken.  Scaled by the applied stress, its node stresses are
  // those of every load before the first rupture (paper figs. 7, 8).
  Summary s;
  s.add("step", 1LL);
  s.add("strain", r.strain_zz);
  s.add("applied_stress", r.stress_zz);
  s.add("stress_norm", r.stress_zz * options_.stress_unit / options_.strength_unit);
  const auto mean =
      write_tension_fields(options_.output_dir + "/elastic", lattice_, system_, provenance_, s);
  if (mean)
    say("node stresses at the first equilibrium: volume average of sigma_zz = %.10g, applied "
        "%.10g (relative gap %.1e)\n",
        (*mean)[kZZ], r.stress_zz, std::fabs((*mean)[kZZ] / r.stress_zz - 1));
}

void FractureRecorder::finish() {
  run_on_root(lattice_.comm, [&] {
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
    sync_directory(options_.output_dir);
  });
}

}  // namespace lem
