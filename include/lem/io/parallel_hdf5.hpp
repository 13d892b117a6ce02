// One HDF5 file written by every rank of a communicator through MPI-IO, each
// rank its own rows of every dataset (the lattice fields and the sample
// files built in parallel).  Every step is collective and agreed on: a
// failure on some ranks makes every rank throw the same IoError, naming the
// step and, when MPI-IO or the disk said why, that reason (WriteWatch).
#pragma once

#include "lem/io/hdf5_util.hpp"
#include "lem/base/provenance.hpp"

#include <hdf5.h>
#include <mpi.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace lem {

/// Rows [offset, offset + local_rows) of a (global_rows x columns) dataset;
/// columns == 0 means a 1-D dataset.
struct Slab {
  hsize_t global_rows = 0;
  hsize_t offset = 0;
  hsize_t local_rows = 0;
  hsize_t columns = 0;

  Slab with_columns(hsize_t c) const {
    Slab s = *this;
    s.columns = c;
    return s;
  }
};

/// Run `work` on every rank; if it fails (returns false or throws) anywhere,
/// every rank throws IoError("<what>: <why>") of the lowest failing rank.
void collective_hdf5_step(MPI_Comm comm, const std::string& what,
                          const std::function<bool()>& work);

/// Sum of `local` over the ranks below this one (0 on rank 0).
std::int64_t exclusive_prefix_sum(MPI_Comm comm, std::int64_t local);

/// Collective: <h5_path> made by `write(temporary)` under the name
/// <h5_path>.tmp (watched by a WriteWatch, HDF5's own error printing off),
/// removed if any rank fails; then rank 0 moves it into place and runs
/// `publish` (e.g. the XDMF documents beside it).  Every rank throws the
/// same error.
void write_hdf5_into_place(MPI_Comm comm, const std::string& h5_path,
                           const std::function<void(const std::string& temporary)>& write,
                           const std::function<void()>& publish);

class ParallelHdf5File {
 public:
  /// Collective: create (truncate) `path` (named in every error).
  ParallelHdf5File(MPI_Comm comm, const std::string& path);
  ParallelHdf5File(const ParallelHdf5File&) = delete;
  ParallelHdf5File& operator=(const ParallelHdf5File&) = delete;

  hid_t root() const { return file_.get(); }
  /// Collective: a group of the root, open until close().
  hid_t group(const std::string& name);
  /// Collective: create `path` (in `parent`, named `name`) and write this
  /// rank's rows.  Large datasets are chunked and compressed.
  void dataset(hid_t parent, const std::string& path, const std::string& name, hid_t file_type,
               hid_t memory_type, const Slab& slab, const void* data);
  /// Collective, with the same value on every rank.
  void attribute(const std::string& name, const std::function<bool(hid_t root)>& write);
  void provenance(const Provenance& p);
  /// Collective: close the groups and the file.
  void close();

 private:
  MPI_Comm comm_;
  std::string path_, label_;
  h5::Handle access_, file_, transfer_;
  std::vector<h5::Handle> groups_;
};

}  // namespace lem
