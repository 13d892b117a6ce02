// A small cemented sample end to end: packing -> cube -> lattice -> Voronoi
// volumes -> calibrated bridges -> phases.
#include "lem/sample/cemented_sample.hpp"
#include "lem/base/error.hpp"

#include "../little_sample.hpp"

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

CementedSampleSpec little_spec() { return little_sample_spec(); }
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
    ASSERT_EQ(s.bond_phase[b],
              bond_phase(s.node_phases, s.lattice.bonds[b].i, s.lattice.bonds[b].j));
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

TEST(CementedSample, BondVolumesPartitionTheCubeAndFollowTheNodes) {
  const auto& s = small_sample();
  double total = 0;
  for (double f : s.stats.bond_volume_fraction) total += f;
  EXPECT_NEAR(total, 1.0, 1e-10);
  // Interface bonds take a share of the particles' volume (at this coarse
  // resolution a large one): fewer p bonds by volume than particle nodes.
  const auto& f = s.stats.bond_volume_fraction;
  EXPECT_LT(f[int(Phase::p)], s.stats.rho_p);
  EXPECT_GT(f[int(Phase::p)] + f[int(Phase::pp)] + f[int(Phase::pm)], 0.5 * s.stats.rho_p);
  EXPECT_GT(f[int(Phase::pp)], 0.0);
  EXPECT_LT(f[int(Phase::pp)], 0.1);
}

TEST(CementedSample, MatrixStageCanBeRepeatedOnTheSameGeometry) {
  CementedSample s = small_sample();
  const auto p_before = s.stats.rho_p;
  BridgeSpec more;
  more.matrix_fraction = 0.2;
  add_matrix(s, more);
  EXPECT_NEAR(s.stats.rho_m, 0.2, 0.2e-3);
  EXPECT_DOUBLE_EQ(s.stats.rho_p, p_before);                                 // particles untouched
  EXPECT_GT(s.stats.interface_ratio, small_sample().stats.interface_ratio);  // more coverage
  BridgeSpec back;
  back.matrix_fraction = 0.13;
  add_matrix(s, back);
  EXPECT_EQ(s.bond_phase, small_sample().bond_phase);  // nothing left over from 0.2
}

TEST(CementedSample, VoidRulesDifferOnlyInBondsWithOneEndInAPore) {
  // The same sample made with both rules: the nodes, bridges and interface
  // bonds agree; any_end voids every bond with an end in a pore, both_ends
  // only those with both ends there and gives the others to p or m.
  CementedSampleSpec spec = little_spec();
  const CementedSample any = build_cemented_sample(spec);
  spec.bridges.void_bonds = VoidRule::both_ends;
  const CementedSample both = build_cemented_sample(spec);
  ASSERT_EQ(any.node_phases.particle, both.node_phases.particle);
  ASSERT_EQ(any.node_phases.matrix, both.node_phases.matrix);
  const NodePhases& np = any.node_phases;
  auto is_void = [&](std::int32_t n) { return np.particle[n] < 0 && !np.matrix[n]; };
  // Bonds with two void ends, and with one whose other end is in a
  // particle [0] or in the matrix [1].
  std::int64_t two_void = 0, one_void[2] = {0, 0};
  for (const auto& [i, j] : any.lattice.bonds) {
    if (is_void(i) && is_void(j))
      ++two_void;
    else if (is_void(i) || is_void(j))
      ++one_void[np.particle[is_void(i) ? j : i] >= 0 ? 0 : 1];
  }
  const auto& a = any.stats.bonds_per_phase;
  const auto& c = both.stats.bonds_per_phase;
  EXPECT_GT(one_void[0], 0);
  EXPECT_GT(one_void[1], 0);
  EXPECT_EQ(a[int(Phase::v)], two_void + one_void[0] + one_void[1]);
  EXPECT_EQ(c[int(Phase::v)], two_void);
  EXPECT_EQ(c[int(Phase::p)], a[int(Phase::p)] + one_void[0]);
  EXPECT_EQ(c[int(Phase::m)], a[int(Phase::m)] + one_void[1]);
  EXPECT_EQ(c[int(Phase::pp)], a[int(Phase::pp)]);
  EXPECT_EQ(c[int(Phase::pm)], a[int(Phase::pm)]);
  EXPECT_EQ(any.stats.rho_v, both.stats.rho_v);  // node volumes do not see the rule
}

TEST(CementedSample, ReproducibleWithSeeds) {
  CementedSampleSpec spec = little_spec();
  const CementedSample a = build_cemented_sample(spec), b = build_cemented_sample(spec);
  EXPECT_EQ(a.lattice.nodes, b.lattice.nodes);
  EXPECT_EQ(a.bond_phase, b.bond_phase);
  ASSERT_EQ(a.bridges.size(), b.bridges.size());
  for (std::size_t k = 0; k < a.bridges.size(); ++k)
    EXPECT_EQ(a.bridges[k].lambda, b.bridges[k].lambda);
  spec.packing.seed = 6;
  EXPECT_NE(build_cemented_sample(spec).particles[0].centre, a.particles[0].centre);
}

TEST(CementedSample, TooSmallOrTooCoarseIsAnInputError) {
  CementedSampleSpec spec;
  spec.packing.count = 100;
  spec.lattice.bonds = 20000;
  spec.sample_particles = 4;
  EXPECT_THROW(build_granular_sample(spec), InputError);
  spec.sample_particles = 200;  // more than the packing holds
  EXPECT_THROW(build_granular_sample(spec), InputError);
  spec.sample_particles = 64;
  spec.lattice.bonds = 5000;  // ~10 nodes per particle
  try {
    build_granular_sample(spec);
    FAIL() << "a coarse lattice was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("too coarse"), std::string::npos) << e.what();
  }
  spec.lattice.bonds = 40000;
  spec.packing.d_max = 0.9;  // below d_min
  EXPECT_THROW(build_granular_sample(spec), InputError);
}
