// A small cemented sample end to end: packing -> cube -> lattice -> Voronoi
// volumes -> calibrated bridges -> phases.
#include "lem/cemented_sample.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

using namespace lem;

namespace {
const CementedSample& small_sample() {
  static const CementedSample sample = [] {
    CementedSampleSpec spec;
    spec.packing.count = 400;
    spec.packing.seed = 3;
    spec.sample_particles = 120;
    spec.lattice.bonds = 80000;
    spec.bridges.matrix_fraction = 0.13;
    return build_cemented_sample(spec);
  }();
  return sample;
}
}  // namespace

TEST(CementedSample, VolumesPartitionTheCube) {
  const auto& s = small_sample();
  const double total = std::accumulate(s.node_volume.begin(), s.node_volume.end(), 0.0);
  EXPECT_NEAR(total / s.lattice.box.volume(), 1.0, 1e-10);
  EXPECT_NEAR(s.stats.rho_p + s.stats.rho_m + s.stats.rho_v, 1.0, 1e-10);
}

TEST(CementedSample, MeasuredFractionsMatchTheRequestAndTheGeometry) {
  const auto& s = small_sample();
  EXPECT_NEAR(s.stats.rho_m, 0.13, 0.13e-3);  // calibrated on the lattice
  // The lattice sees the particles as the geometry does, to the resolution.
  EXPECT_NEAR(s.stats.rho_p, s.stats.rho_p_geometric, 0.02);
  EXPECT_GT(s.stats.bonds_per_phase[int(Phase::pm)], 0);
  EXPECT_GT(s.stats.bridges_per_particle, 1.0);
  EXPECT_GT(s.stats.interface_ratio, 0.0);
  EXPECT_LT(s.stats.interface_ratio, 1.0);
}

TEST(CementedSample, BondPhasesFollowTheirEndNodes) {
  const auto& s = small_sample();
  std::int64_t counted = 0;
  for (auto n : s.stats.bonds_per_phase) counted += n;
  EXPECT_EQ(counted, s.stats.bonds);
  for (std::size_t b = 0; b < s.lattice.bond_count(); ++b)
    ASSERT_EQ(s.bond_phase[b], bond_phase(s.node_phases, s.lattice.bonds[b].i, s.lattice.bonds[b].j));
}

TEST(CementedSample, MechanicalLatticeDropsVoidBondsAndUsesPhaseModuli) {
  const auto& s = small_sample();
  PhaseTable table;  // E^p = 3, E^m = E^pm = E^pp = 1 (units k/a)
  const Lattice l = mechanical_lattice(s, table);
  EXPECT_EQ(std::int64_t(l.bond_count()), s.stats.bonds - s.stats.bonds_per_phase[int(Phase::v)]);
  const double a = lattice_stats(s.lattice).mean_length;
  for (double k : l.stiffness) {
    const bool known = std::fabs(k - 3 * a) < 1e-12 || std::fabs(k - a) < 1e-12;
    ASSERT_TRUE(known) << k;
  }
}
