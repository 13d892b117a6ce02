// Packing stage: jammed periodic packings, the cubic sample cut out of one,
// and the clipped sphere volume (all serial).
#include "lem/base/error.hpp"
#include "lem/packing/packing.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>

using namespace lem;

namespace {

constexpr double kPi = 3.14159265358979323846;

PackingSpec spec_of(std::int64_t count, std::uint64_t seed) {
  PackingSpec s;
  s.count = count;
  s.seed = seed;
  return s;
}

// One 600-sphere packing with the paper's distribution, shared by the tests.
const Packing& paper_packing() {
  static const Packing p = make_packing(spec_of(600, 11));
  return p;
}

double periodic_distance(const Point& a, const Point& b, double L) {
  double s = 0;
  for (int k = 0; k < 3; ++k) {
    double d = std::fabs(a[k] - b[k]);
    d = std::min(d, L - d);
    s += d * d;
  }
  return std::sqrt(s);
}

double uniform(std::mt19937_64& g) { return static_cast<double>(g() >> 11) * 0x1.0p-53; }

}  // namespace

TEST(Packing, JammedDenseAndNoOverlap) {
  const Packing& p = paper_packing();
  ASSERT_EQ(p.spheres.size(), 600u);
  EXPECT_GE(p.stats.volume_fraction, 0.62);
  EXPECT_LE(p.stats.volume_fraction, 0.66);

  // Brute force over all pairs (minimum image): overlaps and contacts.
  const double L = p.box_side;
  double solid = 0, dsum = 0;
  for (const auto& s : p.spheres) {
    solid += 4.0 / 3.0 * kPi * s.radius * s.radius * s.radius;
    dsum += 2 * s.radius;
    for (int k = 0; k < 3; ++k) {
      EXPECT_GE(s.centre[k], 0.0);
      EXPECT_LT(s.centre[k], L);
    }
  }
  const double d_mean = dsum / 600.0;
  EXPECT_NEAR(solid / (L * L * L), p.stats.volume_fraction, 1e-12);
  double max_overlap = 0, sum_overlap = 0;
  std::int64_t overlapping = 0, contacts = 0;
  for (std::size_t i = 0; i < p.spheres.size(); ++i)
    for (std::size_t j = i + 1; j < p.spheres.size(); ++j) {
      const double s = p.spheres[i].radius + p.spheres[j].radius;
      const double d = periodic_distance(p.spheres[i].centre, p.spheres[j].centre, L);
      if (d - s < 1e-3 * d_mean) ++contacts;
      if (d < s) {
        ++overlapping;
        sum_overlap += (s - d) / s;
        max_overlap = std::max(max_overlap, (s - d) / s);
      }
    }
  EXPECT_LT(max_overlap, 1e-4);  // jammed at ~1e-5 in volume fraction
  ASSERT_GT(overlapping, 0);
  EXPECT_LT(sum_overlap / static_cast<double>(overlapping), 1e-5);
  EXPECT_EQ(contacts, p.stats.contacts);
  EXPECT_EQ(overlapping, p.stats.overlapping_pairs);
  EXPECT_NEAR(max_overlap, p.stats.max_overlap, 1e-12);
  EXPECT_LT(p.stats.pressure, 1e-4);

  // Frictionless and jammed: the load-bearing contact network of the
  // non-rattlers is isostatic (z = 6), a few percent rattlers.
  EXPECT_NEAR(p.stats.loaded_coordination, 6.0, 0.1);
  EXPECT_GT(p.stats.mean_coordination, 5.5);
  EXPECT_LT(p.stats.mean_coordination, 7.0);
  EXPECT_LT(p.stats.rattler_fraction, 0.06);
}

TEST(Packing, DiametersUniformInRange) {
  const Packing& p = paper_packing();
  const double n = static_cast<double>(p.spheres.size());
  std::vector<double> d;
  for (const auto& s : p.spheres) d.push_back(2 * s.radius);
  for (double di : d) {
    EXPECT_GE(di, 1.0);
    EXPECT_LE(di, 1.25);
  }
  double mean = 0;
  for (double di : d) mean += di;
  mean /= n;
  const double sigma = 0.25 / std::sqrt(12.0 * n);  // of the mean
  EXPECT_NEAR(mean, 1.125, 3 * sigma);
  // Kolmogorov-Smirnov against U(1, 1.25), 1% level.
  std::sort(d.begin(), d.end());
  double ks = 0;
  for (std::size_t i = 0; i < d.size(); ++i) {
    const double F = (d[i] - 1.0) / 0.25;
    ks = std::max({ks, std::fabs(F - static_cast<double>(i) / n),
                   std::fabs(F - static_cast<double>(i + 1) / n)});
  }
  EXPECT_LT(ks, 1.63 / std::sqrt(n));
}

TEST(Packing, ReproducibleWithSeed) {
  const Packing a = make_packing(spec_of(200, 5));
  const Packing b = make_packing(spec_of(200, 5));
  const Packing c = make_packing(spec_of(200, 6));
  ASSERT_EQ(a.spheres.size(), b.spheres.size());
  EXPECT_EQ(std::memcmp(&a.box_side, &b.box_side, sizeof(double)), 0);
  for (std::size_t i = 0; i < a.spheres.size(); ++i) {
    EXPECT_EQ(std::memcmp(&a.spheres[i], &b.spheres[i], sizeof(Sphere)), 0) << "sphere " << i;
  }
  EXPECT_NE(a.box_side, c.box_side);
  EXPECT_NE(a.spheres[0].radius, c.spheres[0].radius);
  EXPECT_GE(c.stats.volume_fraction, 0.62);
  EXPECT_LE(c.stats.volume_fraction, 0.66);
}

TEST(Packing, OtherDistributionLawAndUnits) {
  // Uniform in volume: d^3 uniform in [d_min^3, d_max^3]; Hertz repulsion;
  // d_min = 2 scales every length.
  PackingSpec s = spec_of(200, 3);
  s.distribution = SizeDistribution::uniform_volume;
  s.law = ContactLaw::hertz;
  s.d_min = 2.0;
  s.d_max = 2.5;
  const Packing p = make_packing(s);
  double cube_mean = 0;
  for (const auto& sp : p.spheres) {
    const double d = 2 * sp.radius;
    EXPECT_GE(d, 2.0);
    EXPECT_LE(d, 2.5);
    cube_mean += d * d * d;
  }
  cube_mean /= 200.0;
  const double lo = 8.0, hi = 2.5 * 2.5 * 2.5;
  EXPECT_NEAR(cube_mean, 0.5 * (lo + hi), 3 * (hi - lo) / std::sqrt(12.0 * 200));
  EXPECT_GE(p.stats.volume_fraction, 0.62);
  EXPECT_LE(p.stats.volume_fraction, 0.66);
  EXPECT_LT(p.stats.max_overlap, 1e-4);
}

TEST(Packing, BadInputThrows) {
  auto bad = [](auto edit) {
    PackingSpec s = spec_of(100, 1);
    edit(s);
    EXPECT_THROW(make_packing(s), InputError);
  };
  bad([](PackingSpec& s) { s.count = 10; });
  bad([](PackingSpec& s) { s.count = 19; });
  bad([](PackingSpec& s) { s.d_max = 0.9; });
  bad([](PackingSpec& s) {
    s.d_min = 0;
    s.d_max = 1;
  });
  bad([](PackingSpec& s) { s.d_min = -1; });
  bad([](PackingSpec& s) { s.d_min = std::nan(""); });
  bad([](PackingSpec& s) { s.d_max = 10; });
  bad([](PackingSpec& s) { s.fraction_tolerance = 0; });
  bad([](PackingSpec& s) {
    s.count = 20;
    s.d_max = 3.5;
  });  // box too small for d_max
  try {
    PackingSpec s = spec_of(5, 1);
    validate(s);
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("count = 5"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(validate(spec_of(20, 1)));
  EXPECT_THROW(cut_cube(paper_packing(), 0), InputError);
  EXPECT_THROW(cut_cube(paper_packing(), 601), InputError);
}

TEST(Packing, CutCube) {
  const Packing& p = paper_packing();
  EXPECT_EQ(cut_cube(p, 516).spheres.size(), 516u);  // exact by construction
  const CubeSample cube = cut_cube(p, 300);
  EXPECT_EQ(cube.spheres.size(), 300u);
  EXPECT_EQ(cube.centres_inside, 300);
  EXPECT_NEAR(cube.side, p.box_side * std::cbrt(300.0 / 600.0), 0.05 * cube.side);
  for (const auto& s : cube.spheres)
    for (int k = 0; k < 3; ++k) {
      EXPECT_GE(s.centre[k], 0.0);
      EXPECT_LT(s.centre[k], cube.side);
    }
  // The sample's own clipped volume fraction against a Monte-Carlo estimate
  // (fixed seed; 1e5 points, sigma ~ 1.6e-3).
  std::mt19937_64 g(2024);
  const int points = 100000;
  int inside = 0;
  for (int k = 0; k < points; ++k) {
    const Point q{uniform(g) * cube.side, uniform(g) * cube.side, uniform(g) * cube.side};
    for (const auto& s : cube.spheres) {
      const double dx = q[0] - s.centre[0], dy = q[1] - s.centre[1], dz = q[2] - s.centre[2];
      if (dx * dx + dy * dy + dz * dz < s.radius * s.radius) {
        ++inside;
        break;
      }
    }
  }
  const double mc = static_cast<double>(inside) / points;
  const double sigma = std::sqrt(mc * (1 - mc) / points);
  EXPECT_NEAR(cube.volume_fraction, mc, 4 * sigma);
  // Spheres crossing the faces lose their outer parts, and the parts of
  // outside spheres are missing: below the packing's density by ~3 r/16 per
  // unit face area, i.e. 6 * 3 rho r / (16 L).
  const double r = 0.5625;
  const double expected = p.stats.volume_fraction * (1 - 18 * r / (16 * cube.side));
  EXPECT_NEAR(cube.volume_fraction, expected, 0.02);
  // With the parts of outside spheres the cube has the packing's density.
  EXPECT_NEAR(cube.region_volume_fraction, p.stats.volume_fraction, 0.02);

  // Keeping the spheres that reach in: the same cube, the packing's density.
  const CubeSample full = cut_cube(p, 300, CubeCut::reaching_in);
  EXPECT_EQ(full.side, cube.side);
  EXPECT_EQ(full.centres_inside, 300);
  EXPECT_GT(full.spheres.size(), 400u);
  for (std::size_t i = 0; i < 300; ++i)
    EXPECT_EQ(std::memcmp(&full.spheres[i], &cube.spheres[i], sizeof(Sphere)), 0);
  for (std::size_t i = 300; i < full.spheres.size(); ++i) {
    const auto& s = full.spheres[i];
    bool outside = false;
    double gap2 = 0;
    for (int k = 0; k < 3; ++k) {
      outside = outside || s.centre[k] < 0 || s.centre[k] >= full.side;
      const double gk = std::max({0.0, -s.centre[k], s.centre[k] - full.side});
      gap2 += gk * gk;
    }
    EXPECT_TRUE(outside);
    EXPECT_LT(gap2, s.radius * s.radius);  // reaches in
  }
  EXPECT_NEAR(full.volume_fraction, cube.region_volume_fraction, 1e-12);
  EXPECT_NEAR(full.region_volume_fraction, cube.region_volume_fraction, 1e-12);

  // The whole packing as a cube: every sphere, and the region density is
  // exactly the box's.
  const CubeSample whole = cut_cube(p, 600);
  EXPECT_EQ(whole.spheres.size(), 600u);
  EXPECT_DOUBLE_EQ(whole.side, p.box_side);
  EXPECT_NEAR(whole.region_volume_fraction, p.stats.volume_fraction, 1e-9);
}

TEST(SphereBoxVolume, ExactCases) {
  const double r = 0.7, full = 4.0 / 3.0 * kPi * r * r * r;
  const Point c{1.0, 2.0, 3.0};
  auto box = [](Point lo, Point hi) {
    Box b;
    b.lo = lo;
    b.hi = hi;
    return b;
  };
  EXPECT_NEAR(sphere_box_volume(c, r, box({0, 0, 0}, {5, 5, 5})), full, 1e-14);
  EXPECT_EQ(sphere_box_volume(c, r, box({2, 2, 2}, {5, 5, 5})), 0.0);
  // Planes through the centre: half, quarter, octant.
  EXPECT_NEAR(sphere_box_volume(c, r, box({1, 0, 0}, {5, 5, 5})), full / 2, 1e-12);
  EXPECT_NEAR(sphere_box_volume(c, r, box({1, 2, 0}, {5, 5, 5})), full / 4, 1e-12);
  EXPECT_NEAR(sphere_box_volume(c, r, box({1, 2, 3}, {5, 5, 5})), full / 8, 1e-12);
  // Spherical cap of height h: pi h^2 (3r - h) / 3.
  const double h = 0.25;
  EXPECT_NEAR(sphere_box_volume(c, r, box({1 + r - h, 0, 0}, {5, 5, 5})),
              kPi * h * h * (3 * r - h) / 3, 1e-12);
  // Any cut point splits space into 8 boxes whose volumes add up.
  std::mt19937_64 g(7);
  for (int t = 0; t < 20; ++t) {
    const Point p{c[0] + (2 * uniform(g) - 1) * r, c[1] + (2 * uniform(g) - 1) * r,
                  c[2] + (2 * uniform(g) - 1) * r};
    double sum = 0;
    for (int s = 0; s < 8; ++s) {
      Point lo{}, hi{};
      for (int k = 0; k < 3; ++k) {
        const bool up = (s >> k) & 1;
        lo[k] = up ? p[k] : -10.0;
        hi[k] = up ? 10.0 : p[k];
      }
      sum += sphere_box_volume(c, r, box(lo, hi));
    }
    EXPECT_NEAR(sum, full, 1e-12);
  }
  // A small box cutting the sphere on all sides, against Monte Carlo.
  const Box b = box({0.6, 1.7, 2.5}, {1.5, 2.3, 3.2});
  int inside = 0;
  const int points = 400000;
  for (int k = 0; k < points; ++k) {
    const Point q{b.lo[0] + uniform(g) * b.length(0), b.lo[1] + uniform(g) * b.length(1),
                  b.lo[2] + uniform(g) * b.length(2)};
    const double dx = q[0] - c[0], dy = q[1] - c[1], dz = q[2] - c[2];
    inside += dx * dx + dy * dy + dz * dz < r * r;
  }
  const double frac = static_cast<double>(inside) / points;
  EXPECT_NEAR(sphere_box_volume(c, r, b) / b.volume(), frac,
              4 * std::sqrt(frac * (1 - frac) / points));
}
