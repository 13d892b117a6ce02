// Result files: written whole or not at all, in an output directory cleared
// of an earlier run's results.
//
// Every C++ writer goes through move_into_place: a file is written under a
// temporary name in its own directory, flushed to disk, then renamed over
// the final name, so a killed run leaves either the old file or the new one,
// never half of one.
#pragma once

#include <mpi.h>

#include <string>
#include <vector>

namespace lem {

/// Write `path` from text held on rank 0 only: `text` goes to <path>.tmp,
/// every write and the close are checked, the data are synced, and the file
/// is renamed onto `path`.  Throws InputError naming `path` on any failure
/// (and removes the temporary file).
void write_text_file_atomically(const std::string& path, const std::string& text);

/// Publish a complete file written under a temporary name `from` (in the
/// same directory as `to`): sync it, rename it onto `to`, sync the directory.
/// Throws InputError naming both files on failure (`from` is removed).
void move_into_place(const std::string& from, const std::string& to);

/// Create `dir` (rank 0) and remove results of an earlier run in it, so that
/// a failed run cannot leave an older summary looking like its own.
void prepare_output_dir(MPI_Comm comm, const std::string& dir,
                        const std::vector<std::string>& result_files);

}  // namespace lem
