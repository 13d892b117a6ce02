// Parallel HDF5 output of lattice fields and their one-grid XDMF documents
// (see lem/hdf5_writer.hpp; the attribute helpers and the XDMF text are in
// hdf5_util.cpp).
//
// Every failure that can happen on a subset of ranks is agreed on with an
// MPI reduction before anybody throws, so that all ranks throw the same
// exception together instead of some of them waiting forever in a collective.
#include "lem/hdf5_writer.hpp"

#include <hdf5.h>
#include <petscsys.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <climits>
#include <ctime>
#include <exception>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <utility>

#include "lem/collective.hpp"
#include "lem/error.hpp"
#include "lem/files.hpp"
#include "lem/hdf5_util.hpp"
#include "lem/options.hpp"
#include "lem/write_watch.hpp"

namespace lem {
namespace {

using h5::Handle;

namespace fs = std::filesystem;

static_assert(sizeof(std::array<double, 3>) == 3 * sizeof(double),
              "node coordinates must be stored contiguously");
static_assert(sizeof(std::array<std::int64_t, 2>) == 2 * sizeof(std::int64_t),
              "bond ends must be stored contiguously");

// ---------------------------------------------------------------------------
// MPI helpers
// ---------------------------------------------------------------------------

int comm_rank(MPI_Comm comm) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  return rank;
}

/// Sum of `local` over the ranks below this one (0 on rank 0).
std::int64_t exclusive_prefix_sum(MPI_Comm comm, std::int64_t local) {
  std::int64_t prefix = 0;
  MPI_Exscan(&local, &prefix, 1, MPI_INT64_T, MPI_SUM, comm);
  if (comm_rank(comm) == 0) prefix = 0;  // MPI_Exscan leaves rank 0's result undefined
  return prefix;
}

// ---------------------------------------------------------------------------
// Collective errors
// ---------------------------------------------------------------------------

/// The first error this rank found, agreed on with the other ranks by
/// raise_collectively before anybody throws.
struct LocalError {
  std::exception_ptr first;

  template <class Error>
  void set(Error error) {
    if (!first) first = std::make_exception_ptr(std::move(error));
  }
};

/// If any rank holds an error, every rank throws the error of the lowest such rank.
void raise_collectively(MPI_Comm comm, const LocalError& error) { agree_on_error(comm, error.first); }

/// Run `work` on every rank; if it fails (returns false or throws) anywhere,
/// every rank throws IoError("<what>: <why>") of the lowest failing rank.
/// The failure is noted in the write's watch first: the library may hold
/// some rank in its own collective calls from here on (closing the file).
void collective_step(MPI_Comm comm, const std::string& what, const std::function<bool()>& work) {
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
      WriteWatch::note_error(message);
      throw IoError(message);
    });
  } catch (const std::exception& e) {
    WriteWatch::note_error(e.what());
    throw;
  }
}

// ---------------------------------------------------------------------------
// Input validation
// ---------------------------------------------------------------------------

struct FieldInfo {
  std::string name;
  int components = 1;
  bool integer = false;
};

std::vector<FieldInfo> field_infos(const std::vector<Field>& fields) {
  std::vector<FieldInfo> infos;
  infos.reserve(fields.size());
  for (const Field& f : fields) infos.push_back({f.name, f.components, f.integer});
  return infos;
}

/// Serialised field layout, compared between ranks.
std::string schema_text(const std::vector<FieldInfo>& nodes, const std::vector<FieldInfo>& bonds) {
  std::ostringstream out;
  for (const auto& f : nodes) out << "node " << f.components << f.integer << ' ' << f.name << '\n';
  for (const auto& f : bonds) out << "bond " << f.components << f.integer << ' ' << f.name << '\n';
  return out.str();
}

void check_fields(const std::vector<Field>& fields, std::size_t items, const char* group,
                  const std::set<std::string>& reserved, int rank, LocalError& error) {
  std::set<std::string> seen;
  for (const Field& f : fields) {
    const std::string where = std::string("/") + group + "/" + f.name;
    if (f.name.empty() || f.name == "." || f.name == ".." ||
        f.name.find_first_of("/\n") != std::string::npos) {
      error.set(std::invalid_argument(
                std::string("write_lattice_fields: invalid ") + group + " field name '" + f.name +
                    "' (must be non-empty and contain no '/')"));
    } else if (reserved.count(f.name) != 0) {
      error.set(std::invalid_argument(
                "write_lattice_fields: field name '" + f.name + "' is reserved in /" + group));
    } else if (!seen.insert(f.name).second) {
      error.set(std::invalid_argument(
                "write_lattice_fields: duplicate field " + where));
    } else if (f.components != 1 && f.components != 3 && f.components != 6) {
      error.set(std::invalid_argument(
                "write_lattice_fields: field " + where + " has " + std::to_string(f.components) +
                    " components (allowed: 1, 3 or 6)"));
    } else if (f.values.size() != items * static_cast<std::size_t>(f.components)) {
      error.set(std::invalid_argument(
                "write_lattice_fields: field " + where + " has " + std::to_string(f.values.size()) +
                    " values on rank " + std::to_string(rank) + ", expected " +
                    std::to_string(items) + " items x " + std::to_string(f.components) +
                    " components"));
    }
  }
}

// ---------------------------------------------------------------------------
// HDF5 writing
// ---------------------------------------------------------------------------

/// Describes one dataset slice: rows [offset, offset + local_rows) of a
/// (global_rows x columns) array; columns == 0 means a 1-D dataset.
struct Slab {
  hsize_t global_rows = 0;
  hsize_t offset = 0;
  hsize_t local_rows = 0;
  hsize_t columns = 0;
};

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

/// Collective: create `group/name` and write this rank's rows into it.
void write_dataset(MPI_Comm comm, hid_t group, const std::string& path, const std::string& name,
                   hid_t file_type, hid_t memory_type, const Slab& slab, const void* data,
                   hid_t transfer, const std::string& file_name) {
  const int rank = slab.columns == 0 ? 1 : 2;
  const hsize_t global_dims[2] = {slab.global_rows, slab.columns};
  Handle file_space;
  Handle memory_space;
  Handle dataset;
  Handle create_plist;

  collective_step(comm, "HDF5: cannot create dataset " + path + " in '" + file_name + "'", [&] {
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
    dataset = Handle(H5Dcreate2(group, name.c_str(), file_type, file_space.get(), H5P_DEFAULT,
                                create_plist.get(), H5P_DEFAULT),
                     H5Dclose);
    if (!dataset.valid()) return false;
    if (slab.local_rows > 0) {
      const hsize_t start[2] = {slab.offset, 0};
      const hsize_t count[2] = {slab.local_rows, slab.columns};
      if (H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start, nullptr, count, nullptr) < 0)
        return false;
      memory_space = Handle(H5Screate_simple(rank, count, nullptr), H5Sclose);
      if (!memory_space.valid()) return false;
    } else {
      // This rank owns nothing but still takes part in the collective write.
      const hsize_t one[2] = {1, slab.columns == 0 ? 1 : slab.columns};
      memory_space = Handle(H5Screate_simple(rank, one, nullptr), H5Sclose);
      if (!memory_space.valid()) return false;
      if (H5Sselect_none(memory_space.get()) < 0) return false;
      if (H5Sselect_none(file_space.get()) < 0) return false;
    }
    return true;
  });

  if (slab.global_rows == 0) return;  // nothing to write on any rank

  collective_step(comm, "HDF5: cannot write dataset " + path + " in '" + file_name + "'", [&] {
    const double dummy = 0.0;  // never read: the selection is empty
    const void* buffer = slab.local_rows > 0 ? data : static_cast<const void*>(&dummy);
    return H5Dwrite(dataset.get(), memory_type, memory_space.get(), file_space.get(), transfer,
                    buffer) >= 0;
  });
  collective_step(comm, "HDF5: cannot close dataset " + path + " in '" + file_name + "'",
                  [&] { return dataset.close(); });
}

struct GlobalLayout {
  std::int64_t nodes = 0;        // global node count
  std::int64_t node_offset = 0;  // first node row of this rank
  std::int64_t bonds = 0;
  std::int64_t bond_offset = 0;
};

/// Collective: write the whole HDF5 file under `path` (the temporary name).
void write_hdf5(MPI_Comm comm, const std::string& path, const NodeSlice& nodes,
                const BondSlice& bonds, const GlobalLayout& layout, const Provenance& provenance,
                const std::vector<std::pair<std::string, double>>& scalars) {
  const auto h = [](std::int64_t v) { return static_cast<hsize_t>(v); };
  const std::string label = "'" + path + "'";

  Handle access;
  Handle file;
  collective_step(comm, "HDF5: cannot set up parallel file access for " + label, [&] {
    access = Handle(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
    if (!access.valid()) return false;
    if (H5Pset_fapl_mpio(access.get(), comm, MPI_INFO_NULL) < 0) return false;
    // All ranks perform identical metadata operations, so they may write
    // metadata collectively (far fewer small writes at scale).
    return H5Pset_coll_metadata_write(access.get(), true) >= 0;
  });
  collective_step(comm, "HDF5: cannot create file " + label, [&] {
    file = Handle(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access.get()), H5Fclose);
    return file.valid();
  });

  Handle transfer;
  Handle node_group;
  Handle bond_group;
  collective_step(comm, "HDF5: cannot create groups /nodes and /bonds in " + label, [&] {
    transfer = Handle(H5Pcreate(H5P_DATASET_XFER), H5Pclose);
    if (!transfer.valid()) return false;
    if (H5Pset_dxpl_mpio(transfer.get(), H5FD_MPIO_COLLECTIVE) < 0) return false;
    node_group = Handle(H5Gcreate2(file.get(), "nodes", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
    bond_group = Handle(H5Gcreate2(file.get(), "bonds", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
    return node_group.valid() && bond_group.valid();
  });

  fault_stall(comm, path);
  const hsize_t local_nodes = static_cast<hsize_t>(nodes.coords.size());
  const hsize_t local_bonds = static_cast<hsize_t>(bonds.ends.size());
  const Slab node_rows{h(layout.nodes), h(layout.node_offset), local_nodes, 0};
  const Slab bond_rows{h(layout.bonds), h(layout.bond_offset), local_bonds, 0};
  const auto with_columns = [](Slab s, hsize_t columns) {
    s.columns = columns;
    return s;
  };

  write_dataset(comm, node_group.get(), "/nodes/coordinates", "coordinates", H5T_IEEE_F64LE,
                H5T_NATIVE_DOUBLE, with_columns(node_rows, 3), nodes.coords.data(), transfer.get(),
                path);
  write_dataset(comm, node_group.get(), "/nodes/id", "id", H5T_STD_I64LE, H5T_NATIVE_INT64,
                node_rows, nodes.ids.data(), transfer.get(), path);
  const std::vector<std::int64_t> vertices =
      h5::XdmfText::vertex_rows(layout.node_offset, static_cast<std::int64_t>(local_nodes));
  write_dataset(comm, node_group.get(), "/nodes/vertices", "vertices", H5T_STD_I64LE,
                H5T_NATIVE_INT64, with_columns(node_rows, 1), vertices.data(), transfer.get(),
                path);
  const auto write_field = [&](hid_t group, const char* group_name, const Field& f,
                               const Slab& rows) {
    const Slab slab = f.components == 1 ? rows : with_columns(rows, f.components);
    const std::string dataset = std::string("/") + group_name + "/" + f.name;
    if (!f.integer) {
      write_dataset(comm, group, dataset, f.name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, slab,
                    f.values.data(), transfer.get(), path);
      return;
    }
    const std::vector<std::int32_t> whole(f.values.begin(), f.values.end());
    write_dataset(comm, group, dataset, f.name, H5T_STD_I32LE, H5T_NATIVE_INT32, slab,
                  whole.data(), transfer.get(), path);
  };
  for (const Field& f : nodes.fields) write_field(node_group.get(), "nodes", f, node_rows);
  write_dataset(comm, bond_group.get(), "/bonds/connectivity", "connectivity", H5T_STD_I64LE,
                H5T_NATIVE_INT64, with_columns(bond_rows, 2), bonds.ends.data(), transfer.get(),
                path);
  write_dataset(comm, bond_group.get(), "/bonds/id", "id", H5T_STD_I64LE, H5T_NATIVE_INT64,
                bond_rows, bonds.ids.data(), transfer.get(), path);
  for (const Field& f : bonds.fields) write_field(bond_group.get(), "bonds", f, bond_rows);

  // Root attributes (identical on every rank: the caller broadcast them).
  const hid_t root = file.get();
  collective_step(comm, "HDF5: cannot write the provenance attributes in " + label,
                  [&] { return h5::write_provenance_attributes(root, provenance); });
  for (const auto& scalar : scalars) {
    collective_step(comm, "HDF5: cannot write attribute '" + scalar.first + "' in " + label, [&] {
      return h5::write_numeric_attribute(root, scalar.first, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE,
                                     &scalar.second);
    });
  }

  collective_step(comm, "HDF5: cannot close " + label, [&] {
    bool ok = node_group.close();
    ok = bond_group.close() && ok;
    ok = transfer.close() && ok;
    ok = file.close() && ok;
    ok = access.close() && ok;
    return ok;
  });
}

// ---------------------------------------------------------------------------
// XDMF
// ---------------------------------------------------------------------------

h5::XdmfArray xdmf_array(const std::string& group, const FieldInfo& f) {
  return f.integer ? h5::XdmfArray{f.name, "/" + group + "/" + f.name, f.components, "Int", 4}
                   : h5::XdmfArray{f.name, "/" + group + "/" + f.name, f.components, "Float", 8};
}

/// <stem>.xmf: the bonds, with the node fields on their ends.
std::string bonds_xdmf(const std::string& h5_name, const GlobalLayout& layout,
                       const std::vector<FieldInfo>& node_fields,
                       const std::vector<FieldInfo>& bond_fields) {
  h5::XdmfText x(h5_name);
  x.begin_polylines("bonds", layout.bonds, "/bonds/connectivity", layout.nodes,
                    "/nodes/coordinates");
  x.attribute({"node_id", "/nodes/id", 1, "Int", 8}, "Node", layout.nodes);
  for (const auto& f : node_fields) x.attribute(xdmf_array("nodes", f), "Node", layout.nodes);
  x.attribute({"id", "/bonds/id", 1, "Int", 8}, "Cell", layout.bonds);
  for (const auto& f : bond_fields) x.attribute(xdmf_array("bonds", f), "Cell", layout.bonds);
  x.end_grid();
  return x.text();
}

/// <stem>_nodes.xmf: the nodes as vertices.
std::string nodes_xdmf(const std::string& h5_name, const GlobalLayout& layout,
                       const std::vector<FieldInfo>& node_fields) {
  h5::XdmfText x(h5_name);
  x.begin_points("nodes", layout.nodes, "/nodes/coordinates", "/nodes/vertices");
  x.attribute({"id", "/nodes/id", 1, "Int", 8}, "Node", layout.nodes);
  for (const auto& f : node_fields) x.attribute(xdmf_array("nodes", f), "Node", layout.nodes);
  x.end_grid();
  return x.text();
}

// ---------------------------------------------------------------------------
// Misc
// ---------------------------------------------------------------------------

/// Rank 0: can `path` be created?  Returns an empty string if yes, else why not.
std::string probe_writable(const std::string& path) {
  const fs::path p(path);
  const fs::path dir = p.parent_path().empty() ? fs::path(".") : p.parent_path();
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    return "directory '" + dir.string() + "' does not exist or is not a directory";
  {
    std::ofstream probe(path, std::ios::binary | std::ios::trunc);
    if (!probe) return "cannot create files in directory '" + dir.string() + "'";
  }
  fs::remove(p, ec);
  return {};
}

}  // namespace

// ---------------------------------------------------------------------------
// Public interface
// ---------------------------------------------------------------------------

void write_lattice_fields(MPI_Comm comm, const std::string& stem, const NodeSlice& nodes,
                          const BondSlice& bonds, const Provenance& provenance,
                          const std::vector<std::pair<std::string, double>>& scalars) {
  const int rank = comm_rank(comm);

  // 1. Local consistency of the slices, agreed on by all ranks.
  LocalError error;
  const std::size_t local_nodes = nodes.coords.size();
  const std::size_t local_bonds = bonds.ends.size();
  if (nodes.ids.size() != local_nodes)
    error.set(std::invalid_argument(
              "write_lattice_fields: rank " + std::to_string(rank) + " has " +
                  std::to_string(local_nodes) + " node coordinates but " +
                  std::to_string(nodes.ids.size()) + " node ids"));
  if (bonds.ids.size() != local_bonds)
    error.set(std::invalid_argument(
              "write_lattice_fields: rank " + std::to_string(rank) + " has " +
                  std::to_string(local_bonds) + " bonds but " + std::to_string(bonds.ids.size()) +
                  " bond ids"));
  check_fields(nodes.fields, local_nodes, "nodes", {"coordinates", "id", "vertices"}, rank, error);
  check_fields(bonds.fields, local_bonds, "bonds", {"connectivity", "id"}, rank, error);
  raise_collectively(comm, error);

  // 2. Every rank must write the same set of datasets.
  const std::vector<FieldInfo> node_fields = field_infos(nodes.fields);
  const std::vector<FieldInfo> bond_fields = field_infos(bonds.fields);
  {
    const std::string mine = schema_text(node_fields, bond_fields);
    const std::string root = broadcast_string(comm, mine, 0);
    if (mine != root)
      error.set(std::invalid_argument(
                "write_lattice_fields: rank " + std::to_string(rank) +
                    " passes different fields (names/components/order) than rank 0"));
    raise_collectively(comm, error);
  }

  // 3. Attributes: rank 0's provenance and scalars are written by everyone.
  Provenance prov;
  prov.program = broadcast_string(comm, provenance.program, 0);
  prov.version = broadcast_string(comm, provenance.version, 0);
  prov.git_hash = broadcast_string(comm, provenance.git_hash, 0);
  prov.options = broadcast_string(comm, provenance.options, 0);
  prov.start_time = broadcast_string(comm, provenance.start_time, 0);
  prov.ranks = provenance.ranks;
  MPI_Bcast(&prov.ranks, 1, MPI_INT, 0, comm);
  std::vector<std::pair<std::string, double>> root_scalars;
  {
    std::int64_t count = static_cast<std::int64_t>(scalars.size());
    MPI_Bcast(&count, 1, MPI_INT64_T, 0, comm);
    std::vector<double> values(static_cast<std::size_t>(count));
    if (rank == 0)
      for (std::size_t i = 0; i < scalars.size(); ++i) values[i] = scalars[i].second;
    broadcast_bytes(comm, values.data(), values.size() * sizeof(double), 0);
    std::set<std::string> names(std::begin(h5::kProvenanceNames), std::end(h5::kProvenanceNames));
    for (std::size_t i = 0; i < values.size(); ++i) {
      std::string name = broadcast_string(comm, rank == 0 ? scalars[i].first : std::string(), 0);
      if (name.empty() || !names.insert(name).second)
        error.set(std::invalid_argument(
                  "write_lattice_fields: scalar name '" + name +
                      "' is empty, duplicated or reserved for provenance"));
      root_scalars.emplace_back(std::move(name), values[i]);
    }
    raise_collectively(comm, error);  // identical on all ranks: no rank is left behind
  }

  // 4. Output paths: decided on rank 0 and shared, so a bad path fails everywhere.
  if (stem.empty() || fs::path(stem).filename().empty()) {
    throw InputError("write_lattice_fields: output stem '" + stem +
                     "' must name a file (e.g. out/result), not be empty or end in '/'");
  }
  const std::string h5_path = stem + ".h5";
  const std::string tmp_path = h5_path + ".tmp";
  const std::string xmf_path = stem + ".xmf";
  const std::string nodes_xmf_path = stem + "_nodes.xmf";
  if (rank == 0) {
    const std::string why = probe_writable(tmp_path);
    if (!why.empty())
      error.set(InputError("cannot write output '" + h5_path + "': " + why));
  }
  raise_collectively(comm, error);

  // 5. Global sizes and this rank's offsets.
  GlobalLayout layout;
  layout.nodes = sum_over_ranks(comm, static_cast<std::int64_t>(local_nodes));
  layout.node_offset = exclusive_prefix_sum(comm, static_cast<std::int64_t>(local_nodes));
  layout.bonds = sum_over_ranks(comm, static_cast<std::int64_t>(local_bonds));
  layout.bond_offset = exclusive_prefix_sum(comm, static_cast<std::int64_t>(local_bonds));
  for (const auto& ends : bonds.ends) {
    for (std::int64_t end : ends) {
      if (end < 0 || end >= layout.nodes) {
        error.set(std::invalid_argument(
                  "write_lattice_fields: bond end node " + std::to_string(end) +
                      " is outside the node rows [0, " + std::to_string(layout.nodes) + ")"));
      }
    }
  }
  raise_collectively(comm, error);

  // 6. The HDF5 file, under its temporary name; errors are ours to report
  // (HDF5 would print its stack on every rank).
  const WriteWatch watch(comm, h5_path, tmp_path);
  const h5::QuietErrors quiet;
  try {
    write_hdf5(comm, tmp_path, nodes, bonds, layout, prov, root_scalars);
  } catch (...) {
    // Every rank is here (the failure was agreed on) and the file is closed.
    MPI_Barrier(comm);
    if (rank == 0) {
      std::error_code ec;
      fs::remove(tmp_path, ec);
    }
    throw;
  }
  MPI_Barrier(comm);  // every rank has closed the file

  // 7. Rank 0 publishes the file and writes the XDMF description.
  if (rank == 0) {
    try {
      move_into_place(tmp_path, h5_path);
      const std::string h5_name = fs::path(h5_path).filename().string();
      write_text_file_atomically(xmf_path,
                                 bonds_xdmf(h5_name, layout, node_fields, bond_fields));
      write_text_file_atomically(nodes_xmf_path, nodes_xdmf(h5_name, layout, node_fields));
    } catch (...) {
      error.first = std::current_exception();
    }
  }
  raise_collectively(comm, error);
}

}  // namespace lem
