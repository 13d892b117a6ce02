// Box-clipped Voronoi volumes: exact cells (box, bisector halves, grids,
// degenerate planes through cell vertices) and the partition of unity on
// random Delaunay lattices.
#include "lem/base/error.hpp"
#include "lem/lattice/lattice.hpp"
#include "lem/lattice/voronoi.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

using namespace lem;

namespace {

Lattice two_nodes(const Box& box, const Point& a, const Point& b) {
  Lattice l;
  l.box = box;
  l.nodes = {a, b};
  l.bonds = {Bond{0, 1}};
  l.stiffness = {1.0};
  return l;
}

// Rectangular grid of (cells+1) nodes per axis with spacing h, starting at
// `lo`, bonded to all 26 neighbours: the diagonal bisectors are redundant
// and pass exactly through vertices and edges of the cells (degenerate cuts).
Lattice grid_lattice(const Point& lo, std::array<int, 3> cells, const Point& h) {
  Lattice l;
  const int nx = cells[0] + 1, ny = cells[1] + 1, nz = cells[2] + 1;
  for (int a = 0; a < 3; ++a) {
    l.box.lo[a] = lo[a];
    l.box.hi[a] = lo[a] + cells[a] * h[a];
  }
  auto id = [&](int i, int j, int k) { return (i * ny + j) * nz + k; };
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j)
      for (int k = 0; k < nz; ++k)
        // The last node on each axis sits exactly on box.hi, like the nodes
        // of make_random_lattice.
        l.nodes.push_back({i == cells[0] ? l.box.hi[0] : lo[0] + i * h[0],
                           j == cells[1] ? l.box.hi[1] : lo[1] + j * h[1],
                           k == cells[2] ? l.box.hi[2] : lo[2] + k * h[2]});
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j)
      for (int k = 0; k < nz; ++k)
        for (int di = -1; di <= 1; ++di)
          for (int dj = -1; dj <= 1; ++dj)
            for (int dk = -1; dk <= 1; ++dk) {
              const int i2 = i + di, j2 = j + dj, k2 = k + dk;
              if (i2 < 0 || j2 < 0 || k2 < 0 || i2 >= nx || j2 >= ny || k2 >= nz) continue;
              const int a = id(i, j, k), b = id(i2, j2, k2);
              if (a < b) l.bonds.push_back(Bond{a, b});
            }
  std::sort(l.bonds.begin(), l.bonds.end());
  l.stiffness.assign(l.bonds.size(), 1.0);
  return l;
}

double sum(const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0); }

}  // namespace

TEST(Voronoi, LoneNodeOwnsTheBox) {
  Box box;
  box.lo = {-1.0, 0.5, 2.0};
  box.hi = {1.0, 3.5, 2.5};
  EXPECT_NEAR(clipped_cell_volume(box, {0.1, 1.0, 2.2}, {}), 3.0, 1e-14);
  // A node on a corner, and a neighbour far outside the box (no cut).
  EXPECT_NEAR(clipped_cell_volume(box, box.lo, {{50.0, 0.0, 0.0}}), 3.0, 1e-14);
  Lattice l;
  l.box = box;
  l.nodes = {{0.0, 2.0, 2.25}};
  const auto v = voronoi_volumes(l);
  ASSERT_EQ(v.size(), 1u);
  EXPECT_NEAR(v[0], 3.0, 1e-14);
}

TEST(Voronoi, TwoNodesSplitTheBoxAtTheirBisector) {
  const Box unit;
  // Symmetric pair: halves.
  auto v = voronoi_volumes(two_nodes(unit, {0.25, 0.5, 0.5}, {0.75, 0.5, 0.5}));
  EXPECT_NEAR(v[0], 0.5, 1e-15);
  EXPECT_NEAR(v[1], 0.5, 1e-15);
  // Off-centre pair: bisector x = 0.3.
  v = voronoi_volumes(two_nodes(unit, {0.1, 0.2, 0.3}, {0.5, 0.2, 0.3}));
  EXPECT_NEAR(v[0], 0.3, 1e-15);
  EXPECT_NEAR(v[1], 0.7, 1e-15);
  // Oblique bisector x + y = 0.8: a triangular prism of area 0.32.
  v = voronoi_volumes(two_nodes(unit, {0.2, 0.2, 0.5}, {0.6, 0.6, 0.5}));
  EXPECT_NEAR(v[0], 0.32, 1e-15);
  EXPECT_NEAR(v[1], 0.68, 1e-15);
  // Bisector x + y = 1 through two box edges.
  v = voronoi_volumes(two_nodes(unit, {0.25, 0.25, 0.5}, {0.75, 0.75, 0.5}));
  EXPECT_NEAR(v[0], 0.5, 1e-15);
  EXPECT_NEAR(v[1], 0.5, 1e-15);
  // Bisector x + y + z = 0.9: a corner tetrahedron.
  v = voronoi_volumes(two_nodes(unit, {0.2, 0.2, 0.2}, {0.4, 0.4, 0.4}));
  EXPECT_NEAR(v[0], 0.9 * 0.9 * 0.9 / 6, 1e-15);
  EXPECT_NEAR(v[1], 1 - 0.9 * 0.9 * 0.9 / 6, 1e-15);
  // Bisector x + y + z = 1 (up to rounding) through three box corners.
  const double b = 2.0 / 3.0 - 0.25;
  v = voronoi_volumes(two_nodes(unit, {0.25, 0.25, 0.25}, {b, b, b}));
  EXPECT_NEAR(v[0], 1.0 / 6, 1e-15);
  EXPECT_NEAR(v[1], 5.0 / 6, 1e-15);
  // A partner outside the box with the bisector outside too: no cut.
  v = voronoi_volumes(two_nodes(unit, {1.0, 0.5, 0.5}, {3.0, 0.5, 0.5}));
  EXPECT_NEAR(v[0], 1.0, 1e-15);
  EXPECT_EQ(v[1], 0.0);
}

TEST(Voronoi, CubicGridGivesCubesAndTheirShares) {
  const double h = 0.1;
  const int cells = 5;
  const Lattice l = grid_lattice({0.3, -0.2, 1.0}, {cells, cells, cells}, {h, h, h});
  const auto v = voronoi_volumes(l);
  ASSERT_EQ(v.size(), l.node_count());
  const auto faces = face_flags(l);
  for (std::size_t i = 0; i < v.size(); ++i) {
    const int on = std::popcount(unsigned(faces[i]));  // 0 inside, 1 face, 2 edge, 3 corner
    const double expected = h * h * h / double(1 << on);
    EXPECT_NEAR(v[i], expected, 1e-12 * expected) << "node " << i << " on " << on << " faces";
  }
  EXPECT_NEAR(sum(v), l.box.volume(), 1e-13 * l.box.volume());
}

TEST(Voronoi, RectangularGridGivesBricks) {
  const Point h{0.25, 0.4, 0.1};
  const Lattice l = grid_lattice({0.0, 0.0, 0.0}, {4, 5, 5}, h);
  const auto v = voronoi_volumes(l);
  const auto faces = face_flags(l);
  for (std::size_t i = 0; i < v.size(); ++i) {
    const int on = std::popcount(unsigned(faces[i]));
    const double expected = h[0] * h[1] * h[2] / double(1 << on);
    EXPECT_NEAR(v[i], expected, 1e-12 * expected) << "node " << i;
  }
  EXPECT_NEAR(sum(v), l.box.volume(), 1e-13 * l.box.volume());
}

TEST(Voronoi, JitteredGridsStillPartitionTheBox) {
  // Grid nodes moved by tiny amounts (around the clipping tolerance and far
  // above it; boundary nodes stay on their faces): the 26-neighbour cells are
  // near-degenerate, with vertices of degree up to 24 split into clusters of
  // nearly coincident vertices.  Every cell must stay positive and the cells
  // must still tile the box.
  const double h = 0.1;
  for (const double jitter : {1e-16, 1e-14, 1e-12, 1e-11, 1e-10, 1e-7, 1e-4}) {
    Lattice l = grid_lattice({0.0, 0.0, 0.0}, {6, 6, 6}, {h, h, h});
    const auto faces = face_flags(l);
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-jitter * h, jitter * h);
    for (std::size_t i = 0; i < l.node_count(); ++i)
      for (int a = 0; a < 3; ++a)
        if (!(faces[i] & (3u << (2 * a)))) l.nodes[i][a] += u(rng);
    const auto v = voronoi_volumes(l);
    EXPECT_GT(*std::min_element(v.begin(), v.end()), 0.1 * h * h * h / 8) << jitter;
    EXPECT_NEAR(sum(v), l.box.volume(), 1e-12 * l.box.volume()) << jitter;
  }
}

TEST(Voronoi, FccCellsAreRhombicDodecahedraAndTileTheBlock) {
  // Nearest-neighbour bonds suffice for FCC (the next shell's bisectors only
  // touch the cell at vertices): bulk cells have the volume a^3 / sqrt(2).
  const double a = 0.7;
  const Lattice l = make_fcc_lattice({3, 4, 2}, a, 1.0);
  const auto v = voronoi_volumes(l);
  const double bulk = a * a * a / std::sqrt(2.0);
  EXPECT_NEAR(*std::max_element(v.begin(), v.end()), bulk, 1e-13 * bulk);
  const auto full = std::count_if(v.begin(), v.end(),
                                  [&](double x) { return std::abs(x - bulk) < 1e-12 * bulk; });
  EXPECT_GT(full, 20);
  EXPECT_NEAR(sum(v), l.box.volume(), 1e-13 * l.box.volume());
}

TEST(Voronoi, NeighbourOrderDoesNotMatter) {
  // An interior grid node with all 26 neighbours, fed in many random orders
  // (so degenerate diagonal planes often cut first); and a corner node.
  const double h = 0.1;
  Box box;
  box.hi = {1.0, 1.0, 1.0};
  const Point c{0.5, 0.5, 0.5};
  std::vector<Point> nb;
  for (int di = -1; di <= 1; ++di)
    for (int dj = -1; dj <= 1; ++dj)
      for (int dk = -1; dk <= 1; ++dk)
        if (di || dj || dk) nb.push_back({c[0] + di * h, c[1] + dj * h, c[2] + dk * h});
  std::mt19937 rng(5);
  for (int t = 0; t < 50; ++t) {
    std::shuffle(nb.begin(), nb.end(), rng);
    EXPECT_NEAR(clipped_cell_volume(box, c, nb), h * h * h, 1e-15);
  }
  const std::vector<Point> corner_nb{{h, 0, 0}, {0, h, 0}, {0, 0, h}, {h, h, 0},
                                     {h, 0, h}, {0, h, h}, {h, h, h}};
  EXPECT_NEAR(clipped_cell_volume(box, {0, 0, 0}, corner_nb), h * h * h / 8, 1e-15);
}

TEST(Voronoi, CoincidentNodesAndBadBondsAreErrors) {
  const Box unit;
  EXPECT_THROW(clipped_cell_volume(unit, {0.5, 0.5, 0.5}, {{0.5, 0.5, 0.5}}), InputError);
  Lattice l = two_nodes(unit, {0.2, 0.2, 0.2}, {0.7, 0.2, 0.2});
  l.bonds = {Bond{0, 2}};
  EXPECT_THROW(voronoi_volumes(l), InputError);
}

TEST(Voronoi, RandomLatticesPartitionTheBox) {
  for (const std::int64_t nodes : {2000, 20000}) {
    for (const std::uint64_t seed : {1u, 2u, 7u}) {
      // Unit cube, the non-cubic box, and a box away from the origin.
      for (const Box& box :
           {Box{}, Box{{0, 0, 0}, {1.0, 2.0, 0.5}}, Box{{10.0, -3.0, 0.25}, {11.0, -2.0, 1.25}}}) {
        RandomLatticeSpec spec;
        spec.box = box;
        spec.nodes = nodes;
        spec.seed = seed;
        const Lattice l = make_random_lattice(spec);
        const auto v = voronoi_volumes(l);
        ASSERT_EQ(v.size(), l.node_count());
        const double mean = l.box.volume() / double(nodes);
        double smallest = mean;
        for (double x : v) smallest = std::min(smallest, x);
        // Hard-core points: no cell is tiny (corner cells are the smallest).
        EXPECT_GT(smallest, 1e-3 * mean) << nodes << " nodes, seed " << seed;
        EXPECT_NEAR(sum(v), l.box.volume(), 1e-10 * l.box.volume())
            << nodes << " nodes, seed " << seed << ", box side " << box.length(0) << ","
            << box.length(1) << "," << box.length(2) << " at " << box.lo[0];
      }
    }
  }
}

TEST(Voronoi, DelaunayNeighboursGiveTheTrueVoronoiCell) {
  // Brute force on a few nodes: clipping by every other node of the lattice
  // (hundreds of redundant planes) gives the same cell as the bonded ones.
  RandomLatticeSpec spec;
  spec.nodes = 2000;
  spec.seed = 4;
  const Lattice l = make_random_lattice(spec);
  const auto v = voronoi_volumes(l);
  for (std::size_t i = 0; i < l.node_count(); i += 97) {
    std::vector<Point> others;
    for (std::size_t j = 0; j < l.node_count(); ++j)
      if (j != i) others.push_back(l.nodes[j]);
    EXPECT_NEAR(clipped_cell_volume(l.box, l.nodes[i], others), v[i], 1e-13 * v[i]) << "node " << i;
  }
}
