// Result files: written whole or not at all, and a result directory that is
// either complete or visibly not.
//
// Every C++ writer goes through move_into_place: a file is written under a
// temporary name in its own directory, flushed to disk, then renamed over
// the final name, so a killed run leaves either the old file or the new one,
// never half of one.  A run of several files commits them together with a
// manifest (commit_results), written last: a directory without one holds no
// finished result, whatever files it has.  A finished result is replaced
// (lem_fracture -output_overwrite) by a new one computed and committed in a
// sibling folder, then put in its place in one step (install_result).
#pragma once

#include <mpi.h>

#include <cstddef>
#include <cstdint>
#include <functional>
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
/// The same for `size` bytes at `data`.
void write_file_atomically(const std::string& path, const void* data, std::size_t size);

/// Why write_file_atomically(path, ...) would fail ("" if it would not):
/// the temporary <path>.tmp is created and removed.  Lets a program refuse
/// an unwritable output before the work that fills it.
std::string unwritable_file(const std::string& path);

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
/// the directory cannot be created or another run holds the lock.  The lock
/// taken is that of the file at <dir>/.lock once it is held (a lock file
/// swapped away with its folder by install_result meanwhile is let go and
/// the new one taken).
class OutputLock {
 public:
  OutputLock(MPI_Comm comm, const std::string& dir);
  ~OutputLock();
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

 private:
  int fd_ = -1;
};

/// What `path` is when it is neither a regular file nor missing: "a pipe
/// (FIFO)", "a character device", "a block device", "a socket", "a
/// directory"; "" for a regular file (through symbolic links) or no file.
/// Only stat(2) is called: an input that is not a regular file (a pipe
/// waits for a writer, /dev/zero never ends) is refused before it is opened.
std::string not_a_regular_file(const std::string& path);

/// CRC-32 (IEEE 802.3, as zlib.crc32 and `gzip`) of `n` bytes, continuing
/// from `crc` (0 to start).
std::uint32_t crc32(const void* data, std::size_t n, std::uint32_t crc = 0);

/// The checksum of a file's content, "crc32:<8 hex digits>"; IoError naming
/// the file if it cannot be read.
std::string file_checksum(const std::string& path);
/// crc32() of the first `bytes` bytes of a file (fewer if it is shorter);
/// IoError naming the file if it cannot be read.
std::uint32_t file_prefix_crc32(const std::string& path, std::uint64_t bytes);
/// A CRC-32 as file_checksum writes it.
std::string crc32_text(std::uint32_t crc);

/// The commit record of a finished result: <dir>/manifest.txt lists the
/// program, a fingerprint of what was computed and every result file with
/// its size in bytes and the checksum of its content.
struct Manifest {
  std::string program;
  std::string fingerprint;  // lines "key=value"
  std::vector<std::pair<std::string, std::int64_t>> files;
  /// file_checksum of each listed file, by name (none in a manifest
  /// written before checksums: its files are checked by size only).
  std::vector<std::pair<std::string, std::string>> checksums;
  /// Codes of the degradations the result carries ("code:count"; none for
  /// a sound run or a manifest written before they were listed).
  std::vector<std::string> warnings;
};

/// Rank 0: whether `dir` has a manifest (damaged or not).
bool has_manifest(const std::string& dir);

/// Rank 0: the manifest of `dir`, or nothing if there is none.  InputError
/// if it is damaged.
std::optional<Manifest> read_manifest(const std::string& dir);

/// Rank 0: why the files listed by `m` are not those it committed (missing,
/// of another size, or of other content than its checksum), empty if they
/// are.
std::string manifest_mismatch(const std::string& dir, const Manifest& m);

/// Rank 0: commit the complete result `files` of `dir` (which must exist),
/// with the `warnings` it carries: each file is synced, then the manifest is
/// written atomically, last.
void commit_results(const std::string& dir, const std::string& program,
                    const std::string& fingerprint, const std::vector<std::string>& files,
                    const std::vector<std::string>& warnings = {});

/// Rank 0: withdraw the result of `dir`: the manifest is removed first (and
/// the removal synced), then `files`.
void withdraw_results(const std::string& dir, const std::vector<std::string>& files);

// ---- Replacing a finished result (lem_fracture -output_overwrite) ----------
// The new run works in the staging folder "<dir>.overwrite" (same parent,
// so the same filesystem), stamped as such and locked like `dir`, and
// commits its result there; install_result then swaps the two folders in
// one rename (renameat2 RENAME_EXCHANGE) and removes the old one, so that
// at every instant `dir` holds the old complete result or the new one.  A
// filesystem without that rename (NFS) gets two renames instead, with a
// moment in which `dir` does not exist.  Whatever a kill interrupts,
// finish_replacement completes it in the next run on `dir`.

/// "<dir>.overwrite" (`dir` without trailing slashes).
std::string staging_dir(const std::string& dir);

/// Rank 0: what is at staging_dir(dir): nothing, a staging folder of ours
/// (stamped, a replaced result, or a bare folder with only a lock), or
/// something else (`foreign`: never touched).
enum class StagingState { none, ours, foreign };
StagingState staging_state(const std::string& dir);

/// Rank 0: InputError unless `dir` can be replaced by a rename of its
/// sibling: not a symbolic link, '.' or '..', nor a mount point.
void check_replaceable(const std::string& dir);

/// Names of the entries a result folder's program writes or draws from its
/// result (curve.csv, calibration, fracture.png, ...).  When a folder is
/// replaced, its other entries (a study's run.json and log) move into the
/// new one unless it has its own.
using ResultNames = std::function<bool(const std::string& name)>;

/// Rank 0, `dir` and its staging folder (if ours) locked: finish a
/// replacement stopped halfway (two renames cut between them: the new
/// folder put in place; a replaced folder still there, aside in `dir` or as
/// the staging folder: removed).  Returns what it did for the log, "" if
/// nothing.
std::string finish_replacement(const std::string& dir, const ResultNames& own);

/// Rank 0, the staging folder of `dir` created and locked: checks it is on
/// the filesystem of `dir` (else InputError), stamps it, and returns whether
/// that filesystem swaps two folders in one rename (false on EINVAL, ENOSYS
/// or EOPNOTSUPP, or if LEM_FAULT_NO_EXCHANGE is set: a test hook).
bool prepare_staging(const std::string& dir);

/// Rank 0: empty the staging folder of `dir` but its lock and stamp; false
/// if there was nothing to remove.
bool clear_staging(const std::string& dir);

/// Rank 0: put the result committed in the staging folder of `dir` in place
/// of the one in `dir` (`exchange`: in one rename, else two), then remove
/// the old folder (its manifest first), keeping its entries that are not
/// `own` in `dir`.  The staging folder is gone afterwards.
void install_result(const std::string& dir, bool exchange, const ResultNames& own);

/// Test hook: if the environment variable LEM_FAULT_KILL names `point`, the
/// process kills itself with SIGKILL there, as a batch system's kill -9
/// would (tests of the commit windows; docs/developer/testing.md).
void fault_point(const char* point);

}  // namespace lem
