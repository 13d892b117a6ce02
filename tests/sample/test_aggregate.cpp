// Matrix bridges and phases: bridge volume against a closed form, pair
// search against brute force, the phase table and the two void rules on a
// hand-made two-particle sample, and the calibration of the matrix fraction.
#include "lem/sample/aggregate.hpp"
#include "lem/base/error.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <random>

using namespace lem;

namespace {
// Volume of a unit-free ball of radius r inside a coaxial cylinder of radius
// rho, on one side of its centre plane.
double half_ball_in_cylinder(double r, double rho) {
  const double s0 = std::sqrt(r * r - rho * rho);
  return std::numbers::pi *
         (rho * rho * s0 + (r * r * r - r * r * r / 3) - (r * r * s0 - s0 * s0 * s0 / 3));
}
}  // namespace

TEST(Bridge, VolumeOfEqualSpheresMatchesClosedForm) {
  // Equal spheres: the frustum is a cylinder of radius lambda r.
  const double r = 0.5, gap = 0.3;
  const Sphere a{{0, 0, 0}, r}, b{{2 * r + gap, 0, 0}, r};
  for (double lambda : {0.2, 0.5, 0.9}) {
    const double rho = lambda * r, length = 2 * r + gap;
    const double exact = std::numbers::pi * rho * rho * length - 2 * half_ball_in_cylinder(r, rho);
    EXPECT_NEAR(bridge_volume(a, b, lambda), exact, 1e-6 * exact) << "lambda " << lambda;
  }
  // Monotone in lambda.
  EXPECT_LT(bridge_volume(a, b, 0.5), bridge_volume(a, b, 0.6));
}

TEST(Bridge, EligiblePairsMatchBruteForce) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0, 5), d(0.5, 0.625);
  std::vector<Sphere> s;
  for (int k = 0; k < 300; ++k) s.push_back({{u(rng), u(rng), u(rng)}, d(rng)});
  const auto pairs = eligible_pairs(s, 0.5);
  std::size_t brute = 0;
  for (std::size_t i = 0; i < s.size(); ++i)
    for (std::size_t j = i + 1; j < s.size(); ++j) {
      const double dx = s[i].centre[0] - s[j].centre[0], dy = s[i].centre[1] - s[j].centre[1],
                   dz = s[i].centre[2] - s[j].centre[2];
      brute += std::sqrt(dx * dx + dy * dy + dz * dz) - s[i].radius - s[j].radius <= 0.5;
    }
  EXPECT_EQ(pairs.size(), brute);
  for (const auto& p : pairs) EXPECT_LT(p.i, p.j);
}

TEST(Phases, HandMadeTwoParticleSample) {
  Box box;
  box.hi = {3, 2, 2};
  const std::vector<Sphere> particles{{{0.9, 1, 1}, 0.5}, {{2.1, 1, 1}, 0.5}};  // gap 0.2
  AggregateGeometry g(box, particles, {Bridge{0, 1, 0.6}});
  const std::vector<Point> nodes{
      {0.9, 1, 1},     // 0: particle 0
      {0.7, 1, 1},     // 1: particle 0
      {2.1, 1, 1},     // 2: particle 1
      {1.5, 1, 1},     // 3: matrix (bridge axis, between the particles)
      {1.5, 1.25, 1},  // 4: matrix (radius 0.3 there)
      {1.5, 1.4, 1},   // 5: void (outside the bridge)
      {0.2, 0.2, 0.2}  // 6: void
  };
  const NodePhases np = g.classify(nodes);
  EXPECT_EQ(np.particle[0], 0);
  EXPECT_EQ(np.particle[2], 1);
  EXPECT_TRUE(np.matrix[3]);
  EXPECT_TRUE(np.matrix[4]);
  EXPECT_FALSE(np.matrix[5]);
  EXPECT_EQ(bond_phase(np, 0, 1), Phase::p);
  EXPECT_EQ(bond_phase(np, 0, 2), Phase::pp);
  EXPECT_EQ(bond_phase(np, 0, 3), Phase::pm);
  EXPECT_EQ(bond_phase(np, 3, 2), Phase::pm);
  EXPECT_EQ(bond_phase(np, 3, 4), Phase::m);
  EXPECT_EQ(bond_phase(np, 4, 5), Phase::v);
  EXPECT_EQ(bond_phase(np, 0, 6), Phase::v);
  EXPECT_STREQ(phase_name(Phase::pm), "pm");
}

TEST(Phases, VoidRulesOnTheHandMadeSample) {
  // The sample above with every pair of its seven nodes bonded (21 bonds):
  // particle 0 {0, 1}, particle 1 {2}, matrix {3, 4}, void {5, 6}.
  Box box;
  box.hi = {3, 2, 2};
  const std::vector<Sphere> particles{{{0.9, 1, 1}, 0.5}, {{2.1, 1, 1}, 0.5}};
  const NodePhases np = AggregateGeometry(box, particles, {Bridge{0, 1, 0.6}})
                            .classify({{0.9, 1, 1},
                                       {0.7, 1, 1},
                                       {2.1, 1, 1},
                                       {1.5, 1, 1},
                                       {1.5, 1.25, 1},
                                       {1.5, 1.4, 1},
                                       {0.2, 0.2, 0.2}});
  auto counts = [&](VoidRule rule) {
    std::array<int, kPhaseCount> n{};
    for (std::int32_t a = 0; a < 7; ++a)
      for (std::int32_t b = a + 1; b < 7; ++b) ++n[static_cast<int>(bond_phase(np, a, b, rule))];
    return n;
  };
  // any_end: the 6 particle-void, 4 matrix-void and 1 void-void bonds are void.
  const auto any = counts(VoidRule::any_end);
  EXPECT_EQ(any[int(Phase::p)], 1);
  EXPECT_EQ(any[int(Phase::pp)], 2);
  EXPECT_EQ(any[int(Phase::pm)], 6);
  EXPECT_EQ(any[int(Phase::m)], 1);
  EXPECT_EQ(any[int(Phase::v)], 11);
  // both_ends: only the void-void bond; particle-void bonds are p, matrix-void m.
  const auto both = counts(VoidRule::both_ends);
  EXPECT_EQ(both[int(Phase::p)], 1 + 6);
  EXPECT_EQ(both[int(Phase::pp)], 2);
  EXPECT_EQ(both[int(Phase::pm)], 6);
  EXPECT_EQ(both[int(Phase::m)], 1 + 4);
  EXPECT_EQ(both[int(Phase::v)], 1);
  EXPECT_EQ(bond_phase(np, 6, 0, VoidRule::both_ends), Phase::p);  // either order
  EXPECT_EQ(bond_phase(np, 5, 4, VoidRule::both_ends), Phase::m);
  EXPECT_EQ(bond_phase(np, 0, 6), bond_phase(np, 0, 6, VoidRule::any_end));  // the default
  EXPECT_STREQ(void_rule_name(VoidRule::any_end), "any_end");
  EXPECT_STREQ(void_rule_name(VoidRule::both_ends), "both_ends");
}

namespace {
// Simple cubic arrangement of 27 equal spheres with gaps, and a point
// estimate of the matrix fraction (the role Voronoi-weighted nodes play in a
// real sample).
struct CubicSample {
  Box box;
  std::vector<Sphere> particles;
  std::vector<Point> grid;
  CubicSample() {
    box.hi = {3.3, 3.3, 3.3};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k)
          particles.push_back({{0.55 + 1.1 * i, 0.55 + 1.1 * j, 0.55 + 1.1 * k}, 0.5});
    // Random points: a regular grid aligned with the bridges would measure
    // the fraction in coarse steps.
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<double> u(0.0, 3.3);
    for (int k = 0; k < 200000; ++k) grid.push_back({u(rng), u(rng), u(rng)});
  }
  double matrix_fraction(const std::vector<Bridge>& bridges) const {
    const AggregateGeometry g(box, particles, bridges);
    std::size_t in = 0;
    for (const auto& x : grid) in += g.particle_at(x) < 0 && g.matrix_at(x);
    return double(in) / double(grid.size());
  }
};
}  // namespace

TEST(Calibration, ReachesTheRequestedMatrixFraction) {
  const CubicSample s;
  BridgeSpec spec;
  spec.max_gap = 0.15;  // only the 54 face-to-face neighbour pairs
  for (double target : {0.03, 0.10}) {
    spec.matrix_fraction = target;
    const auto cal = calibrate_bridges(
        s.box, s.particles, spec, [&](const auto& b) { return s.matrix_fraction(b); }, 1e-3);
    EXPECT_EQ(cal.bridges.size(), 54u);
    EXPECT_NEAR(cal.matrix_fraction, target, 1e-3 * target);
    EXPECT_NEAR(s.matrix_fraction(cal.bridges), target, 1e-3 * target);
  }
}

TEST(Calibration, TooMuchMatrixIsAnInputError) {
  const CubicSample s;
  BridgeSpec spec;
  spec.max_gap = 0.15;
  spec.max_lambda = 1.0;
  spec.matrix_fraction = 0.45;  // more than the pore space holds (1 - 0.393)
  EXPECT_THROW(calibrate_bridges(s.box, s.particles, spec,
                                 [&](const auto& b) { return s.matrix_fraction(b); }),
               InputError);
  spec.max_gap = 0.01;  // no pair close enough
  spec.matrix_fraction = 0.1;
  EXPECT_THROW(calibrate_bridges(s.box, s.particles, spec,
                                 [&](const auto& b) { return s.matrix_fraction(b); }),
               InputError);
}
