#include "lem/io/parallel_hdf5.hpp"

#include "lem/base/collective.hpp"
#include "lem/base/error.hpp"
#include "lem/base/files.hpp"
#include "lem/io/write_watch.hpp"

#include <algorithm>
#include <exception>
#include <filesystem>
#include <system_error>

namespace lem {
namespace {

using h5::Handle;

// Datasets of at least this many values are compressed: below it the
// chunk index costs more than deflate saves.
constexpr hsize_t kCompressFrom = 4096;
constexpr hsize_t kChunkRows = 65536;
constexpr unsigned kDeflateLevel = 4;  // most of level 9's gain at a fraction of its time

bool deflate_available() {
  unsigned config = 0;
  return H5Zfilter_avail(H5Z_FILTER_DEFLATE) > 0 &&
         H5Zget_filter_info(H5Z_FILTER_DEFLATE, &config) >= 0 &&
         (config & H5Z_FILTER_CONFIG_ENCODE_ENABLED) != 0;
}

bool compressed(const Slab& slab) {
  static const bool available = deflate_available();
  return available && slab.global_rows * std::max<hsize_t>(slab.columns, 1) >= kCompressFrom;
}

}  // namespace

void collective_hdf5_step(MPI_Comm comm, const std::string& what,
                          const std::function<bool()>& work) {
  try {
    run_collectively(comm, [&] {
      bool ok = false;
      try {
        ok = work();
      } catch (const std::exception&) {
        ok = false;
      }
      if (ok) return;
      std::string why = WriteWatch::first_error();  // MPI-IO's, the most telling
      if (why.empty()) {
        why = h5::error_text();
        why = (why.empty() ? "HDF5 reported an error" : why) + WriteWatch::space_left();
      }
      const std::string message = what + ": " + why;
      // Noted in the write's watch first: the library may hold some rank in
      // its own collective calls from here on (closing the file).
      WriteWatch::note_error(message);
      throw IoError(message);
    });
  } catch (const std::exception& e) {
    WriteWatch::note_error(e.what());
    throw;
  }
}

std::int64_t exclusive_prefix_sum(MPI_Comm comm, std::int64_t local) {
  std::int64_t prefix = 0;
  MPI_Exscan(&local, &prefix, 1, MPI_INT64_T, MPI_SUM, comm);
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  return rank == 0 ? 0 : prefix;  // MPI_Exscan leaves rank 0's result undefined
}

void write_hdf5_into_place(MPI_Comm comm, const std::string& h5_path,
                           const std::function<void(const std::string& temporary)>& write,
                           const std::function<void()>& publish) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  const std::string temporary = h5_path + ".tmp";
  const WriteWatch watch(comm, h5_path, temporary);
  {
    const h5::QuietErrors quiet;
    try {
      write(temporary);
    } catch (...) {
      // Every rank is here (the failure was agreed on) and the file is closed.
      MPI_Barrier(comm);
      std::error_code ec;
      if (rank == 0) std::filesystem::remove(temporary, ec);
      throw;
    }
  }
  MPI_Barrier(comm);  // every rank has closed the file
  run_collectively(comm, [&] {
    if (rank != 0) return;
    move_into_place(temporary, h5_path);
    publish();
  });
}

ParallelHdf5File::ParallelHdf5File(MPI_Comm comm, const std::string& path)
    : comm_(comm), path_(path), label_("'" + path + "'") {
  collective_hdf5_step(comm_, "HDF5: cannot set up parallel file access for " + label_, [&] {
    access_ = Handle(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
    if (!access_.valid()) return false;
    if (H5Pset_fapl_mpio(access_.get(), comm_, MPI_INFO_NULL) < 0) return false;
    // All ranks perform identical metadata operations, so they may write
    // metadata collectively (far fewer small writes at scale).
    return H5Pset_coll_metadata_write(access_.get(), true) >= 0;
  });
  collective_hdf5_step(comm_, "HDF5: cannot create file " + label_, [&] {
    file_ = Handle(H5Fcreate(path_.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access_.get()), H5Fclose);
    if (!file_.valid()) return false;
    transfer_ = Handle(H5Pcreate(H5P_DATASET_XFER), H5Pclose);
    return transfer_.valid() && H5Pset_dxpl_mpio(transfer_.get(), H5FD_MPIO_COLLECTIVE) >= 0;
  });
}

hid_t ParallelHdf5File::group(const std::string& name) {
  collective_hdf5_step(comm_, "HDF5: cannot create group /" + name + " in " + label_, [&] {
    groups_.emplace_back(H5Gcreate2(file_.get(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT,
                                    H5P_DEFAULT),
                         H5Gclose);
    return groups_.back().valid();
  });
  return groups_.back().get();
}

void ParallelHdf5File::dataset(hid_t parent, const std::string& path, const std::string& name,
                               hid_t file_type, hid_t memory_type, const Slab& slab,
                               const void* data) {
  const int rank = slab.columns == 0 ? 1 : 2;
  const hsize_t global_dims[2] = {slab.global_rows, slab.columns};
  Handle file_space;
  Handle memory_space;
  Handle set;
  Handle create_plist;

  collective_hdf5_step(comm_, "HDF5: cannot create dataset " + path + " in " + label_, [&] {
    file_space = Handle(H5Screate_simple(rank, global_dims, nullptr), H5Sclose);
    if (!file_space.valid()) return false;
    create_plist = Handle(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
    if (!create_plist.valid()) return false;
    // Every element is written below, so fill values would be wasted I/O.
    if (H5Pset_fill_time(create_plist.get(), H5D_FILL_TIME_NEVER) < 0) return false;
    if (compressed(slab)) {
      // Parallel HDF5 (1.10.2 on) writes filtered datasets collectively;
      // byte shuffling first makes integers and smooth doubles shrink far more.
      const hsize_t chunk[2] = {std::min<hsize_t>(slab.global_rows, kChunkRows),
                                slab.columns == 0 ? 1 : slab.columns};
      if (H5Pset_chunk(create_plist.get(), rank, chunk) < 0 ||
          H5Pset_shuffle(create_plist.get()) < 0 ||
          H5Pset_deflate(create_plist.get(), kDeflateLevel) < 0)
        return false;
    }
    set = Handle(H5Dcreate2(parent, name.c_str(), file_type, file_space.get(), H5P_DEFAULT,
                            create_plist.get(), H5P_DEFAULT),
                 H5Dclose);
    if (!set.valid()) return false;
    if (slab.local_rows > 0) {
      const hsize_t start[2] = {slab.offset, 0};
      const hsize_t count[2] = {slab.local_rows, slab.columns};
      if (H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start, nullptr, count, nullptr) < 0)
        return false;
      memory_space = Handle(H5Screate_simple(rank, count, nullptr), H5Sclose);
      return memory_space.valid();
    }
    // This rank owns nothing but still takes part in the collective write.
    const hsize_t one[2] = {1, slab.columns == 0 ? 1 : slab.columns};
    memory_space = Handle(H5Screate_simple(rank, one, nullptr), H5Sclose);
    return memory_space.valid() && H5Sselect_none(memory_space.get()) >= 0 &&
           H5Sselect_none(file_space.get()) >= 0;
  });

  if (slab.global_rows > 0) {  // else nothing to write on any rank
    collective_hdf5_step(comm_, "HDF5: cannot write dataset " + path + " in " + label_, [&] {
      const double dummy = 0.0;  // never read: the selection is empty
      const void* buffer = slab.local_rows > 0 ? data : static_cast<const void*>(&dummy);
      return H5Dwrite(set.get(), memory_type, memory_space.get(), file_space.get(), transfer_.get(),
                      buffer) >= 0;
    });
  }
  collective_hdf5_step(comm_, "HDF5: cannot close dataset " + path + " in " + label_,
                       [&] { return set.close(); });
}

void ParallelHdf5File::attribute(const std::string& name,
                                 const std::function<bool(hid_t root)>& write) {
  collective_hdf5_step(comm_, "HDF5: cannot write attribute '" + name + "' in " + label_,
                       [&] { return write(file_.get()); });
}

void ParallelHdf5File::provenance(const Provenance& p) {
  collective_hdf5_step(comm_, "HDF5: cannot write the provenance attributes in " + label_,
                       [&] { return h5::write_provenance_attributes(file_.get(), p); });
}

void ParallelHdf5File::close() {
  collective_hdf5_step(comm_, "HDF5: cannot close " + label_, [&] {
    bool ok = true;
    for (auto& g : groups_) ok = g.close() && ok;
    ok = transfer_.close() && ok;
    ok = file_.close() && ok;
    return access_.close() && ok;
  });
}

}  // namespace lem
