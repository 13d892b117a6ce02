// A bound on how long a collective write may hold the job.
//
// Parallel HDF5 does not fail collectively: after an I/O error on one rank
// (a full disk) its ranks can end up in different internal collective
// operations (one closing the MPI file, another in a metadata barrier) and
// wait there for ever, outside any code of ours that could agree on the
// error.  A WriteWatch covers one collective write with a helper thread on
// every rank: once this rank has seen an I/O error (reported by us, or by
// MPI-IO's error handler inside the library), the write must end within
// kErrorGraceSeconds, else the thread removes the temporary file, prints the
// error and ends the job with exit status 3 (MPI_Abort).  A stop request
// (SIGTERM, SIGUSR1) that comes while the write goes on gives it
// write_stop_grace() seconds, then ends the job with status 4 the same way.
#pragma once

#include "lem/base/error.hpp"

#include <mpi.h>

#include <memory>
#include <string>

namespace lem {

class WriteWatch {
 public:
  /// Seconds a write may go on after this rank's I/O error.
  static constexpr double kErrorGraceSeconds = RankEnds::kGraceSeconds;

  /// Watch the write of `file` under the temporary name `temporary` (removed
  /// if the job is ended) by the ranks of `comm`.  Not collective.
  WriteWatch(MPI_Comm comm, std::string file, std::string temporary);
  ~WriteWatch();
  WriteWatch(const WriteWatch&) = delete;
  WriteWatch& operator=(const WriteWatch&) = delete;

  /// This rank's I/O error in the write being watched (the first one counts),
  /// if a watch is active; from now on the write has kErrorGraceSeconds.
  static void note_error(const std::string& why);
  /// The first I/O error of the active watch on this rank ("" if none).
  static std::string first_error();
  /// "; <n> bytes free on the filesystem of <folder>" for the file of the
  /// active watch, with "(full: no space left on device)" below 1 MiB: MPI-IO
  /// reports a full disk to HDF5 as a short write, without errno ("" if no
  /// watch is active).
  static std::string space_left();

  struct State;  // the thread and what it watches (write_watch.cpp)

 private:
  std::unique_ptr<State> state_;
};

/// Test hook: if the environment variable LEM_FAULT_STALL is part of the
/// name of `file`, the last rank of `comm` prints "test hook: rank R (pid P)
/// stalls in the write of <file>" and waits there for 120 s, deaf to stop
/// requests, as a rank held by a hung filesystem would, while the others go
/// into the write's collective calls (docs/developer/testing.md).
void fault_stall(MPI_Comm comm, const std::string& file);

/// Seconds a collective write may go on after a stop request before the job
/// is ended without it (-output_write_grace of lem_fracture; default 60).
void set_write_stop_grace(double seconds);
double write_stop_grace();

}  // namespace lem
