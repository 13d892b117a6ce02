// Parallel HDF5 output of lattice fields and their one-grid XDMF documents
// (see lem/io/hdf5_writer.hpp; the attribute helpers and the XDMF text are in
// hdf5_util.cpp).
//
// Every failure that can happen on a subset of ranks is agreed on with an
// MPI reduction before anybody throws, so that all ranks throw the same
// exception together instead of some of them waiting forever in a collective.
#include "lem/io/hdf5_writer.hpp"

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

#include "lem/base/collective.hpp"
#include "lem/base/error.hpp"
#include "lem/base/files.hpp"
#include "lem/io/hdf5_util.hpp"
#include "lem/io/parallel_hdf5.hpp"
#include "lem/base/options.hpp"
#include "lem/io/write_watch.hpp"

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
void raise_collectively(MPI_Comm comm, const LocalError& error) {
  agree_on_error(comm, error.first);
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
      error.set(std::invalid_argument(std::string("write_lattice_fields: invalid ") + group +
                                      " field name '" + f.name +
                                      "' (must be non-empty and contain no '/')"));
    } else if (reserved.count(f.name) != 0) {
      error.set(std::invalid_argument("write_lattice_fields: field name '" + f.name +
                                      "' is reserved in /" + group));
    } else if (!seen.insert(f.name).second) {
      error.set(std::invalid_argument("write_lattice_fields: duplicate field " + where));
    } else if (f.components != 1 && f.components != 3 && f.components != 6) {
      error.set(std::invalid_argument("write_lattice_fields: field " + where + " has " +
                                      std::to_string(f.components) +
                                      " components (allowed: 1, 3 or 6)"));
    } else if (f.values.size() != items * static_cast<std::size_t>(f.components)) {
      error.set(std::invalid_argument("write_lattice_fields: field " + where + " has " +
                                      std::to_string(f.values.size()) + " values on rank " +
                                      std::to_string(rank) + ", expected " + std::to_string(items) +
                                      " items x " + std::to_string(f.components) + " components"));
    }
  }
}

// ---------------------------------------------------------------------------
// HDF5 writing
// ---------------------------------------------------------------------------

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
  ParallelHdf5File file(comm, path);
  const hid_t node_group = file.group("nodes");
  const hid_t bond_group = file.group("bonds");

  fault_stall(comm, path);
  const hsize_t local_nodes = static_cast<hsize_t>(nodes.coords.size());
  const hsize_t local_bonds = static_cast<hsize_t>(bonds.ends.size());
  const Slab node_rows{h(layout.nodes), h(layout.node_offset), local_nodes, 0};
  const Slab bond_rows{h(layout.bonds), h(layout.bond_offset), local_bonds, 0};

  file.dataset(node_group, "/nodes/coordinates", "coordinates", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE,
               node_rows.with_columns(3), nodes.coords.data());
  file.dataset(node_group, "/nodes/id", "id", H5T_STD_I64LE, H5T_NATIVE_INT64, node_rows,
               nodes.ids.data());
  const std::vector<std::int64_t> vertices =
      h5::XdmfText::vertex_rows(layout.node_offset, static_cast<std::int64_t>(local_nodes));
  file.dataset(node_group, "/nodes/vertices", "vertices", H5T_STD_I64LE, H5T_NATIVE_INT64,
               node_rows.with_columns(1), vertices.data());
  const auto write_field = [&](hid_t group, const char* group_name, const Field& f,
                               const Slab& rows) {
    const Slab slab = f.components == 1 ? rows : rows.with_columns(f.components);
    const std::string dataset = std::string("/") + group_name + "/" + f.name;
    if (!f.integer) {
      file.dataset(group, dataset, f.name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, slab,
                   f.values.data());
      return;
    }
    const std::vector<std::int32_t> whole(f.values.begin(), f.values.end());
    file.dataset(group, dataset, f.name, H5T_STD_I32LE, H5T_NATIVE_INT32, slab, whole.data());
  };
  for (const Field& f : nodes.fields) write_field(node_group, "nodes", f, node_rows);
  file.dataset(bond_group, "/bonds/connectivity", "connectivity", H5T_STD_I64LE, H5T_NATIVE_INT64,
               bond_rows.with_columns(2), bonds.ends.data());
  file.dataset(bond_group, "/bonds/id", "id", H5T_STD_I64LE, H5T_NATIVE_INT64, bond_rows,
               bonds.ids.data());
  for (const Field& f : bonds.fields) write_field(bond_group, "bonds", f, bond_rows);

  // Root attributes (identical on every rank: the caller broadcast them).
  file.provenance(provenance);
  for (const auto& scalar : scalars)
    file.attribute(scalar.first, [&](hid_t root) {
      return h5::write_numeric_attribute(root, scalar.first, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE,
                                         &scalar.second);
    });
  file.close();
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

// The steps of write_lattice_fields, each agreed on by all ranks.

/// 1. Local consistency of the slices.
void check_slices(MPI_Comm comm, const NodeSlice& nodes, const BondSlice& bonds) {
  const int rank = comm_rank(comm);
  LocalError error;
  const std::size_t local_nodes = nodes.coords.size();
  const std::size_t local_bonds = bonds.ends.size();
  if (nodes.ids.size() != local_nodes)
    error.set(std::invalid_argument("write_lattice_fields: rank " + std::to_string(rank) + " has " +
                                    std::to_string(local_nodes) + " node coordinates but " +
                                    std::to_string(nodes.ids.size()) + " node ids"));
  if (bonds.ids.size() != local_bonds)
    error.set(std::invalid_argument("write_lattice_fields: rank " + std::to_string(rank) + " has " +
                                    std::to_string(local_bonds) + " bonds but " +
                                    std::to_string(bonds.ids.size()) + " bond ids"));
  check_fields(nodes.fields, local_nodes, "nodes", {"coordinates", "id", "vertices"}, rank, error);
  check_fields(bonds.fields, local_bonds, "bonds", {"connectivity", "id"}, rank, error);
  raise_collectively(comm, error);
}

/// 2. Every rank must write the same set of datasets.
void check_same_fields(MPI_Comm comm, const std::vector<FieldInfo>& node_fields,
                       const std::vector<FieldInfo>& bond_fields) {
  LocalError error;
  const std::string mine = schema_text(node_fields, bond_fields);
  const std::string root = broadcast_string(comm, mine, 0);
  if (mine != root)
    error.set(
        std::invalid_argument("write_lattice_fields: rank " + std::to_string(comm_rank(comm)) +
                              " passes different fields (names/components/order) than rank 0"));
  raise_collectively(comm, error);
}

/// 3a. Rank 0's provenance, on every rank.
Provenance root_provenance(MPI_Comm comm, const Provenance& provenance) {
  Provenance prov;
  prov.program = broadcast_string(comm, provenance.program, 0);
  prov.version = broadcast_string(comm, provenance.version, 0);
  prov.git_hash = broadcast_string(comm, provenance.git_hash, 0);
  prov.options = broadcast_string(comm, provenance.options, 0);
  prov.start_time = broadcast_string(comm, provenance.start_time, 0);
  prov.ranks = provenance.ranks;
  MPI_Bcast(&prov.ranks, 1, MPI_INT, 0, comm);
  return prov;
}

/// 3b. Rank 0's scalars, on every rank; their names neither empty,
/// repeated nor those of the provenance.
std::vector<std::pair<std::string, double>> root_scalars(
    MPI_Comm comm, const std::vector<std::pair<std::string, double>>& scalars) {
  const int rank = comm_rank(comm);
  LocalError error;
  std::vector<std::pair<std::string, double>> out;
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
      error.set(std::invalid_argument("write_lattice_fields: scalar name '" + name +
                                      "' is empty, duplicated or reserved for provenance"));
    out.emplace_back(std::move(name), values[i]);
  }
  raise_collectively(comm, error);  // identical on all ranks: no rank is left behind
  return out;
}

/// 4. The output can be written: decided on rank 0 and shared, so a bad
/// path fails everywhere.
void check_writable(MPI_Comm comm, const std::string& stem, const std::string& h5_path) {
  if (stem.empty() || fs::path(stem).filename().empty()) {
    throw InputError("write_lattice_fields: output stem '" + stem +
                     "' must name a file (e.g. out/result), not be empty or end in '/'");
  }
  LocalError error;
  if (comm_rank(comm) == 0) {
    const std::string why = probe_writable(h5_path + ".tmp");
    if (!why.empty()) error.set(InputError("cannot write output '" + h5_path + "': " + why));
  }
  raise_collectively(comm, error);
}

/// 5. Global sizes and this rank's offsets; every bond end a node row.
GlobalLayout global_layout(MPI_Comm comm, const NodeSlice& nodes, const BondSlice& bonds) {
  const auto local_nodes = static_cast<std::int64_t>(nodes.coords.size());
  const auto local_bonds = static_cast<std::int64_t>(bonds.ends.size());
  GlobalLayout layout;
  layout.nodes = sum_over_ranks(comm, local_nodes);
  layout.node_offset = exclusive_prefix_sum(comm, local_nodes);
  layout.bonds = sum_over_ranks(comm, local_bonds);
  layout.bond_offset = exclusive_prefix_sum(comm, local_bonds);
  LocalError error;
  for (const auto& ends : bonds.ends) {
    for (std::int64_t end : ends) {
      if (end < 0 || end >= layout.nodes) {
        error.set(std::invalid_argument("write_lattice_fields: bond end node " +
                                        std::to_string(end) + " is outside the node rows [0, " +
                                        std::to_string(layout.nodes) + ")"));
      }
    }
  }
  raise_collectively(comm, error);
  return layout;
}

}  // namespace

// ---------------------------------------------------------------------------
// Public interface
// ---------------------------------------------------------------------------

void write_lattice_fields(MPI_Comm comm, const std::string& stem, const NodeSlice& nodes,
                          const BondSlice& bonds, const Provenance& provenance,
                          const std::vector<std::pair<std::string, double>>& scalars) {
  check_slices(comm, nodes, bonds);
  const std::vector<FieldInfo> node_fields = field_infos(nodes.fields);
  const std::vector<FieldInfo> bond_fields = field_infos(bonds.fields);
  check_same_fields(comm, node_fields, bond_fields);
  // Attributes: rank 0's provenance and scalars are written by everyone.
  const Provenance prov = root_provenance(comm, provenance);
  const auto scalars_of_root = root_scalars(comm, scalars);
  const std::string h5_path = stem + ".h5";
  check_writable(comm, stem, h5_path);
  const GlobalLayout layout = global_layout(comm, nodes, bonds);

  // 6. The HDF5 file under its temporary name, then rank 0 publishes it
  // and writes the XDMF description.
  write_hdf5_into_place(
      comm, h5_path,
      [&](const std::string& temporary) {
        write_hdf5(comm, temporary, nodes, bonds, layout, prov, scalars_of_root);
      },
      [&] {
        const std::string h5_name = fs::path(h5_path).filename().string();
        write_text_file_atomically(stem + ".xmf",
                                   bonds_xdmf(h5_name, layout, node_fields, bond_fields));
        write_text_file_atomically(stem + "_nodes.xmf", nodes_xdmf(h5_name, layout, node_fields));
      });
}

}  // namespace lem
