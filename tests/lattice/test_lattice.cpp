// Lattice stage: random and FCC generators, affine moduli, inclusions,
// partition and tension constraints (all serial).
#include "lem/base/error.hpp"
#include "lem/lattice/inclusions.hpp"
#include "lem/lattice/lattice.hpp"
#include "lem/system/partition.hpp"
#include "lem/system/tension.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

using namespace lem;

namespace {
RandomLatticeSpec small_spec(std::int64_t nodes, std::uint64_t seed = 3) {
  RandomLatticeSpec s;
  s.nodes = nodes;
  s.seed = seed;
  return s;
}
double distance(const Point& p, const Point& q) {
  return std::sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                   (p[2] - q[2]) * (p[2] - q[2]));
}
}  // namespace

TEST(RandomLattice, SizeSeparationAndBondList) {
  const auto spec = small_spec(3000);
  const Lattice l = make_random_lattice(spec);
  ASSERT_EQ(l.node_count(), 3000u);
  // Minimum separation, checked by brute force.
  const double rmin = spec.min_separation * std::cbrt(1.0 / 3000.0);
  double closest = 1e9;
  for (std::size_t i = 0; i < l.node_count(); ++i)
    for (std::size_t j = i + 1; j < l.node_count(); ++j)
      closest = std::min(closest, distance(l.nodes[i], l.nodes[j]));
  EXPECT_GE(closest, rmin);
  // Bonds unique, i < j, sorted, every node bonded.
  EXPECT_TRUE(std::is_sorted(l.bonds.begin(), l.bonds.end()));
  EXPECT_EQ(std::adjacent_find(l.bonds.begin(), l.bonds.end()), l.bonds.end());
  std::vector<int> degree(l.node_count(), 0);
  for (const auto& b : l.bonds) {
    EXPECT_LT(b.i, b.j);
    ++degree[b.i];
    ++degree[b.j];
  }
  EXPECT_GE(*std::min_element(degree.begin(), degree.end()), 3);
  // A 3D Delaunay tetrahedralisation: Euler's relation for a ball,
  // V - E + F - T = 1, cannot be checked without faces; check the mean
  // coordination instead (about 14-15 for hard-core points, lower at faces).
  const auto stats = lattice_stats(l);
  EXPECT_GT(stats.mean_coordination, 12.5);
  EXPECT_LT(stats.mean_coordination, 15.5);
}

TEST(RandomLattice, EveryFaceIsPopulatedAndFlat) {
  const Lattice l = make_random_lattice(small_spec(4000));
  const auto faces = face_flags(l);
  for (std::uint8_t f : {kXmin, kXmax, kYmin, kYmax, kZmin, kZmax}) {
    const auto n = std::count_if(faces.begin(), faces.end(), [&](auto x) { return x & f; });
    // about (N^(1/3))^2 = 252 points per face
    EXPECT_GT(n, 150) << "face " << int(f);
  }
  // All 8 corners are nodes.
  const auto corners = std::count_if(faces.begin(), faces.end(),
                                     [](auto x) { return std::popcount(unsigned(x)) == 3; });
  EXPECT_EQ(corners, 8);
}

TEST(RandomLattice, HalvingFaceBondsTakesHalfPerFaceTheBondLiesIn) {
  Lattice l = make_random_lattice(small_spec(2000));
  l.strength.assign(l.bond_count(), 3.0);
  const Lattice whole = l;
  halve_face_bonds(l);
  int in_one_face = 0, on_an_edge = 0;
  for (std::size_t b = 0; b < l.bond_count(); ++b) {
    // From the coordinates: the faces both ends lie on.
    const Point& p = l.nodes[l.bonds[b].i];
    const Point& q = l.nodes[l.bonds[b].j];
    int faces = 0;
    for (int a = 0; a < 3; ++a)
      for (double side : {l.box.lo[a], l.box.hi[a]}) faces += p[a] == side && q[a] == side;
    const double share = faces == 0 ? 1.0 : faces == 1 ? 0.5 : 0.25;
    EXPECT_EQ(l.stiffness[b], share * whole.stiffness[b]) << "bond " << b;
    EXPECT_EQ(l.strength[b], share * whole.strength[b]) << "bond " << b;
    in_one_face += faces == 1;
    on_an_edge += faces == 2;
  }
  // About 6 faces x 3 x (N^(1/3))^2 bonds; 12 edges x N^(1/3).
  EXPECT_GT(in_one_face, 1000);
  EXPECT_GT(on_an_edge, 50);
}

TEST(RandomLattice, ReproducibleWithSeed) {
  const Lattice a = make_random_lattice(small_spec(500, 11));
  const Lattice b = make_random_lattice(small_spec(500, 11));
  const Lattice c = make_random_lattice(small_spec(500, 12));
  EXPECT_EQ(a.nodes, b.nodes);
  EXPECT_TRUE(a.bonds == b.bonds);
  EXPECT_NE(a.nodes, c.nodes);
}

TEST(RandomLattice, SizedByBondsOrMeshDensity) {
  RandomLatticeSpec s;
  s.bonds = 50000;
  const auto stats = lattice_stats(make_random_lattice(s));
  EXPECT_NEAR(double(stats.bonds), 50000.0, 0.05 * 50000);
  RandomLatticeSpec t;
  t.mesh_density = 0.03;  // M = 37037
  const auto st = lattice_stats(make_random_lattice(t));
  EXPECT_NEAR(st.mesh_density, 0.03, 0.03 * 0.03);
}

TEST(RandomLattice, BadSizesAreInputErrors) {
  EXPECT_THROW(make_random_lattice(small_spec(0)), InputError);
  EXPECT_THROW(make_random_lattice(small_spec(5)), InputError);  // box too small
  RandomLatticeSpec s = small_spec(1000);
  s.box.hi = {1.0, 1.0, 0.05};  // thinner than two spacings
  EXPECT_THROW(make_random_lattice(s), InputError);
}

TEST(FccLattice, CountsAndAffineModuli) {
  const int n = 3;
  const Lattice l = make_fcc_lattice({n, n, n}, 1.0, 2.0);
  // Sites of a (2n+1)^3 grid with even coordinate sum.
  const int g = 2 * n + 1;
  EXPECT_EQ(l.node_count(), std::size_t((g * g * g + 1) / 2));
  const auto stats = lattice_stats(l);
  EXPECT_DOUBLE_EQ(stats.mean_length, 1.0);
  // With face bonds at half stiffness the block is an exact share of the
  // infinite lattice: C11 = sqrt2 k/a, C12 = C44 = k/(sqrt2 a) (docs/model/theory.md).
  const AffineModuli m = affine_moduli(l);
  const double k = 2.0;
  EXPECT_NEAR(m.C[0][0], std::sqrt(2.0) * k, 1e-12);
  EXPECT_NEAR(m.C[0][1], k / std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(m.C[3][3], k / std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(m.C[0][3], 0.0, 1e-12);
  EXPECT_NEAR(m.young_z, 2.0 * std::sqrt(2.0) / 3.0 * k, 1e-12);
  EXPECT_NEAR(m.poisson_z, 1.0 / 3.0, 1e-12);
}

TEST(AffineModuli, RandomLatticeIsNearlyIsotropic) {
  const Lattice l = make_random_lattice(small_spec(20000, 5));
  const AffineModuli m = affine_moduli(l);
  // Isotropic bond orientations: C11 = 3 C12 and nu = 1/4 (appendix B).
  EXPECT_NEAR(m.C[0][0] / m.C[0][1], 3.0, 0.15);
  EXPECT_NEAR(m.poisson_z, 0.25, 0.02);
}

TEST(Inclusions, ExactFractionNoOverlapAndErrors) {
  Box box;
  const Inclusions inc = place_inclusions(box, InclusionSpec{0.2, 0.1, 4});
  EXPECT_NEAR(inc.volume_fraction(), 0.2, 0.2 / 48);  // whole spheres: within one sphere
  for (std::size_t i = 0; i < inc.centres.size(); ++i)
    for (std::size_t j = i + 1; j < inc.centres.size(); ++j) {
      double d2 = 0;
      for (int a = 0; a < 3; ++a) {
        double d = std::fabs(inc.centres[i][a] - inc.centres[j][a]);
        d = std::min(d, 1.0 - d);
        d2 += d * d;
      }
      EXPECT_GE(std::sqrt(d2), 2 * inc.radius);
    }
  EXPECT_THROW(place_inclusions(box, InclusionSpec{0.6, 0.1, 4}), InputError);
  EXPECT_THROW(place_inclusions(box, InclusionSpec{0.2, 0.6, 4}), InputError);
  // The node fraction inside estimates the volume fraction.
  const Lattice l = make_random_lattice(small_spec(20000));
  EXPECT_NEAR(node_fraction_inside(l, inc), inc.volume_fraction(), 0.02);
}

TEST(Inclusions, StiffenAndCarve) {
  Lattice l = make_random_lattice(small_spec(3000));
  const Inclusions inc = place_inclusions(l.box, InclusionSpec{0.2, 0.15, 9});
  Lattice stiff = l;
  stiffen_inclusions(stiff, inc, 10.0);
  Lattice porous = l;
  carve_pores(porous, inc);
  std::size_t inside = 0, touching = 0;
  for (const auto& b : l.bonds) {
    const bool pi = inc.contains(l.nodes[b.i]), pj = inc.contains(l.nodes[b.j]);
    inside += pi && pj;
    touching += pi || pj;
  }
  EXPECT_EQ(std::count(stiff.stiffness.begin(), stiff.stiffness.end(), 10.0), long(inside));
  EXPECT_EQ(porous.bond_count(), l.bond_count() - touching);
  EXPECT_TRUE(std::is_sorted(porous.bonds.begin(), porous.bonds.end()));
}

TEST(Partition, BlocksArePermutationAndContiguous) {
  const Lattice l = make_random_lattice(small_spec(5000));
  for (int parts : {1, 2, 3}) {
    const Partition p = partition_lattice(l, {}, parts);
    std::vector<std::int64_t> sorted = p.new_index;
    std::sort(sorted.begin(), sorted.end());
    for (std::size_t k = 0; k < sorted.size(); ++k) ASSERT_EQ(sorted[k], std::int64_t(k));
    for (std::size_t n = 0; n < l.node_count(); ++n) {
      EXPECT_GE(p.new_index[n], p.offsets[p.owner[n]]);
      EXPECT_LT(p.new_index[n], p.offsets[p.owner[n] + 1]);
    }
    // Balanced within METIS' default 3% imbalance (plus rounding).
    for (int r = 0; r < parts; ++r)
      EXPECT_LE(p.offsets[r + 1] - p.offsets[r], std::int64_t(1.04 * 5000 / parts + 2));
    if (parts > 1) {
      EXPECT_LT(p.edge_cut, std::int64_t(l.bond_count() / 5));
    }
  }
}

TEST(Partition, MortonOrderFollowsTheCurve) {
  Box box;
  EXPECT_LT(morton_code({0.1, 0.1, 0.1}, box), morton_code({0.9, 0.1, 0.1}, box));
  EXPECT_LT(morton_code({0.9, 0.9, 0.1}, box), morton_code({0.1, 0.1, 0.9}, box));
  EXPECT_EQ(morton_code({0, 0, 0}, box), 0u);
}

namespace {
// A unit cube split into 6 tetrahedra around the diagonal, plus a dangling
// node joined by one bond and a separate floating pair.
Lattice hand_made_lattice() {
  Lattice l;
  for (int c = 0; c < 8; ++c)
    l.nodes.push_back({double(c & 1), double((c >> 1) & 1), double((c >> 2) & 1)});
  l.nodes.push_back({0.5, 0.5, 0.5});  // 8: dangling, bonded to 0 only
  l.nodes.push_back({0.3, 0.3, 0.4});  // 9, 10: floating pair
  l.nodes.push_back({0.3, 0.4, 0.4});
  // cube edges + face diagonals from node 0 and the long diagonal 0-7
  const int pairs[][2] = {{0, 1}, {0, 2}, {0, 4}, {1, 3}, {1, 5}, {2, 3}, {2, 6}, {3, 7},
                          {4, 5}, {4, 6}, {5, 7}, {6, 7}, {0, 3}, {0, 5}, {0, 6}, {3, 5},
                          {3, 6}, {5, 6}, {0, 7}, {1, 7}, {2, 7}, {4, 7}, {0, 8}, {9, 10}};
  for (const auto& p : pairs) l.bonds.push_back(Bond{p[0], p[1]});
  std::sort(l.bonds.begin(), l.bonds.end());
  l.stiffness.assign(l.bonds.size(), 1.0);
  return l;
}
}  // namespace

TEST(TensionConstraints, PrunesZeroForceBondsAndAnchorsOnce) {
  const Lattice l = hand_made_lattice();
  const auto faces = face_flags(l);
  const TensionConstraints tc = make_tension_constraints(l, faces);
  EXPECT_EQ(tc.pinned_nodes, 3);  // dangling node and floating pair
  EXPECT_EQ(tc.pruned_bonds, 2);
  EXPECT_EQ(tc.loaded_pieces, 1);
  EXPECT_EQ(tc.bottom_nodes, 4);
  EXPECT_EQ(tc.top_nodes, 4);
  int x = 0, y = 0;
  for (std::size_t n = 0; n < 8; ++n) {
    x += (tc.dof_flags[n] & kFixX) != 0;
    y += (tc.dof_flags[n] & kFixY) != 0;
    EXPECT_TRUE(tc.dof_flags[n] & kFixZ);
    EXPECT_EQ(bool(tc.dof_flags[n] & kLoadedTop), l.nodes[n][2] == 1.0);
  }
  EXPECT_EQ(x + y, 3);  // exactly three in-plane constraints
}

TEST(TensionConstraints, DisconnectedSampleIsAnInputError) {
  Lattice l = hand_made_lattice();
  // Remove every bond reaching the top face.
  std::vector<Bond> kept;
  for (const auto& b : l.bonds)
    if (l.nodes[b.i][2] < 1 && l.nodes[b.j][2] < 1) kept.push_back(b);
  l.bonds = kept;
  l.stiffness.assign(kept.size(), 1.0);
  EXPECT_THROW(make_tension_constraints(l, face_flags(l)), InputError);
}
