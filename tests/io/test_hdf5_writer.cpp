// Parallel HDF5/XDMF writer: every rank writes a slice of known global fields
// (slice sizes differ between ranks, and at 2 ranks rank 0 owns no bonds);
// rank 0 then reads the file back with the serial HDF5 API and checks every
// value, shape, attribute and the XDMF description.
#include "../world.hpp"

#include <gtest/gtest.h>
#include <hdf5.h>
#include <mpi.h>
#include <petscsys.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "lem/base/error.hpp"
#include "lem/io/hdf5_writer.hpp"

namespace {

namespace fs = std::filesystem;

std::string broadcast_from_root(std::string text) {
  int length = static_cast<int>(text.size());
  MPI_Bcast(&length, 1, MPI_INT, 0, PETSC_COMM_WORLD);
  text.resize(static_cast<std::size_t>(length));
  if (length > 0) MPI_Bcast(text.data(), length, MPI_CHAR, 0, PETSC_COMM_WORLD);
  return text;
}

// --- the known global data ---------------------------------------------------

/// Contiguous block [first, first + count) of `total` items owned by a rank.
struct Block {
  std::int64_t first = 0;
  std::int64_t count = 0;
  std::int64_t total = 0;
};

Block block_of(int rank, int size, std::int64_t (*count_of)(int, int)) {
  Block b;
  for (int r = 0; r < size; ++r) {
    if (r < rank) b.first += count_of(r, size);
    b.total += count_of(r, size);
  }
  b.count = count_of(rank, size);
  return b;
}

// Different slice sizes on every rank.
std::int64_t nodes_on(int rank, int /*size*/) { return 4 + 3 * rank; }
// At more than one rank, rank 0 reports no bonds at all.
std::int64_t bonds_on(int rank, int size) { return size > 1 && rank == 0 ? 0 : 6 + 2 * rank; }
// Alternative distributions: every rank reports bonds (so the bond offsets
// are non-trivial at 2 ranks), or the last rank reports none.
std::int64_t bonds_on_every_rank(int rank, int /*size*/) { return 5 + 4 * rank; }
std::int64_t bonds_on_all_but_last(int rank, int size) {
  return size > 1 && rank == size - 1 ? 0 : 3 + rank;
}
using CountOf = std::int64_t (*)(int, int);

std::array<double, 3> coordinate(std::int64_t i) {
  const double x = static_cast<double>(i);
  return {x, 2.0 * x + 0.5, -x / 3.0};
}
std::int64_t node_id(std::int64_t i) { return 1000 + 7 * i; }
double displacement(std::int64_t i, int c, double scale) {
  return scale * (0.001 * static_cast<double>(i) + 0.1 * c);
}
double pinned(std::int64_t i) { return i % 3 == 0 ? 1.0 : 0.0; }

std::array<std::int64_t, 2> bond_ends(std::int64_t b, std::int64_t nodes) {
  return {b % nodes, (3 * b + 1) % nodes};
}
std::int64_t bond_id(std::int64_t b) { return 50000 + 11 * b; }
double force(std::int64_t b, double scale) { return scale * (1.5 * static_cast<double>(b) - 2.0); }
double direction(std::int64_t b, int c) {
  const double x = static_cast<double>(b);
  return c == 0 ? 1.0 : (c == 1 ? -0.5 * x : x * x);
}

lem::NodeSlice make_nodes(double scale) {
  const Block block = block_of(world_rank(), world_size(), nodes_on);
  lem::NodeSlice nodes;
  lem::Field disp{"displacement", 3, {}};
  lem::Field pin{"pinned", 1, {}};
  for (std::int64_t i = block.first; i < block.first + block.count; ++i) {
    nodes.coords.push_back(coordinate(i));
    nodes.ids.push_back(node_id(i));
    for (int c = 0; c < 3; ++c) disp.values.push_back(displacement(i, c, scale));
    pin.values.push_back(pinned(i));
  }
  nodes.fields = {disp, pin};
  return nodes;
}

lem::BondSlice make_bonds(double scale, CountOf count_of = bonds_on) {
  const std::int64_t total_nodes = block_of(world_rank(), world_size(), nodes_on).total;
  const Block block = block_of(world_rank(), world_size(), count_of);
  lem::BondSlice bonds;
  lem::Field f{"force", 1, {}};
  lem::Field dir{"direction", 3, {}};
  for (std::int64_t b = block.first; b < block.first + block.count; ++b) {
    bonds.ends.push_back(bond_ends(b, total_nodes));
    bonds.ids.push_back(bond_id(b));
    f.values.push_back(force(b, scale));
    for (int c = 0; c < 3; ++c) dir.values.push_back(direction(b, c));
  }
  bonds.fields = {f, dir};
  return bonds;
}

const std::vector<std::pair<std::string, double>> kScalars = {{"applied_strain", 2.5e-3},
                                                              {"peak_force", -17.25}};

// --- serial HDF5 reading (rank 0 only) --------------------------------------

std::vector<hsize_t> shape_of(hid_t file, const std::string& path) {
  std::vector<hsize_t> dims;
  const hid_t dset = H5Dopen2(file, path.c_str(), H5P_DEFAULT);
  if (dset < 0) return dims;
  const hid_t space = H5Dget_space(dset);
  const int rank = H5Sget_simple_extent_ndims(space);
  if (rank > 0) {
    dims.resize(static_cast<std::size_t>(rank));
    H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  }
  H5Sclose(space);
  H5Dclose(dset);
  return dims;
}

template <class T>
std::vector<T> read_all(hid_t file, const std::string& path, hid_t memory_type) {
  std::vector<T> values;
  const hid_t dset = H5Dopen2(file, path.c_str(), H5P_DEFAULT);
  if (dset < 0) {
    ADD_FAILURE() << "missing dataset " << path;
    return values;
  }
  const hid_t space = H5Dget_space(dset);
  const hssize_t n = H5Sget_simple_extent_npoints(space);
  values.resize(static_cast<std::size_t>(n));
  if (n > 0) {
    EXPECT_GE(H5Dread(dset, memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), 0) << path;
  }
  H5Sclose(space);
  H5Dclose(dset);
  return values;
}

bool stored_as_int64(hid_t file, const std::string& path) {
  const hid_t dset = H5Dopen2(file, path.c_str(), H5P_DEFAULT);
  if (dset < 0) return false;
  const hid_t type = H5Dget_type(dset);
  const bool ok =
      H5Tget_class(type) == H5T_INTEGER && H5Tget_size(type) == 8 && H5Tget_sign(type) == H5T_SGN_2;
  H5Tclose(type);
  H5Dclose(dset);
  return ok;
}

double read_double_attribute(hid_t file, const std::string& name) {
  double value = std::nan("");
  const hid_t attr = H5Aopen(file, name.c_str(), H5P_DEFAULT);
  if (attr < 0) {
    ADD_FAILURE() << "missing attribute " << name;
    return value;
  }
  EXPECT_GE(H5Aread(attr, H5T_NATIVE_DOUBLE, &value), 0) << name;
  H5Aclose(attr);
  return value;
}

std::int64_t read_int_attribute(hid_t file, const std::string& name) {
  std::int64_t value = -1;
  const hid_t attr = H5Aopen(file, name.c_str(), H5P_DEFAULT);
  if (attr < 0) {
    ADD_FAILURE() << "missing attribute " << name;
    return value;
  }
  EXPECT_GE(H5Aread(attr, H5T_NATIVE_INT64, &value), 0) << name;
  H5Aclose(attr);
  return value;
}

std::string read_string_attribute(hid_t file, const std::string& name) {
  std::string value;
  const hid_t attr = H5Aopen(file, name.c_str(), H5P_DEFAULT);
  if (attr < 0) {
    ADD_FAILURE() << "missing attribute " << name;
    return value;
  }
  const hid_t type = H5Aget_type(attr);
  EXPECT_EQ(H5Tget_class(type), H5T_STRING) << name;
  if (H5Tis_variable_str(type) > 0) {
    char* text = nullptr;
    const hid_t memory = H5Tcopy(H5T_C_S1);
    H5Tset_size(memory, H5T_VARIABLE);
    H5Tset_cset(memory, H5Tget_cset(type));
    EXPECT_GE(H5Aread(attr, memory, &text), 0) << name;
    if (text != nullptr) {
      value = text;
      H5free_memory(text);
    }
    H5Tclose(memory);
  } else {
    std::vector<char> buffer(H5Tget_size(type) + 1, '\0');
    EXPECT_GE(H5Aread(attr, type, buffer.data()), 0) << name;
    value = buffer.data();
  }
  H5Tclose(type);
  H5Aclose(attr);
  return value;
}

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// What write_lattice_fields leaves in an empty folder (stem "lattice").
const std::set<std::string> kWritten = {"lattice.h5", "lattice.xmf", "lattice_nodes.xmf"};

std::set<std::string> directory_listing(const std::string& dir) {
  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir))
    names.insert(entry.path().filename().string());
  return names;
}

/// Rank 0: every value, shape and attribute of a file written by make_nodes/make_bonds.
void check_h5(const std::string& path, double scale, const lem::Provenance& provenance,
              CountOf bond_count_of = bonds_on) {
  const int size = world_size();
  const std::int64_t n = block_of(0, size, nodes_on).total;
  const std::int64_t m = block_of(0, size, bond_count_of).total;
  const auto N = static_cast<hsize_t>(n);
  const auto M = static_cast<hsize_t>(m);

  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(file, 0) << "cannot open " << path;

  EXPECT_EQ(shape_of(file, "/nodes/coordinates"), (std::vector<hsize_t>{N, 3}));
  EXPECT_EQ(shape_of(file, "/nodes/id"), (std::vector<hsize_t>{N}));
  EXPECT_EQ(shape_of(file, "/nodes/displacement"), (std::vector<hsize_t>{N, 3}));
  EXPECT_EQ(shape_of(file, "/nodes/pinned"), (std::vector<hsize_t>{N}));
  EXPECT_EQ(shape_of(file, "/bonds/connectivity"), (std::vector<hsize_t>{M, 2}));
  EXPECT_EQ(shape_of(file, "/bonds/id"), (std::vector<hsize_t>{M}));
  EXPECT_EQ(shape_of(file, "/bonds/force"), (std::vector<hsize_t>{M}));
  EXPECT_EQ(shape_of(file, "/bonds/direction"), (std::vector<hsize_t>{M, 3}));
  EXPECT_TRUE(stored_as_int64(file, "/bonds/connectivity"));
  EXPECT_TRUE(stored_as_int64(file, "/nodes/id"));
  EXPECT_TRUE(stored_as_int64(file, "/bonds/id"));

  const auto coords = read_all<double>(file, "/nodes/coordinates", H5T_NATIVE_DOUBLE);
  const auto ids = read_all<std::int64_t>(file, "/nodes/id", H5T_NATIVE_INT64);
  const auto disp = read_all<double>(file, "/nodes/displacement", H5T_NATIVE_DOUBLE);
  const auto pin = read_all<double>(file, "/nodes/pinned", H5T_NATIVE_DOUBLE);
  ASSERT_EQ(coords.size(), 3 * N);
  ASSERT_EQ(ids.size(), N);
  ASSERT_EQ(disp.size(), 3 * N);
  ASSERT_EQ(pin.size(), N);
  for (std::int64_t i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const auto x = coordinate(i);
    for (std::size_t c = 0; c < 3; ++c) {
      EXPECT_EQ(coords[3 * k + c], x[c]) << "node " << i << " coordinate " << c;
      EXPECT_EQ(disp[3 * k + c], displacement(i, static_cast<int>(c), scale)) << "node " << i;
    }
    EXPECT_EQ(ids[k], node_id(i)) << "node " << i;
    EXPECT_EQ(pin[k], pinned(i)) << "node " << i;
  }

  const auto conn = read_all<std::int64_t>(file, "/bonds/connectivity", H5T_NATIVE_INT64);
  const auto bids = read_all<std::int64_t>(file, "/bonds/id", H5T_NATIVE_INT64);
  const auto f = read_all<double>(file, "/bonds/force", H5T_NATIVE_DOUBLE);
  const auto dir = read_all<double>(file, "/bonds/direction", H5T_NATIVE_DOUBLE);
  ASSERT_EQ(conn.size(), 2 * M);
  ASSERT_EQ(bids.size(), M);
  ASSERT_EQ(f.size(), M);
  ASSERT_EQ(dir.size(), 3 * M);
  for (std::int64_t b = 0; b < m; ++b) {
    const auto k = static_cast<std::size_t>(b);
    const auto ends = bond_ends(b, n);
    EXPECT_EQ(conn[2 * k], ends[0]) << "bond " << b;
    EXPECT_EQ(conn[2 * k + 1], ends[1]) << "bond " << b;
    EXPECT_EQ(bids[k], bond_id(b)) << "bond " << b;
    EXPECT_EQ(f[k], force(b, scale)) << "bond " << b;
    for (std::size_t c = 0; c < 3; ++c)
      EXPECT_EQ(dir[3 * k + c], direction(b, static_cast<int>(c))) << "bond " << b;
  }

  for (const auto& [name, value] : kScalars) EXPECT_EQ(read_double_attribute(file, name), value);
  EXPECT_EQ(read_string_attribute(file, "program"), provenance.program);
  EXPECT_EQ(read_string_attribute(file, "version"), provenance.version);
  EXPECT_EQ(read_string_attribute(file, "git_hash"), provenance.git_hash);
  EXPECT_EQ(read_string_attribute(file, "options"), provenance.options);
  EXPECT_EQ(read_string_attribute(file, "start_time"), provenance.start_time);
  EXPECT_EQ(read_int_attribute(file, "ranks"), size);

  EXPECT_GE(H5Fclose(file), 0);
}

// --- fixture: a fresh directory per test, shared by all ranks ---------------

class Hdf5Writer : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string name;
    if (world_rank() == 0) {
      char pattern[] = "/tmp/lem_test_hdf5_writer_XXXXXX";
      const char* made = mkdtemp(pattern);
      name = made != nullptr ? made : "";
    }
    dir_ = broadcast_from_root(name);
    ASSERT_FALSE(dir_.empty()) << "mkdtemp failed";
    stem_ = dir_ + "/lattice";
  }

  void TearDown() override {
    MPI_Barrier(PETSC_COMM_WORLD);
    if (world_rank() == 0 && !dir_.empty()) {
      std::error_code ec;
      fs::remove_all(dir_, ec);
    }
    MPI_Barrier(PETSC_COMM_WORLD);
  }

  std::string dir_;
  std::string stem_;
};

TEST_F(Hdf5Writer, EveryValueShapeAndAttributeReadsBack) {
  const lem::Provenance provenance = lem::collect_provenance(PETSC_COMM_WORLD, "test_hdf5_writer");
  const auto nodes = make_nodes(1.0);
  const auto bonds = make_bonds(1.0);
  if (world_size() == 2) {
    EXPECT_EQ(bonds.ends.empty(), world_rank() == 0);  // the empty-selection case is exercised
  }
  ASSERT_NO_THROW(
      lem::write_lattice_fields(PETSC_COMM_WORLD, stem_, nodes, bonds, provenance, kScalars));

  if (world_rank() == 0) {
    check_h5(stem_ + ".h5", 1.0, provenance);
    EXPECT_FALSE(fs::exists(stem_ + ".h5.tmp"));
    EXPECT_FALSE(fs::exists(stem_ + ".xmf.tmp"));
    EXPECT_EQ(directory_listing(dir_), (kWritten));
  }
}

TEST_F(Hdf5Writer, OtherBondDistributionsReadBack) {
  const lem::Provenance provenance = lem::collect_provenance(PETSC_COMM_WORLD, "distributions");
  for (CountOf count_of : {bonds_on_every_rank, bonds_on_all_but_last}) {
    ASSERT_NO_THROW(lem::write_lattice_fields(PETSC_COMM_WORLD, stem_, make_nodes(2.0),
                                              make_bonds(2.0, count_of), provenance, kScalars));
    if (world_rank() == 0) {
      check_h5(stem_ + ".h5", 2.0, provenance, count_of);
      EXPECT_EQ(directory_listing(dir_), (kWritten));
    }
  }
}

TEST_F(Hdf5Writer, OverwritesAnEarlierResult) {
  const lem::Provenance provenance = lem::collect_provenance(PETSC_COMM_WORLD, "overwrite");
  ASSERT_NO_THROW(lem::write_lattice_fields(PETSC_COMM_WORLD, stem_, make_nodes(1.0),
                                            make_bonds(1.0), provenance, kScalars));
  ASSERT_NO_THROW(lem::write_lattice_fields(PETSC_COMM_WORLD, stem_, make_nodes(-3.0),
                                            make_bonds(-3.0), provenance, kScalars));
  if (world_rank() == 0) {
    check_h5(stem_ + ".h5", -3.0, provenance);
    EXPECT_EQ(directory_listing(dir_), (kWritten));
  }
}

TEST_F(Hdf5Writer, XdmfReferencesEveryDatasetWithItsShape) {
  const lem::Provenance provenance = lem::collect_provenance(PETSC_COMM_WORLD, "xdmf");
  ASSERT_NO_THROW(lem::write_lattice_fields(PETSC_COMM_WORLD, stem_, make_nodes(1.0),
                                            make_bonds(1.0), provenance, kScalars));
  if (world_rank() != 0) return;

  // One grid per file: the bonds in lattice.xmf, the nodes in lattice_nodes.xmf.
  const std::string xmf = read_text(stem_ + ".xmf");
  const std::string nodes_xmf = read_text(stem_ + "_nodes.xmf");
  ASSERT_FALSE(xmf.empty()) << "missing " << stem_ << ".xmf";
  ASSERT_FALSE(nodes_xmf.empty()) << "missing " << stem_ << "_nodes.xmf";
  for (const std::string* text : {&xmf, &nodes_xmf}) {
    EXPECT_NE(text->find("<Xdmf Version=\"3.0\">"), std::string::npos);
    EXPECT_EQ(text->find("<Grid "), text->rfind("<Grid ")) << "more than one grid";
    EXPECT_EQ(text->find(dir_), std::string::npos)
        << "the .h5 must be referenced by file name only";
  }
  EXPECT_NE(xmf.find("<Grid Name=\"bonds\""), std::string::npos);
  EXPECT_NE(xmf.find("TopologyType=\"Polyline\""), std::string::npos);
  EXPECT_NE(xmf.find("NodesPerElement=\"2\""), std::string::npos);
  EXPECT_NE(nodes_xmf.find("<Grid Name=\"nodes\""), std::string::npos);
  EXPECT_NE(nodes_xmf.find("TopologyType=\"Polyvertex\""), std::string::npos);

  // Every dataset is referenced, as lattice.h5:<path>, with its true shape.
  const std::regex item(
      R"re(<DataItem Dimensions="([0-9 ]+)" NumberType="(Float|Int)" Precision="([48])" Format="HDF">([^<:]+):([^<]+)</DataItem>)re");
  std::map<std::string, std::string> dims_of;  // dataset -> Dimensions (last seen)
  std::map<std::string, int> references;
  for (const std::string* text : {&xmf, &nodes_xmf})
    for (auto it = std::sregex_iterator(text->begin(), text->end(), item);
         it != std::sregex_iterator(); ++it) {
      const std::smatch& match = *it;
      EXPECT_EQ(match[4].str(), "lattice.h5");
      const std::string path = match[5].str();
      const bool integer = path == "/bonds/connectivity" || path == "/nodes/id" ||
                           path == "/bonds/id" || path == "/nodes/vertices";
      EXPECT_EQ(match[2].str(), integer ? "Int" : "Float") << path;
      EXPECT_EQ(match[3].str(), "8") << path;
      dims_of[path] = match[1].str();
      ++references[path];
    }
  const hid_t file = H5Fopen((stem_ + ".h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  for (const char* path :
       {"/nodes/coordinates", "/nodes/id", "/nodes/vertices", "/nodes/displacement",
        "/nodes/pinned", "/bonds/connectivity", "/bonds/id", "/bonds/force", "/bonds/direction"}) {
    ASSERT_EQ(dims_of.count(path), 1u) << path << " is not referenced by the .xmf";
    std::ostringstream expected;
    const auto shape = shape_of(file, path);
    for (std::size_t d = 0; d < shape.size(); ++d) expected << (d ? " " : "") << shape[d];
    EXPECT_EQ(dims_of[path], expected.str()) << path;
  }
  H5Fclose(file);
  // Geometry and node fields appear in both grids; bond data only in "bonds".
  EXPECT_EQ(references["/nodes/coordinates"], 2);
  EXPECT_EQ(references["/nodes/displacement"], 2);
  EXPECT_EQ(references["/nodes/pinned"], 2);
  EXPECT_EQ(references["/nodes/vertices"], 1);
  EXPECT_EQ(references["/bonds/connectivity"], 1);
  EXPECT_EQ(references["/bonds/force"], 1);

  const std::string m = std::to_string(block_of(0, world_size(), bonds_on).total);
  EXPECT_NE(xmf.find("NumberOfElements=\"" + m + "\""), std::string::npos);
  EXPECT_NE(xmf.find(R"(<Attribute Name="displacement" AttributeType="Vector" Center="Node">)"),
            std::string::npos);
  EXPECT_NE(xmf.find(R"(<Attribute Name="pinned" AttributeType="Scalar" Center="Node">)"),
            std::string::npos);
  EXPECT_NE(xmf.find(R"(<Attribute Name="force" AttributeType="Scalar" Center="Cell">)"),
            std::string::npos);
  EXPECT_NE(xmf.find(R"(<Attribute Name="direction" AttributeType="Vector" Center="Cell">)"),
            std::string::npos);
}

TEST_F(Hdf5Writer, NoBondsAnywhereGivesEmptyBondDatasets) {
  const lem::Provenance provenance = lem::collect_provenance(PETSC_COMM_WORLD, "empty");
  lem::BondSlice none;
  none.fields = {{"force", 1, {}}};
  ASSERT_NO_THROW(
      lem::write_lattice_fields(PETSC_COMM_WORLD, stem_, make_nodes(1.0), none, provenance, {}));
  if (world_rank() == 0) {
    const hid_t file = H5Fopen((stem_ + ".h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    ASSERT_GE(file, 0);
    EXPECT_EQ(shape_of(file, "/bonds/connectivity"), (std::vector<hsize_t>{0, 2}));
    EXPECT_EQ(shape_of(file, "/bonds/id"), (std::vector<hsize_t>{0}));
    EXPECT_EQ(shape_of(file, "/bonds/force"), (std::vector<hsize_t>{0}));
    const auto n = static_cast<hsize_t>(block_of(0, world_size(), nodes_on).total);
    EXPECT_EQ(shape_of(file, "/nodes/coordinates"), (std::vector<hsize_t>{n, 3}));
    H5Fclose(file);
  }
}

TEST_F(Hdf5Writer, UnwritablePathThrowsInputErrorOnEveryRank) {
  const lem::Provenance provenance = lem::collect_provenance(PETSC_COMM_WORLD, "bad path");
  const auto nodes = make_nodes(1.0);
  const auto bonds = make_bonds(1.0);

  // A regular file where a directory is expected.
  if (world_rank() == 0) std::ofstream(dir_ + "/plain_file") << "x";
  MPI_Barrier(PETSC_COMM_WORLD);

  for (const std::string& stem : {std::string("/nonexistent_dir/x"), dir_ + "/plain_file/x"}) {
    bool input_error = false;
    std::string message;
    try {
      lem::write_lattice_fields(PETSC_COMM_WORLD, stem, nodes, bonds, provenance, kScalars);
    } catch (const lem::InputError& e) {
      input_error = true;
      message = e.what();
    } catch (const std::exception& e) {
      message = e.what();
    }
    EXPECT_TRUE(input_error) << stem << ": " << message;
    EXPECT_NE(message.find(stem), std::string::npos)
        << "message does not name the path: " << message;
  }
  if (world_rank() == 0) {
    EXPECT_EQ(directory_listing(dir_), (std::set<std::string>{"plain_file"}));
  }
}

TEST_F(Hdf5Writer, InconsistentSliceOnOneRankThrowsOnEveryRank) {
  const lem::Provenance provenance = lem::collect_provenance(PETSC_COMM_WORLD, "bad slice");
  auto nodes = make_nodes(1.0);
  if (world_rank() == world_size() - 1) nodes.fields[0].values.push_back(0.0);  // one too many
  EXPECT_THROW(lem::write_lattice_fields(PETSC_COMM_WORLD, stem_, nodes, make_bonds(1.0),
                                         provenance, kScalars),
               std::invalid_argument);
  if (world_rank() == 0) {
    EXPECT_TRUE(directory_listing(dir_).empty());
  }
}

TEST_F(Hdf5Writer, TextFileIsWrittenAtomically) {
  if (world_rank() != 0) return;  // rank-0-only function, no collectives inside
  const std::string path = dir_ + "/notes.txt";
  lem::write_text_file_atomically(path, "first\n");
  EXPECT_EQ(read_text(path), "first\n");
  lem::write_text_file_atomically(path, "second version\n");
  EXPECT_EQ(read_text(path), "second version\n");
  EXPECT_EQ(directory_listing(dir_), (std::set<std::string>{"notes.txt"}));

  const std::string bad = "/nonexistent_dir/notes.txt";
  try {
    lem::write_text_file_atomically(bad, "x");
    ADD_FAILURE() << "no exception for " << bad;
  } catch (const lem::IoError& e) {
    EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
  }
}

TEST_F(Hdf5Writer, ProvenanceAgreesOnEveryRank) {
  ASSERT_EQ(PetscOptionsSetValue(nullptr, "-lem_hdf5_test_marker", "42"), 0);
  const lem::Provenance p = lem::collect_provenance(PETSC_COMM_WORLD, "prog");
  ASSERT_EQ(PetscOptionsClearValue(nullptr, "-lem_hdf5_test_marker"), 0);

  EXPECT_EQ(p.program, "prog");
  EXPECT_EQ(p.ranks, world_size());
  EXPECT_FALSE(p.version.empty());
  EXPECT_FALSE(p.git_hash.empty());
  EXPECT_TRUE(std::regex_match(p.start_time, std::regex(R"(\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ)")))
      << p.start_time;
  std::istringstream lines(p.options);
  std::set<std::string> options;
  for (std::string line; std::getline(lines, line);) options.insert(line);
  EXPECT_EQ(options.count("-lem_hdf5_test_marker 42"), 1u) << p.options;

  EXPECT_EQ(broadcast_from_root(p.start_time), p.start_time);
  EXPECT_EQ(broadcast_from_root(p.options), p.options);
}

}  // namespace
