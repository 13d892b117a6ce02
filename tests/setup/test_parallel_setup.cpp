// The parallel set-up of a sample file against the serial one, at 1 to 4
// ranks: the same nodes (positions, volumes, particles, constraint flags),
// the same bonds (ends, stiffness, strength, phase) by id, the same counts;
// stiffnesses and strengths to 1e-14 (a, the mean bond length, is summed in
// another order).
#include "lem/setup/parallel_setup.hpp"
#include "lem/base/collective.hpp"
#include "lem/setup/setup.hpp"

#include "../world.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

using namespace lem;

namespace {

struct NodeRow {
  std::int64_t id;
  Point x;
  double volume;
  std::int32_t particle;
  std::uint8_t flags, faces, pad[2];
};

struct BondRow {
  std::int64_t id, i, j;
  double k, f;
  std::uint8_t tag, pad[7];
};

// Every rank's owned nodes and reported bonds, by id (a test may gather).
void collect(const DistributedLattice& l, std::vector<NodeRow>& nodes,
             std::vector<BondRow>& bonds) {
  std::vector<NodeRow> my_nodes;
  for (int n = 0; n < l.owned; ++n)
    my_nodes.push_back({l.node_id[n],
                        l.coords[n],
                        l.node_volume[n],
                        l.node_particle[n],
                        l.dof_flags[n],
                        l.faces[n],
                        {0, 0}});
  std::vector<BondRow> my_bonds;
  for (int b = 0; b < l.local_bonds(); ++b)
    if (l.bond_reported[b]) {
      const auto [p, q] = l.bond_ends[b];
      std::int64_t i = l.node_id[p], j = l.node_id[q];
      if (i > j) std::swap(i, j);
      my_bonds.push_back(
          {l.bond_id[b], i, j, l.bond_stiffness[b], l.bond_strength[b], l.bond_tag[b], {0}});
    }
  nodes = allgather(PETSC_COMM_WORLD, my_nodes);
  bonds = allgather(PETSC_COMM_WORLD, my_bonds);
  std::sort(nodes.begin(), nodes.end(), [](auto& a, auto& b) { return a.id < b.id; });
  std::sort(bonds.begin(), bonds.end(), [](auto& a, auto& b) { return a.id < b.id; });
}

void expect_same_setup(const SampleOptions& options) {
  SetupReport serial_report, parallel_report;
  const DistributedLattice serial = setup_tension_lattice(
      PETSC_COMM_WORLD, [&](SampleInfo& info) { return build_sample(options, info); },
      serial_report);
  const DistributedLattice parallel =
      setup_sample_in_parallel(PETSC_COMM_WORLD, options, parallel_report);

  EXPECT_EQ(parallel.global_nodes, serial.global_nodes);
  EXPECT_EQ(parallel.global_bonds, serial.global_bonds);
  EXPECT_NEAR(parallel.mean_bond_length, serial.mean_bond_length, 1e-14 * serial.mean_bond_length);
  EXPECT_EQ(parallel_report.active_bonds, serial_report.active_bonds);
  EXPECT_EQ(parallel_report.pruned_bonds, serial_report.pruned_bonds);
  EXPECT_EQ(parallel_report.pinned_nodes, serial_report.pinned_nodes);
  EXPECT_EQ(parallel_report.bottom_nodes, serial_report.bottom_nodes);
  EXPECT_EQ(parallel_report.top_nodes, serial_report.top_nodes);
  const LatticeStats &ps = parallel_report.sample.stats, &ss = serial_report.sample.stats;
  EXPECT_EQ(ps.nodes, ss.nodes);
  EXPECT_EQ(ps.bonds, ss.bonds);
  EXPECT_NEAR(ps.mean_length, ss.mean_length, 1e-14 * ss.mean_length);
  EXPECT_NEAR(ps.std_length, ss.std_length, 1e-9 * ss.std_length);
  EXPECT_EQ(ps.min_length, ss.min_length);
  EXPECT_EQ(ps.max_length, ss.max_length);
  EXPECT_NEAR(parallel_report.sample.affine.young_z, serial_report.sample.affine.young_z,
              1e-12 * serial_report.sample.affine.young_z);
  EXPECT_EQ(parallel_report.sample.cemented.rho_m, serial_report.sample.cemented.rho_m);

  std::vector<NodeRow> pn, sn;
  std::vector<BondRow> pb, sb;
  collect(parallel, pn, pb);
  collect(serial, sn, sb);
  ASSERT_EQ(pn.size(), sn.size());
  for (std::size_t k = 0; k < pn.size(); ++k) {
    ASSERT_EQ(pn[k].id, sn[k].id);
    EXPECT_EQ(pn[k].x, sn[k].x) << "node " << sn[k].id;
    EXPECT_EQ(pn[k].volume, sn[k].volume) << "node " << sn[k].id;
    EXPECT_EQ(pn[k].particle, sn[k].particle) << "node " << sn[k].id;
    EXPECT_EQ(pn[k].faces, sn[k].faces) << "node " << sn[k].id;
    EXPECT_EQ(int(pn[k].flags), int(sn[k].flags)) << "node " << sn[k].id;
  }
  ASSERT_EQ(pb.size(), sb.size());
  for (std::size_t k = 0; k < pb.size(); ++k) {
    ASSERT_EQ(pb[k].id, sb[k].id);
    EXPECT_EQ(pb[k].i, sb[k].i) << "bond " << sb[k].id;
    EXPECT_EQ(pb[k].j, sb[k].j) << "bond " << sb[k].id;
    EXPECT_NEAR(pb[k].k, sb[k].k, 1e-14 * sb[k].k) << "bond " << sb[k].id;
    EXPECT_NEAR(pb[k].f, sb[k].f, 1e-14 * std::fabs(sb[k].f)) << "bond " << sb[k].id;
    EXPECT_EQ(pb[k].tag, sb[k].tag) << "bond " << sb[k].id;
  }
}

}  // namespace

TEST(ParallelSetup, SameLatticeAsTheSerialSetUp) {
  SampleOptions options;
  options.sample_file = LEM_MESHES "/mini.h5";
  expect_same_setup(options);
}

TEST(ParallelSetup, SameHomogeneousLatticeWithHalvedFaceBonds) {
  // The calibration's lattice (every bond of the particle phase, void ones
  // too) with the face bonds halved.
  SampleOptions options;
  options.sample_file = LEM_MESHES "/mini.h5";
  options.homogeneous = true;
  options.halve_face_bonds = true;
  expect_same_setup(options);
}
