// Result files: written whole or not at all, and a result directory that is
// either complete or visibly not.
//
// Every C++ writer goes through move_into_place: a file is written under a
// temporary name in its own directory, flushed to disk, then renamed over
// the final name, so a killed run leaves either the old file or the new one,
// never half of one.  A run of several files commits them together with a
// manifest (commit_results), written last: a directory without one holds no
// finished result, whatever files it has.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace lem {

/// Write `path` from text held on rank 0 only: `text` goes to <path>.tmp,
/// every write and the close are checked, the data are synced, and the file
/// is renamed onto `path`.  Throws IoError naming `path` on any failure
/// (and removes the temporary file).
void write_text_file_atomically(const std::string& path, const std::string& text);

/// Publish a complete file written under a temporary name `from` (in the
/// same directory as `to`): sync it, rename it onto `to`, sync the directory.
/// Throws IoError naming both files on failure (`from` is removed).
void move_into_place(const std::string& from, const std::string& to);

/// fsync a directory (after renames or removals in it); IoError on failure.
void sync_directory(const std::string& dir);

/// Create `dir` (rank 0) and remove results of an earlier run in it, so that
/// a failed run cannot leave an older summary looking like its own.  Call it
/// only once the input has been checked.
void prepare_output_dir(MPI_Comm comm, const std::string& dir,
                        const std::vector<std::string>& result_files);

/// An exclusive advisory lock (flock) on <dir>/.lock, held by rank 0 for
/// the object's lifetime (the kernel drops it when the process dies, even
/// by kill -9).  Creates `dir`.  Collective: every rank throws InputError if
/// the directory cannot be created or another run holds the lock.
class OutputLock {
 public:
  OutputLock(MPI_Comm comm, const std::string& dir);
  ~OutputLock();
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

 private:
  int fd_ = -1;
};

/// The commit record of a finished result: <dir>/manifest.txt lists the
/// program, a fingerprint of what was computed and every result file with
/// its size in bytes.
struct Manifest {
  std::string program;
  std::string fingerprint;  // lines "key=value"
  std::vector<std::pair<std::string, std::int64_t>> files;
};

/// Rank 0: the manifest of `dir`, or nothing if there is none.  InputError
/// if it is damaged.
std::optional<Manifest> read_manifest(const std::string& dir);

/// Rank 0: why the files listed by `m` are not those it committed (missing
/// or of another size), empty if they are.
std::string manifest_mismatch(const std::string& dir, const Manifest& m);

/// Rank 0: commit the complete result `files` of `dir` (which must exist):
/// each is synced, then the manifest is written atomically, last.
void commit_results(const std::string& dir, const std::string& program,
                    const std::string& fingerprint, const std::vector<std::string>& files);

/// Rank 0: withdraw the result of `dir`: the manifest is removed first (and
/// the removal synced), then `files`.
void withdraw_results(const std::string& dir, const std::vector<std::string>& files);

/// Test hook: if the environment variable LEM_FAULT_KILL names `point`, the
/// process kills itself with SIGKILL there, as a batch system's kill -9
/// would (tests of the commit windows; docs/testing.md).
void fault_point(const char* point);

}  // namespace lem
