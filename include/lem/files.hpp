// Result files: written whole or not at all, in an output directory cleared
// of an earlier run's results.
#pragma once

#include <mpi.h>

#include <string>
#include <vector>

namespace lem {

/// Write `path` from text held on rank 0 only: via a temporary file and an
/// atomic rename, so a killed run leaves no half-written result.
void write_text_file_atomically(const std::string& path, const std::string& text);

/// Create `dir` (rank 0) and remove results of an earlier run in it, so that
/// a failed run cannot leave an older summary looking like its own.
void prepare_output_dir(MPI_Comm comm, const std::string& dir,
                        const std::vector<std::string>& result_files);

}  // namespace lem
