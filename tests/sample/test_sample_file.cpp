// The cemented sample file: an exact round trip, and one clear InputError
// for every kind of wrong file.
#include "lem/sample/cemented_sample.hpp"
#include "lem/base/error.hpp"
#include "lem/io/hdf5_util.hpp"
#include "lem/io/hdf5_writer.hpp"
#include "lem/sample/sample_writer.hpp"

#include <gtest/gtest.h>
#include <hdf5.h>
#include <mpi.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>

using namespace lem;
namespace fs = std::filesystem;

namespace {

struct Built {
  CementedSample sample;
  CementedSampleSpec spec;
};

const Built& small() {
  static const Built built = [] {
    Built b;
    b.spec.packing.count = 100;
    b.spec.packing.seed = 5;
    b.spec.sample_particles = 20;
    b.spec.lattice.bonds = 20000;
    b.spec.lattice.seed = 9;
    b.spec.bridges.matrix_fraction = 0.1;
    b.sample = build_cemented_sample(b.spec);
    return b;
  }();
  return built;
}

class SampleFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("lem_sample_file_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    provenance_ = collect_provenance(MPI_COMM_SELF, "test_sample_file");
  }
  void TearDown() override { fs::remove_all(dir_); }

  /// A valid sample file (written once per test).
  std::string written(const std::string& name = "s") {
    const std::string stem = (dir_ / name).string();
    write_sample(stem, small().sample, small().spec, provenance_);
    return stem + ".h5";
  }

  /// `read_sample(path)` must throw InputError whose message contains `text`.
  static void expect_input_error(const std::string& path, const std::string& text) {
    try {
      read_sample(path);
      ADD_FAILURE() << "no error reading " << path;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(text), std::string::npos)
          << "message: " << e.what() << "\nexpected to contain: " << text;
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  }

  /// Change the file in place with raw HDF5 calls.
  static void edit(const std::string& path, const std::function<void(hid_t)>& change) {
    const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(file, 0);
    change(file);
    H5Fclose(file);
  }

  /// Overwrite an integer attribute of the root group.
  static void set_attribute(const std::string& path, const char* name, std::int64_t value) {
    edit(path, [&](hid_t file) {
      const hid_t attribute = H5Aopen(file, name, H5P_DEFAULT);
      EXPECT_GE(H5Awrite(attribute, H5T_NATIVE_INT64, &value), 0);
      H5Aclose(attribute);
    });
  }

  /// Overwrite element `index` of an integer dataset.
  static void poke(const std::string& path, const char* dataset, hsize_t index,
                   std::int64_t value) {
    edit(path, [&](hid_t file) {
      const hid_t set = H5Dopen2(file, dataset, H5P_DEFAULT);
      const hid_t space = H5Dget_space(set);
      const int rank = H5Sget_simple_extent_ndims(space);
      const hsize_t start[2] = {index, 0}, count[2] = {1, 1};
      H5Sselect_hyperslab(space, H5S_SELECT_SET, start, nullptr, count, nullptr);
      const hid_t memory = H5Screate_simple(rank, count, nullptr);
      EXPECT_GE(H5Dwrite(set, H5T_NATIVE_INT64, memory, space, H5P_DEFAULT, &value), 0);
      H5Sclose(memory);
      H5Sclose(space);
      H5Dclose(set);
    });
  }

  /// Overwrite row `row` of a 2-D dataset with `values` (one per column).
  template <class T>
  static void set_row(const std::string& path, const char* dataset, hsize_t row,
                      const std::vector<T>& values, hid_t memory_type) {
    edit(path, [&](hid_t file) {
      const hid_t set = H5Dopen2(file, dataset, H5P_DEFAULT);
      const hid_t space = H5Dget_space(set);
      const hsize_t start[2] = {row, 0}, count[2] = {1, values.size()};
      H5Sselect_hyperslab(space, H5S_SELECT_SET, start, nullptr, count, nullptr);
      const hid_t memory = H5Screate_simple(2, count, nullptr);
      EXPECT_GE(H5Dwrite(set, memory_type, memory, space, H5P_DEFAULT, values.data()), 0);
      H5Sclose(memory);
      H5Sclose(space);
      H5Dclose(set);
    });
  }

  fs::path dir_;
  Provenance provenance_;
};

}  // namespace

TEST_F(SampleFileTest, RoundTripIsExact) {
  const std::string path = written();
  EXPECT_TRUE(fs::exists(dir_ / "s.xmf"));
  EXPECT_FALSE(fs::exists(path + ".tmp"));
  const SampleFile f = read_sample_file(path);
  const CementedSample& a = small().sample;
  const CementedSample& b = f.sample;
  EXPECT_EQ(a.lattice.box.lo, b.lattice.box.lo);
  EXPECT_EQ(a.lattice.box.hi, b.lattice.box.hi);
  EXPECT_EQ(a.lattice.nodes, b.lattice.nodes);
  ASSERT_EQ(a.lattice.bond_count(), b.lattice.bond_count());
  for (std::size_t i = 0; i < a.lattice.bond_count(); ++i) {
    ASSERT_EQ(a.lattice.bonds[i].i, b.lattice.bonds[i].i);
    ASSERT_EQ(a.lattice.bonds[i].j, b.lattice.bonds[i].j);
  }
  EXPECT_EQ(a.lattice.stiffness, b.lattice.stiffness);
  EXPECT_EQ(a.node_volume, b.node_volume);
  EXPECT_EQ(a.node_phases.particle, b.node_phases.particle);
  EXPECT_EQ(a.node_phases.matrix, b.node_phases.matrix);
  EXPECT_EQ(a.bond_phase, b.bond_phase);
  ASSERT_EQ(a.particles.size(), b.particles.size());
  for (std::size_t i = 0; i < a.particles.size(); ++i) {
    EXPECT_EQ(a.particles[i].centre, b.particles[i].centre);
    EXPECT_EQ(a.particles[i].radius, b.particles[i].radius);
  }
  ASSERT_EQ(a.bridges.size(), b.bridges.size());
  for (std::size_t k = 0; k < a.bridges.size(); ++k) {
    EXPECT_EQ(a.bridges[k].i, b.bridges[k].i);
    EXPECT_EQ(a.bridges[k].j, b.bridges[k].j);
    EXPECT_EQ(a.bridges[k].lambda, b.bridges[k].lambda);
  }
  // Every stats field, bit for bit (the struct holds only numbers).
  EXPECT_EQ(std::memcmp(&a.stats, &b.stats, sizeof a.stats), 0);
  EXPECT_GT(b.stats.bonds, 10000);

  const CementedSampleSpec& s = small().spec;
  EXPECT_EQ(f.spec.packing.count, s.packing.count);
  EXPECT_EQ(f.spec.packing.seed, s.packing.seed);
  EXPECT_EQ(f.spec.packing.d_min, s.packing.d_min);
  EXPECT_EQ(f.spec.packing.d_max, s.packing.d_max);
  EXPECT_EQ(f.spec.packing.distribution, s.packing.distribution);
  EXPECT_EQ(f.spec.sample_particles, s.sample_particles);
  EXPECT_EQ(f.spec.lattice.bonds, s.lattice.bonds);
  EXPECT_EQ(f.spec.lattice.seed, s.lattice.seed);
  EXPECT_EQ(f.spec.lattice.min_separation, s.lattice.min_separation);
  EXPECT_EQ(f.spec.bridges.matrix_fraction, s.bridges.matrix_fraction);
  EXPECT_EQ(f.spec.bridges.max_gap, s.bridges.max_gap);
  EXPECT_EQ(f.spec.bridges.max_lambda, s.bridges.max_lambda);
  EXPECT_EQ(f.provenance.program, "test_sample_file");
  EXPECT_EQ(f.provenance.git_hash, provenance_.git_hash);
  EXPECT_EQ(f.provenance.start_time, provenance_.start_time);
}

TEST_F(SampleFileTest, XdmfShowsPhasesOnNodesAndBonds) {
  written();
  std::ifstream in(dir_ / "s.xmf");
  const std::string xmf((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (const char* piece : {"s.h5:/nodes/phase", "s.h5:/nodes/particle", "s.h5:/bonds/phase",
                            "s.h5:/bonds/connectivity", "TopologyType=\"Polyline\""})
    EXPECT_NE(xmf.find(piece), std::string::npos) << piece;
}

TEST_F(SampleFileTest, MissingFile) {
  expect_input_error((dir_ / "missing.h5").string(), "does not exist");
}

TEST_F(SampleFileTest, TextFileIsNotHdf5) {
  const std::string path = (dir_ / "notes.h5").string();
  std::ofstream(path) << "this is not an HDF5 file\n";
  expect_input_error(path, "is not a readable HDF5 file");
}

TEST_F(SampleFileTest, OtherHdf5FileIsNotASample) {
  // The fields file of a tension run: HDF5, but without the format tag.
  NodeSlice nodes;
  nodes.coords = {{0, 0, 0}, {1, 0, 0}};
  nodes.ids = {0, 1};
  BondSlice bonds;
  bonds.ends = {{0, 1}};
  bonds.ids = {0};
  write_lattice_fields(MPI_COMM_SELF, (dir_ / "fields").string(), nodes, bonds, provenance_, {});
  expect_input_error((dir_ / "fields.h5").string(), "is not a lem cemented-sample file");
}

TEST_F(SampleFileTest, TruncatedFileFailsClearly) {
  const std::string good = written();
  const std::string cut = (dir_ / "cut.h5").string();
  fs::copy_file(good, cut);
  fs::resize_file(cut, fs::file_size(good) / 2);
  try {
    read_sample(cut);
    ADD_FAILURE() << "no error reading a truncated file";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(cut), std::string::npos) << m;
    EXPECT_TRUE(m.find("not a readable HDF5 file") != std::string::npos ||
                m.find("corrupt") != std::string::npos)
        << m;
  }
}

TEST_F(SampleFileTest, WrongFormatVersion) {
  const std::string path = written();
  set_attribute(path, "format_version", 2);
  expect_input_error(path, "has format_version 2");
}

TEST_F(SampleFileTest, MissingDatasetIsCorrupt) {
  const std::string path = written();
  edit(path, [](hid_t file) { EXPECT_GE(H5Ldelete(file, "/nodes/volume", H5P_DEFAULT), 0); });
  expect_input_error(path, "is corrupt: dataset /nodes/volume is missing");
}

TEST_F(SampleFileTest, BondEndOutOfRangeIsCorrupt) {
  const std::string path = written();
  poke(path, "/bonds/connectivity", 3, small().sample.stats.nodes + 5);
  expect_input_error(path, "is corrupt: /bonds/connectivity row 3 joins nodes");
}

TEST_F(SampleFileTest, PhaseCodeOutOfRangeIsCorrupt) {
  const std::string path = written();
  poke(path, "/bonds/phase", 7, 9);
  expect_input_error(path, "is corrupt: /bonds/phase row 7 holds 9, out of range [0, 4]");
}

TEST_F(SampleFileTest, InconsistentSizesAreCorrupt) {
  const std::string path = written();
  set_attribute(path, "bonds", 17);  // the datasets hold more
  expect_input_error(path, "is corrupt: dataset /bonds/connectivity has");
}

TEST_F(SampleFileTest, StatisticMissingFromAnOlderFileReadsAsZero) {
  const std::string path = written();
  edit(path, [](hid_t file) { EXPECT_GE(H5Adelete(file, "interface_ratio"), 0); });
  const CementedSample s = read_sample(path);
  EXPECT_EQ(s.stats.interface_ratio, 0.0);
  EXPECT_EQ(s.stats.rho_m, small().sample.stats.rho_m);
}

TEST_F(SampleFileTest, VoidRuleIsStoredAndOlderFilesReadAsAnyEnd) {
  CementedSampleSpec spec = small().spec;
  spec.bridges.void_bonds = VoidRule::both_ends;
  const std::string stem = (dir_ / "both").string();
  write_sample(stem, small().sample, spec, provenance_);
  EXPECT_EQ(read_sample_file(stem + ".h5").spec.bridges.void_bonds, VoidRule::both_ends);
  // A file from before the rule was a choice has no attribute: any_end.
  edit(stem + ".h5", [](hid_t file) { EXPECT_GE(H5Adelete(file, "void_bonds"), 0); });
  EXPECT_EQ(read_sample_file(stem + ".h5").spec.bridges.void_bonds, VoidRule::any_end);
  const std::string path = written();
  EXPECT_EQ(read_sample_file(path).spec.bridges.void_bonds, VoidRule::any_end);
  edit(path, [](hid_t file) {
    EXPECT_GE(H5Adelete(file, "void_bonds"), 0);
    EXPECT_TRUE(h5::write_string_attribute(file, "void_bonds", "some_ends"));
  });
  expect_input_error(path, "is corrupt: unknown void_bonds 'some_ends'");
}

TEST_F(SampleFileTest, RepeatedBondNamesTheFirstRepeat) {
  const std::string path = written();
  const auto& bonds = small().sample.lattice.bonds;
  auto row = [&](std::size_t b) { return std::vector<std::int64_t>{bonds[b].i, bonds[b].j}; };
  set_row(path, "/bonds/connectivity", 300, row(5), H5T_NATIVE_INT64);
  set_row(path, "/bonds/connectivity", 100, row(40), H5T_NATIVE_INT64);
  expect_input_error(path, "is corrupt: /bonds/connectivity row 100 repeats row 40");
}

TEST_F(SampleFileTest, NonFiniteCoordinateIsCorrupt) {
  const std::string path = written();
  const Point& p = small().sample.lattice.nodes[9];
  set_row(path, "/nodes/coordinates", 9, std::vector<double>{p[0], p[1], NAN}, H5T_NATIVE_DOUBLE);
  expect_input_error(path, "is corrupt: /nodes/coordinates row 9 = (");
  expect_input_error(path, "nan) is not finite");
}
