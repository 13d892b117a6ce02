// The life of a result folder (docs/reference/result-folder.md, "manifest.txt
// and the commit"), in one place for the programs that write one:
//
//   open      lock the folder; finish a replacement stopped halfway; decide
//             whether the finished result of this very run is already there
//             (nothing to do), whether a complete replacement waits in the
//             staging folder (put it in place), or where to compute: the
//             folder itself, or <dir>.overwrite under -output_overwrite;
//   withdraw  what an earlier run left (manifest first), keeping the logs
//             and fields of a run that resumes from its checkpoint;
//   commit    the summary, then every result file synced, then the
//             manifest, then the checkpoint goes;
//   install   a staged result takes the old one's place in one rename.
//
// The names of the files a program writes are given once, in its
// ResultLayout: the withdrawal, the commit, and what a replacement carries
// over all derive from it.
#pragma once

#include "lem/base/summary.hpp"

#include <mpi.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace lem {

class OptionGroup;
class OutputLock;

/// What a program writes in its result folder.
struct ResultLayout {
  std::string program;
  /// Files every finished result has, first in its manifest, in this order.
  std::vector<std::string> required;
  /// Files committed when present.  A run that resumes from a checkpoint
  /// keeps them (they are its logs so far); any other run withdraws them.
  std::vector<std::string> optional;
  /// Families of field files by stem: "fields" is fields.h5, fields.xmf,
  /// fields_nodes.xmf; "snapshot" is snapshot_<step>.h5/.xmf.  `final_families` are written at the end of a run
  /// (withdrawn before every run); the others before its first checkpoint
  /// or during it (kept when it resumes).
  std::vector<std::string> final_families;
  std::vector<std::string> running_families;
  /// Entries that belong to the result without being committed: plots that
  /// the tools draw from it, sub-folders of the run, its checkpoint.
  std::vector<std::string> extras;

  /// Whether `name` is an entry of this program's result (also a file it is
  /// writing under a temporary name).  Entries that are not (a study's
  /// run.json and log) are never removed and move into a replacement.
  bool owns(const std::string& name) const;
};

/// lem_fracture's folder: curve, ruptures, summary, fields, snapshots, the
/// calibration sub-folder, its checkpoint and the plots of its tools.
const ResultLayout& fracture_layout();
/// lem_tension: summary and fields.  lem_stiffness, lem_convergence: their
/// tables and summary.  lem_pack: the packing (and the whole box).
const ResultLayout& tension_layout();
const ResultLayout& stiffness_layout();
const ResultLayout& convergence_layout();
const ResultLayout& packing_layout();

/// The fingerprint of a run that is its options (lem/base/fingerprint.hpp:
/// every option the program read, given or default, but those that only say
/// where and how the run is kept), then `inputs`, lines that identify the
/// input by content (e.g. lattice_fingerprint of protocol/fingerprint.hpp).
/// Call it once every option is read.  Collective; the text is made on rank
/// 0 (the folder's work is done there), "" elsewhere.
std::string options_fingerprint(MPI_Comm comm, const std::string& inputs = "");

/// A result folder opened by a run.  Collective: every method is called on
/// every rank; rank 0 does the file work and every rank gets its answers.
class ResultFolder {
 public:
  struct Request {
    std::string dir;  // -output_dir
    /// What the result depends on (manifest's fingerprint, "key=value" lines).
    std::string fingerprint;
    bool overwrite = false;  // -output_overwrite
    bool resume = true;      // -checkpoint_resume
    /// A finished result with warnings is an error (-fracture_strict).
    bool strict = false;
  };

  ResultFolder(MPI_Comm comm, const ResultLayout& layout, Request request);
  /// The options every program that writes a folder reads, in `group`:
  /// -output_dir (default `default_dir`) and -output_overwrite.
  static Request read_request(OptionGroup& group, const char* default_dir);
  ~ResultFolder();
  ResultFolder(const ResultFolder&) = delete;
  ResultFolder& operator=(const ResultFolder&) = delete;

  /// Where the run computes and writes: the folder, or its staging folder.
  const std::string& work_dir() const { return work_; }
  /// Whether a checkpoint in work_dir() will be resumed.
  bool resuming() const;

  /// Whether there is a result to compute: false when the finished result
  /// is there or a staged one was put in place (install()); else the
  /// result an earlier run left in work_dir() is withdrawn (the manifest
  /// first), keeping what a resumed run goes on from.
  bool begin() const;
  /// Write `summary` as summary.json/.csv (if the layout has them), commit
  /// every result file present with `warnings` (codes of a degraded result,
  /// for a later -fracture_strict), then remove the checkpoint.
  void commit(const Summary& summary, const std::vector<std::string>& warnings) const;
  /// Put a staged result in place of the old one, say where the result is,
  /// and stop (Interrupted) if a stop request came while it was written.
  void install() const;

 private:
  MPI_Comm comm_;
  const ResultLayout& layout_;
  Request request_;
  std::unique_ptr<OutputLock> lock_, staging_lock_;
  std::string work_;
  bool finished_ = false, pending_ = false, staging_ = false, exchange_ = false;
};

}  // namespace lem
