// Random lattice: hard-core random points (random sequential addition) on the
// corners, edges, faces and inside of the box, joined by their Delaunay edges.
#include "lem/base/cell_grid.hpp"
#include "lem/base/error.hpp"
#include "lem/lattice/lattice.hpp"

#include "random_points.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>

namespace lem {
namespace {

// Hard-core placement: is any point already placed closer than the radius?
class HardCoreGrid {
 public:
  HardCoreGrid(const Box& box, double cell, double radius)
      : grid_(box, cell), r2_(radius * radius), head_(grid_.cell_count(), -1) {}

  bool try_add(const Point& p, std::vector<Point>& points) {
    const bool clear = grid_.for_each_cell_near(p, [&](std::size_t cell) {
      for (int q = head_[cell]; q >= 0; q = next_[q]) {
        const Point& o = points[q];
        const double dx = o[0] - p[0], dy = o[1] - p[1], dz = o[2] - p[2];
        if (dx * dx + dy * dy + dz * dz < r2_) return false;
      }
      return true;
    });
    if (!clear) return false;
    const std::size_t cell = grid_.cell_of(p);
    next_.push_back(head_[cell]);
    head_[cell] = static_cast<std::int32_t>(points.size());
    points.push_back(p);
    return true;
  }

 private:
  CellGrid grid_;
  double r2_;
  std::vector<std::int32_t> head_, next_;  // per cell, a linked list of points
};

}  // namespace

std::int64_t nodes_for_bond_count(std::int64_t bonds) {
  // Bonds per node measured on these lattices (unit cube, min separation
  // 0.5): 7.21 at 2e4 nodes, 7.48 at 1.9e5.  Fitted as 7.72 - 13.9 N^(-1/3)
  // (the surface deficit); solved for N by fixed-point iteration.
  double n = static_cast<double>(bonds) / 7.5;
  for (int it = 0; it < 20; ++it)
    n = static_cast<double>(bonds) / std::max(1.0, 7.72 - 13.9 / std::cbrt(std::max(n, 8.0)));
  return std::max<std::int64_t>(8, std::llround(n));
}

std::int64_t target_node_count(const RandomLatticeSpec& spec) {
  if (spec.nodes > 0) return spec.nodes;
  if (spec.bonds > 0) return nodes_for_bond_count(spec.bonds);
  if (spec.mesh_density > 0)
    return nodes_for_bond_count(std::llround(std::pow(spec.mesh_density, -3.0)));
  throw InputError("random lattice: give a node count, a bond count or L_n > 0");
}

PointCounts point_counts(const Box& box, std::int64_t target) {
  PointCounts c;
  c.spacing = std::cbrt(box.volume() / static_cast<double>(target));
  const double spacing = c.spacing;
  const double shortest = std::min({box.length(0), box.length(1), box.length(2)});
  if (shortest < 2.0 * spacing) {
    std::ostringstream s;
    s << "random lattice: " << target << " nodes give a mean spacing of " << spacing
      << ", too coarse for a box side of " << shortest
      << " (need at least two spacings per side: increase the node count)";
    throw InputError(s.str());
  }
  std::int64_t boundary = 8;
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, d = (a + 2) % 3;
    c.edge[a] = std::max<std::int64_t>(0, std::llround(box.length(a) / spacing) - 1);
    c.face[a] =
        std::max<std::int64_t>(0,
                               std::llround(box.length(b) * box.length(d) / (spacing * spacing)) -
                                   2 * std::llround((box.length(b) + box.length(d)) / spacing));
    boundary += 4 * c.edge[a] + 2 * c.face[a];
  }
  c.inside = target - boundary;
  if (c.inside < 1) {
    std::ostringstream s;
    s << "random lattice: " << target << " nodes are too few to fill the box (the faces alone "
      << "take " << boundary << ")";
    throw InputError(s.str());
  }
  return c;
}

Lattice make_random_lattice(const RandomLatticeSpec& spec) {
  const Box& box = spec.box;
  const std::int64_t target = target_node_count(spec);
  if (target > 200'000'000) throw InputError("random lattice: more than 2e8 nodes requested");
  const PointCounts counts = point_counts(box, target);
  const double spacing = counts.spacing;
  const double rmin = spec.min_separation * spacing;
  HardCoreGrid grid(box, std::max(rmin, spacing), rmin);
  std::mt19937_64 rng(spec.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Point> points;
  points.reserve(static_cast<std::size_t>(target));

  // Place `count` random points with coordinates fixed on the axes in `fixed`
  // (value lo or hi), uniform on the free axes.
  auto sprinkle = [&](std::int64_t count, const std::array<int, 3>& fixed, const Point& at,
                      const char* where) {
    std::int64_t placed = 0, tries = 0;
    const std::int64_t max_tries = 200 * count + 1000;
    while (placed < count) {
      if (++tries > max_tries) {
        std::ostringstream s;
        s << "random lattice: could only place " << placed << " of " << count << " points on the "
          << where << " with minimum separation " << rmin << " (lower -lattice_min_separation)";
        throw InputError(s.str());
      }
      Point p;
      for (int a = 0; a < 3; ++a) p[a] = fixed[a] ? at[a] : box.lo[a] + unit(rng) * box.length(a);
      if (grid.try_add(p, points)) ++placed;
    }
  };

  // Corners, then edges, faces and the inside, at the density of the bulk.
  for (int c = 0; c < 8; ++c) {
    Point p{(c & 1) ? box.hi[0] : box.lo[0], (c & 2) ? box.hi[1] : box.lo[1],
            (c & 4) ? box.hi[2] : box.lo[2]};
    grid.try_add(p, points);
  }
  for (int a = 0; a < 3; ++a) {  // edges parallel to axis a
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    const std::int64_t count = counts.edge[a];
    for (int s = 0; s < 4; ++s) {
      std::array<int, 3> fixed{1, 1, 1};
      fixed[a] = 0;
      Point at{};
      at[b] = (s & 1) ? box.hi[b] : box.lo[b];
      at[c] = (s & 2) ? box.hi[c] : box.lo[c];
      sprinkle(count, fixed, at, "box edges");
    }
  }
  for (int a = 0; a < 3; ++a) {  // faces normal to axis a
    const std::int64_t count = counts.face[a];
    for (int s = 0; s < 2; ++s) {
      std::array<int, 3> fixed{0, 0, 0};
      fixed[a] = 1;
      Point at{};
      at[a] = s ? box.hi[a] : box.lo[a];
      sprinkle(count, fixed, at, "box faces");
    }
  }
  sprinkle(counts.inside, {0, 0, 0}, Point{}, "inside of the box");

  // Delaunay tetrahedralisation; its edges are the bonds.
  std::vector<std::pair<DelaunayKernel::Point_3, std::int64_t>> input;
  input.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    input.emplace_back(DelaunayKernel::Point_3(points[i][0], points[i][1], points[i][2]),
                       static_cast<std::int64_t>(i));
  Delaunay triangulation(input.begin(), input.end());

  Lattice lattice;
  lattice.box = box;
  lattice.nodes = std::move(points);
  lattice.bonds.reserve(triangulation.number_of_finite_edges());
  for (auto e = triangulation.finite_edges_begin(); e != triangulation.finite_edges_end(); ++e) {
    const auto i = static_cast<std::int32_t>(e->first->vertex(e->second)->info());
    const auto j = static_cast<std::int32_t>(e->first->vertex(e->third)->info());
    lattice.bonds.push_back(Bond{std::min(i, j), std::max(i, j)});
  }
  std::sort(lattice.bonds.begin(), lattice.bonds.end());
  lattice.stiffness.assign(lattice.bonds.size(), spec.stiffness);
  return lattice;
}

}  // namespace lem
