#include "lem/protocol/recorder.hpp"

#include "lem/driver.hpp"
#include "lem/error.hpp"
#include "lem/files.hpp"
#include "lem/node_stress.hpp"
#include "lem/summary.hpp"
#include "lem/tension_output.hpp"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <unistd.h>

namespace lem {

FractureRecorder::FractureRecorder(const DistributedLattice& lattice, const ElasticSystem& system,
                                   const FractureOptions& options, const Provenance& provenance)
    : lattice_(lattice), system_(system), options_(options), provenance_(provenance),
      curve_path_(options.output_dir + "/curve.csv"),
      broken_path_(options.output_dir + "/broken.csv") {
  MPI_Comm_rank(lattice.comm, &rank_);
}

void FractureRecorder::open_new() {
  run_on_root(lattice_.comm, [&] {
    curve_.reset(std::fopen((curve_path_ + ".part").c_str(), "wb"));
    broken_.reset(std::fopen((broken_path_ + ".part").c_str(), "wb"));
    if (!curve_ || !broken_)
      throw InputError("cannot write the results in '" + options_.output_dir + "': " +
                       std::strerror(errno));
    // Snapshots of an earlier run would mix with this run's.
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(options_.output_dir, ec))
      if (entry.path().filename().string().rfind("snapshot_", 0) == 0)
        std::filesystem::remove(entry.path(), ec);
    std::fprintf(curve_.get(),
                 "# stress-strain curve of lem_fracture; sigma columns normalised by "
                 "sigma_unit = %.10g (E^phase units), raw stress in E^phase units, energies in "
                 "lattice units (k a^2)\n"
                 "step,strain,displacement_over_a,stress_before_norm,stress_norm,stress,"
                 "broken,broken_p,broken_m,broken_pp,broken_pm,n_b,cycles,loose_nodes,"
                 "solves,iterations,pc_builds,work,stored_energy,released_energy,idle,"
                 "elapsed_s\n",
                 options_.strength_unit);
    std::fprintf(broken_.get(), "step,cycle,strain,bond_id,phase,x,y,z,force,threshold\n");
    std::fflush(curve_.get());
    std::fflush(broken_.get());
  });
}

void FractureRecorder::reopen(const ResultFileMarks& marks) {
  run_on_root(lattice_.comm, [&] {
    // Drop the rows written after the checkpoint.
    for (auto [path, size] : {std::pair{curve_path_ + ".part", marks.curve_bytes},
                              std::pair{broken_path_ + ".part", marks.broken_bytes}}) {
      if (::truncate(path.c_str(), static_cast<off_t>(size)) != 0)
        throw InputError("cannot resume: '" + path + "' is missing or unwritable (" +
                         std::strerror(errno) + "); remove the checkpoint to start over");
    }
    curve_.reset(std::fopen((curve_path_ + ".part").c_str(), "ab"));
    broken_.reset(std::fopen((broken_path_ + ".part").c_str(), "ab"));
    if (!curve_ || !broken_)
      throw InputError("cannot write the results in '" + options_.output_dir + "': " +
                       std::strerror(errno));
    // ftell() of a fresh append stream may say 0 until the first write.
    std::fseek(curve_.get(), 0, SEEK_END);
    std::fseek(broken_.get(), 0, SEEK_END);
  });
}

void FractureRecorder::curve_row(std::int64_t step, const TensionResponse& r,
                                 double stress_before, int cycles, bool idle,
                                 const FractureTally& t, double elapsed) {
  if (rank_ != 0) return;
  const double su = options_.stress_unit, norm = su / options_.strength_unit;
  std::fprintf(curve_.get(),
               "%lld,%.12e,%.12e,%.12e,%.12e,%.12e,%lld,%lld,%lld,%lld,%lld,%.6f,%d,%lld,%lld,"
               "%lld,%lld,%.12e,%.12e,%.12e,%d,%.3f\n",
               (long long)step, r.strain_zz, r.top_displacement / lattice_.mean_bond_length,
               stress_before * norm, r.stress_zz * norm, r.stress_zz * su,
               (long long)t.broken_total(), (long long)t.broken[0], (long long)t.broken[1],
               (long long)t.broken[3], (long long)t.broken[4], t.particle_damage(), cycles,
               (long long)t.pinned_nodes, (long long)t.solves, (long long)t.iterations,
               (long long)t.preconditioner_builds, t.work, r.stored_energy, t.released_energy,
               idle ? 1 : 0, elapsed);
  std::fflush(curve_.get());
}

void FractureRecorder::rupture(std::int64_t step, int cycle, double strain, const Rupture& x) {
  if (rank_ != 0) return;
  std::fprintf(broken_.get(), "%lld,%d,%.12e,%lld,%s,%.9g,%.9g,%.9g,%.12e,%.12e\n",
               (long long)step, cycle, strain, (long long)x.id, kPhaseNames[x.phase], x.x, x.y,
               x.z, x.force, x.threshold);
}

void FractureRecorder::flush_ruptures() {
  if (rank_ == 0) std::fflush(broken_.get());
}

ResultFileMarks FractureRecorder::marks() {
  ResultFileMarks m;
  if (rank_ == 0) {
    std::fflush(curve_.get());
    std::fflush(broken_.get());
    m.curve_bytes = std::ftell(curve_.get());
    m.broken_bytes = std::ftell(broken_.get());
  }
  MPI_Bcast(&m, sizeof(m), MPI_BYTE, 0, lattice_.comm);
  return m;
}

void FractureRecorder::sync() {
  if (rank_ != 0) return;
  std::fflush(curve_.get());
  std::fflush(broken_.get());
  ::fsync(fileno(curve_.get()));
  ::fsync(fileno(broken_.get()));
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
    curve_.reset();
    broken_.reset();
    for (const std::string& path : {curve_path_, broken_path_})
      move_into_place(path + ".part", path);
  });
}

}  // namespace lem
