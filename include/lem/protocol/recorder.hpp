// The fracture results of one run directory: the stress-strain curve
// (curve.csv, one row per evaluated load step, with its column units in
// curve.json), every rupture (broken.csv),
// field snapshots and the fields of the first equilibrium.  The CSV files
// grow as <name>.part and are renamed when the run is complete; on resume
// they are cut back to the lengths recorded with the checkpoint, once what
// they hold up to there is what it recorded (a CRC-32 of each).  Every
// write is checked: a failure is remembered on rank 0 and raised on every
// rank as an IoError naming the file at the next collective call (marks,
// sync, finish), before anything is renamed.
#pragma once

#include "lem/system/distributed_lattice.hpp"
#include "lem/system/elastic_system.hpp"
#include "lem/protocol/break_rule.hpp"
#include "lem/protocol/options.hpp"
#include "lem/protocol/state.hpp"
#include "lem/io/hdf5_writer.hpp"

#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>

namespace lem {

class FractureRecorder {
 public:
  FractureRecorder(const DistributedLattice& lattice, const ElasticSystem& system,
                   const FractureOutput& output, const Provenance& provenance);

  /// Start new files (and drop an earlier run's snapshots), or reopen them
  /// at the recorded lengths.  Collective.
  void open_new();
  void reopen(const ResultFileMarks& marks);

  /// Rank 0 writes; the others ignore the call.
  void curve_row(std::int64_t step, const TensionResponse& r, double stress_before, int cycles,
                 bool idle, const FractureTally& tally, double elapsed_seconds);
  void rupture(std::int64_t step, int cycle, double strain, const Rupture& x);
  void flush_ruptures();

  /// Lengths of the files now (flushed), the same on every rank.  Collective;
  /// IoError if a write failed.
  ResultFileMarks marks();
  /// Flush and fsync (before a checkpoint).  Collective; IoError if a write
  /// or the sync failed.
  void sync();

  /// Fields of the current state as snapshot_<step> when a multiple of
  /// -output_snapshot_steps was crossed since `previous_step`.  Collective.
  void snapshot_if_due(std::int64_t step, std::int64_t previous_step, const TensionResponse& r);
  /// Whether snapshot_if_due writes at `step`.
  bool snapshot_due(std::int64_t step, std::int64_t previous_step) const;
  /// elastic.h5: the first equilibrium with its node stresses.  Collective.
  void elastic_fields(const TensionResponse& r);

  /// Close (checked, synced) and move curve.csv and broken.csv into place.
  /// Collective.  They are not committed yet: the driver's manifest does that.
  void finish();

  /// The header row of curve.csv (its first line).
  static std::string curve_header();

 private:
  /// curve.json: what each column of curve.csv holds, in which unit.
  std::string curve_sidecar() const;
  struct FileCloser {
    void operator()(std::FILE* f) const { std::fclose(f); }
  };
  using File = std::unique_ptr<std::FILE, FileCloser>;
  /// A results file growing as <final>.part, with its first failure.
  struct Stream {
    File file;
    std::string final_path, error;
    std::uint32_t crc = 0;  // CRC-32 of every byte written to the file so far
    std::string part() const { return final_path + ".part"; }
    void open(const char* mode);
    void print(const char* format, ...) __attribute__((format(printf, 2, 3)));
    void flush();
    /// Flush, and throw IoError if any write so far failed.
    void check();
    void sync();
    void close();
  };

  /// Rank 0 of a resumed run: the log as the checkpoint recorded it, or InputError.
  void take_back(const Stream& stream, std::int64_t bytes, std::uint32_t crc);

  const DistributedLattice& lattice_;
  const ElasticSystem& system_;
  const FractureOutput& output_;
  const Provenance& provenance_;
  int rank_ = 0;
  Stream curve_, broken_;
};

}  // namespace lem
