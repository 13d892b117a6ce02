// A cemented sample built in parallel (build_cemented_sample_block) at 1 to
// 3 ranks: the same sample file, bit for bit in every dataset and statistic,
// on every rank count that divides the ranks of the test; and the same
// Voronoi volumes, bridges, phases and statistics as the serial stages
// (voronoi_volumes, add_matrix) give for its lattice gathered on one rank.
#include "lem/base/collective.hpp"
#include "lem/sample/parallel_sample.hpp"
#include "lem/sample/sample_writer.hpp"
#include "lem/lattice/voronoi.hpp"

#include "../little_sample.hpp"
#include "../world.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

using namespace lem;

namespace {

// The little sample of the sample tests, with the cells generator.
CementedSampleSpec little_spec() {
  CementedSampleSpec spec = little_sample_spec();
  spec.generator = LatticeGenerator::cells;
  return spec;
}

// A folder every rank of the test names alike (rank 0's pid).
std::string test_folder(const std::string& name) {
  int pid = world_rank() == 0 ? static_cast<int>(getpid()) : 0;
  MPI_Bcast(&pid, 1, MPI_INT, 0, PETSC_COMM_WORLD);
  const auto dir = std::filesystem::temp_directory_path() /
                   ("lem_parallel_sample_" + std::to_string(pid) + "_" + name);
  if (world_rank() == 0) std::filesystem::create_directories(dir);
  MPI_Barrier(PETSC_COMM_WORLD);
  return dir.string();
}

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

bool same_statistics(const CementedSampleStats& a, const CementedSampleStats& b) {
  // Everything but the times, compared bit for bit.
  CementedSampleStats x = a, y = b;
  for (auto* s : {&x, &y})
    s->packing_seconds = s->lattice_seconds = s->voronoi_seconds = s->phases_seconds = 0;
  return std::memcmp(&x, &y, sizeof x) == 0;
}

// Every rank of `comm` gets the whole sample of the blocks (a test may gather).
CementedSample gather(MPI_Comm comm, const SampleBlock& b) {
  CementedSample s = b.description.sample;
  s.lattice.nodes = allgather(comm, b.coords);
  s.node_volume = allgather(comm, b.volume);
  s.node_phases.particle = allgather(comm, b.particle);
  s.node_phases.matrix = allgather(comm, b.matrix);
  for (const auto& [i, j] : allgather(comm, b.ends))
    s.lattice.bonds.push_back({static_cast<std::int32_t>(i), static_cast<std::int32_t>(j)});
  s.lattice.stiffness.assign(s.lattice.bonds.size(), 1.0);
  s.bond_phase = allgather(comm, b.bond_phase);
  return s;
}

}  // namespace

TEST(ParallelSample, TheSameFileOnEveryRankCount) {
  const std::string dir = test_folder("ranks");
  std::vector<SampleFile> files;
  for (int size = world_size(); size >= 1; --size) {
    if (world_size() % size != 0) continue;
    MPI_Comm part;
    MPI_Comm_split(PETSC_COMM_WORLD, world_rank() / size, world_rank(), &part);
    SampleBlock b = build_cemented_sample_block(part, little_spec());
    b.description.provenance.program = "test";
    const std::string stem =
        dir + "/np" + std::to_string(size) + "_" + std::to_string(world_rank() / size);
    write_sample_block(part, stem, b);
    MPI_Barrier(PETSC_COMM_WORLD);
    files.push_back(read_sample_file(stem + ".h5"));
    // What was written is what was built.
    const CementedSample whole = gather(part, b);
    const CementedSample& read = files.back().sample;
    EXPECT_TRUE(same_bits(read.lattice.nodes, whole.lattice.nodes));
    EXPECT_TRUE(same_bits(read.node_volume, whole.node_volume));
    EXPECT_TRUE(same_bits(read.bond_phase, whole.bond_phase));
    EXPECT_TRUE(same_statistics(read.stats, b.description.sample.stats));
    EXPECT_EQ(files.back().spec.generator, LatticeGenerator::cells);
    MPI_Comm_free(&part);
  }
  for (std::size_t k = 1; k < files.size(); ++k) {
    const CementedSample &a = files[0].sample, &b = files[k].sample;
    EXPECT_TRUE(same_bits(a.lattice.nodes, b.lattice.nodes)) << "rank count number " << k;
    ASSERT_EQ(a.lattice.bonds.size(), b.lattice.bonds.size());
    for (std::size_t m = 0; m < a.lattice.bonds.size(); ++m)
      ASSERT_TRUE(a.lattice.bonds[m].i == b.lattice.bonds[m].i &&
                  a.lattice.bonds[m].j == b.lattice.bonds[m].j)
          << "bond " << m;
    EXPECT_TRUE(same_bits(a.node_volume, b.node_volume));
    EXPECT_TRUE(same_bits(a.node_phases.particle, b.node_phases.particle));
    EXPECT_TRUE(same_bits(a.node_phases.matrix, b.node_phases.matrix));
    EXPECT_TRUE(same_bits(a.bond_phase, b.bond_phase));
    ASSERT_EQ(a.bridges.size(), b.bridges.size());
    for (std::size_t m = 0; m < a.bridges.size(); ++m)
      EXPECT_EQ(a.bridges[m].lambda, b.bridges[m].lambda) << "bridge " << m;
    EXPECT_TRUE(same_statistics(a.stats, b.stats)) << "rank count number " << k;
  }
  MPI_Barrier(PETSC_COMM_WORLD);
  if (world_rank() == 0) std::filesystem::remove_all(dir);
}

TEST(ParallelSample, AgreesWithTheSerialStagesOnItsLattice) {
  const CementedSampleSpec spec = little_spec();
  const SampleBlock b = build_cemented_sample_block(PETSC_COMM_WORLD, spec);
  const CementedSample parallel = gather(PETSC_COMM_WORLD, b);
  const CementedSampleStats& ps = parallel.stats;
  ASSERT_EQ(static_cast<std::int64_t>(parallel.lattice.node_count()), ps.nodes);
  ASSERT_EQ(static_cast<std::int64_t>(parallel.lattice.bond_count()), ps.bonds);

  // The serial stages on the same lattice and particles.
  CementedSample serial;
  serial.lattice = parallel.lattice;
  serial.particles = parallel.particles;
  serial.stats.sample_particles = ps.sample_particles;
  serial.node_volume = voronoi_volumes(serial.lattice);
  for (std::size_t n = 0; n < serial.node_volume.size(); ++n)
    ASSERT_NEAR(parallel.node_volume[n], serial.node_volume[n], 1e-13 * serial.node_volume[n])
        << "node " << n;
  serial.node_phases =
      AggregateGeometry(serial.lattice.box, serial.particles, {}).classify(serial.lattice.nodes);
  serial.stats.nodes_per_particle =
      static_cast<double>(std::count_if(serial.node_phases.particle.begin(),
                                        serial.node_phases.particle.end(),
                                        [](std::int32_t p) { return p >= 0; })) /
      static_cast<double>(ps.sample_particles);
  add_matrix(serial, spec.bridges);
  const CementedSampleStats& ss = serial.stats;

  ASSERT_EQ(parallel.bridges.size(), serial.bridges.size());
  for (std::size_t k = 0; k < serial.bridges.size(); ++k)
    EXPECT_NEAR(parallel.bridges[k].lambda, serial.bridges[k].lambda, 1e-12) << "bridge " << k;
  EXPECT_EQ(parallel.node_phases.particle, serial.node_phases.particle);
  EXPECT_EQ(parallel.node_phases.matrix, serial.node_phases.matrix);
  EXPECT_EQ(parallel.bond_phase, serial.bond_phase);
  EXPECT_EQ(ps.bonds_per_phase, ss.bonds_per_phase);
  for (const auto& [p, s] : {std::pair{ps.rho_p, ss.rho_p},
                             {ps.rho_m, ss.rho_m},
                             {ps.rho_v, ss.rho_v},
                             {ps.nodes_per_particle, ss.nodes_per_particle},
                             {ps.bonds_per_particle, ss.bonds_per_particle},
                             {ps.interface_ratio, ss.interface_ratio},
                             {ps.eligible_per_particle, ss.eligible_per_particle},
                             {ps.bridges_per_particle, ss.bridges_per_particle}})
    EXPECT_NEAR(p, s, 1e-12 * std::fabs(s));
  for (int k = 0; k < kPhaseCount; ++k)
    EXPECT_NEAR(ps.bond_volume_fraction[k], ss.bond_volume_fraction[k], 1e-12)
        << phase_name(Phase(k));
  EXPECT_EQ(ps.bridges, ss.bridges);
  EXPECT_EQ(ps.eligible_pairs, ss.eligible_pairs);
  // The sample is a real one: calibrated matrix (to the resolution of so
  // small a lattice), volumes filling the cube.
  EXPECT_NEAR(ps.rho_m, spec.bridges.matrix_fraction, 0.01 * spec.bridges.matrix_fraction);
  EXPECT_NEAR(ps.rho_p + ps.rho_m + ps.rho_v, 1.0, 1e-12);
  EXPECT_GT(ps.bonds_per_phase[int(Phase::pm)], 0);
}
