// The random lattice of lem/lattice/cell_lattice.hpp, made in parallel.
#include "lem/lattice/cell_lattice.hpp"

#include "lem/base/byte_stream.hpp"
#include "lem/base/collective.hpp"
#include "lem/base/error.hpp"
#include "lem/base/redistribute.hpp"

#include "random_points.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>
#include <string>

namespace lem {
namespace {

using Kernel = DelaunayKernel;

using Cell = std::array<int, 3>;

// The generation grid, its cells' ranks (blocks of a 3-D grid of ranks) and
// the points this rank knows: of its cells and of a margin around them.
class Grid {
 public:
  Grid(MPI_Comm comm, const Box& box, double side) : box_(box) {
    MPI_Comm_rank(comm, &rank_);
    MPI_Comm_size(comm, &ranks_);
    for (int a = 0; a < 3; ++a)
      n_[a] = static_cast<int>(std::clamp(std::floor(box.length(a) / side), 1.0, 1024.0));
    int dims[3] = {0, 0, 0};
    MPI_Dims_create(ranks_, 3, dims);
    for (int a = 0; a < 3; ++a) dims_[a] = dims[a];
    const Cell me = rank_cell(rank_);
    for (int a = 0; a < 3; ++a) {
      lo_[a] = first(a, me[a]);
      hi_[a] = first(a, me[a] + 1);
      elo_[a] = std::max(0, lo_[a] - kTriangulationMarginCells);
      ehi_[a] = std::min(n_[a], hi_[a] + kTriangulationMarginCells);
    }
    points_.resize(static_cast<std::size_t>(ehi_[0] - elo_[0]) * (ehi_[1] - elo_[1]) *
                   (ehi_[2] - elo_[2]));
  }

  const Cell& counts() const { return n_; }
  std::int64_t cell_count() const { return std::int64_t(n_[0]) * n_[1] * n_[2]; }
  std::int64_t index(const Cell& c) const {
    return (std::int64_t(c[0]) * n_[1] + c[1]) * n_[2] + c[2];
  }
  Cell cell_at(std::int64_t q) const {
    return {static_cast<int>(q / n_[2] / n_[1]), static_cast<int>(q / n_[2] % n_[1]),
            static_cast<int>(q % n_[2])};
  }
  /// The rank of a cell.
  int owner(const Cell& c) const {
    int r[3];
    for (int a = 0; a < 3; ++a)  // the largest r with first(a, r) <= c[a]
      r[a] = static_cast<int>(((std::int64_t(c[a]) + 1) * dims_[a] - 1) / n_[a]);
    return (r[0] * dims_[1] + r[1]) * dims_[2] + r[2];
  }
  bool owned(const Cell& c) const { return inside(c, lo_, hi_); }
  bool known(const Cell& c) const { return inside(c, elo_, ehi_); }
  /// Calls visit(cell) for every cell of this rank.
  template <class Visit>
  void for_each_owned(Visit&& visit) const {
    for (int i = lo_[0]; i < hi_[0]; ++i)
      for (int j = lo_[1]; j < hi_[1]; ++j)
        for (int k = lo_[2]; k < hi_[2]; ++k) visit(Cell{i, j, k});
  }
  /// Calls visit(cell) for the cells of the grid within `reach` cells of c.
  template <class Visit>
  void for_each_near(const Cell& c, int reach, Visit&& visit) const {
    for (int i = std::max(0, c[0] - reach); i <= std::min(n_[0] - 1, c[0] + reach); ++i)
      for (int j = std::max(0, c[1] - reach); j <= std::min(n_[1] - 1, c[1] + reach); ++j)
        for (int k = std::max(0, c[2] - reach); k <= std::min(n_[2] - 1, c[2] + reach); ++k)
          visit(Cell{i, j, k});
  }
  /// The ranks other than this one whose cells, widened by `reach` cells,
  /// hold c.
  std::vector<int> ranks_near(const Cell& c, int reach) const {
    std::vector<int> out;
    for_each_near(c, reach, [&](const Cell& d) {
      const int r = owner(d);
      if (r != rank_ && std::find(out.begin(), out.end(), r) == out.end()) out.push_back(r);
    });
    return out;
  }
  /// The points of a known cell.
  std::vector<Point>& points(const Cell& c) {
    return points_[(std::size_t(c[0] - elo_[0]) * (ehi_[1] - elo_[1]) + (c[1] - elo_[1])) *
                       (ehi_[2] - elo_[2]) +
                   (c[2] - elo_[2])];
  }
  /// The part of the box a cell covers.
  Box extent(const Cell& c) const {
    Box b;
    for (int a = 0; a < 3; ++a) {
      b.lo[a] = box_.lo[a] + box_.length(a) * c[a] / n_[a];
      b.hi[a] = c[a] + 1 == n_[a] ? box_.hi[a] : box_.lo[a] + box_.length(a) * (c[a] + 1) / n_[a];
    }
    return b;
  }
  /// The region whose points this rank knows, as a box.
  Box known_region() const {
    return {extent({elo_[0], elo_[1], elo_[2]}).lo,
            extent({ehi_[0] - 1, ehi_[1] - 1, ehi_[2] - 1}).hi};
  }
  int rank() const { return rank_; }

 private:
  int first(int a, int r) const { return static_cast<int>(std::int64_t(n_[a]) * r / dims_[a]); }
  Cell rank_cell(int r) const {
    return {r / (dims_[1] * dims_[2]), r / dims_[2] % dims_[1], r % dims_[2]};
  }
  static bool inside(const Cell& c, const Cell& lo, const Cell& hi) {
    for (int a = 0; a < 3; ++a)
      if (c[a] < lo[a] || c[a] >= hi[a]) return false;
    return true;
  }

  Box box_;
  int rank_ = 0, ranks_ = 1;
  Cell n_{1, 1, 1}, dims_{1, 1, 1}, lo_{}, hi_{}, elo_{}, ehi_{};
  std::vector<std::vector<Point>> points_;
};

int colour(const Cell& c) { return (c[0] % 2) * 4 + (c[1] % 2) * 2 + c[2] % 2; }

// The k-th candidate's coordinate on `axis` in a cell, in [0, 1): a
// counter-based stream, so that a cell draws the same numbers on any rank.
double uniform(std::uint64_t seed, int phase, std::int64_t cell, std::int64_t k, int axis) {
  std::uint64_t h = mix64(seed);
  h = mix64(h ^ static_cast<std::uint64_t>(phase));
  h = mix64(h ^ static_cast<std::uint64_t>(cell));
  h = mix64(h ^ static_cast<std::uint64_t>(k));
  h = mix64(h ^ static_cast<std::uint64_t>(axis));
  return static_cast<double>(h >> 11) * 0x1.0p-53;
}

// count * (q + 1) / total - count * q / total: share q of `count` spread
// over `total` parts, in whole numbers that add up to count.
std::int64_t share(std::int64_t count, std::int64_t q, std::int64_t total) {
  const auto part = [&](std::int64_t x) {
    return static_cast<std::int64_t>((static_cast<long double>(count) * x) / total);
  };
  return part(q + 1) - part(q);
}

// What a phase places in a cell: how many points, with which coordinates
// fixed (at `at`), and its name for messages.
struct Placement {
  std::int64_t count = 0;
  std::array<int, 3> fixed{0, 0, 0};
  Point at{};
};

struct Phase {
  const char* where;
  // The placements of this phase in cell c (none, or several for a cell on
  // more than one edge or face).
  std::function<std::vector<Placement>(const Cell&)> in_cell;
};

// A new point that other ranks must learn: its cell and position.
struct Sent {
  std::int64_t cell;
  Point x;
};

}  // namespace

static_assert(kTriangulationMarginCells >= 1,
              "the random sequential addition reads the cells next to a rank's own");

LatticeBlock make_cell_lattice(MPI_Comm comm, const RandomLatticeSpec& spec) {
  const Box& box = spec.box;
  const PointCounts counts = point_counts(box, target_node_count(spec));
  const double spacing = counts.spacing;
  const double rmin = spec.min_separation * spacing, r2 = rmin * rmin;
  Grid grid(comm, box, std::max(rmin, kGenerationCellSpacings * spacing));
  const Cell n = grid.counts();

  const std::int64_t* edge_count = counts.edge;
  const std::int64_t* face_count = counts.face;
  const std::int64_t inside = counts.inside;
  const auto side_at = [&](int a, int s) { return s ? box.hi[a] : box.lo[a]; };
  const auto on_side = [&](const Cell& c, int a, int s) { return c[a] == (s ? n[a] - 1 : 0); };
  const Phase phases[] = {
      {"box corners",
       [&](const Cell& c) {
         std::vector<Placement> out;
         for (int k = 0; k < 8; ++k) {
           const int s[3] = {k & 1, (k >> 1) & 1, (k >> 2) & 1};
           if (on_side(c, 0, s[0]) && on_side(c, 1, s[1]) && on_side(c, 2, s[2]))
             out.push_back({1, {1, 1, 1}, {side_at(0, s[0]), side_at(1, s[1]), side_at(2, s[2])}});
         }
         return out;
       }},
      {"box edges",
       [&](const Cell& c) {
         std::vector<Placement> out;
         for (int a = 0; a < 3; ++a) {  // edges parallel to axis a
           const int b = (a + 1) % 3, d = (a + 2) % 3;
           for (int s = 0; s < 4; ++s) {
             if (!on_side(c, b, s & 1) || !on_side(c, d, (s >> 1) & 1)) continue;
             Placement p{share(edge_count[a], c[a], n[a]), {1, 1, 1}, {}};
             p.fixed[a] = 0;
             p.at[b] = side_at(b, s & 1);
             p.at[d] = side_at(d, (s >> 1) & 1);
             out.push_back(p);
           }
         }
         return out;
       }},
      {"box faces",
       [&](const Cell& c) {
         std::vector<Placement> out;
         for (int a = 0; a < 3; ++a) {  // faces normal to axis a
           const int b = (a + 1) % 3, d = (a + 2) % 3;
           for (int s = 0; s < 2; ++s) {
             if (!on_side(c, a, s)) continue;
             Placement p{share(face_count[a], std::int64_t(c[b]) * n[d] + c[d],
                               std::int64_t(n[b]) * n[d]),
                         {0, 0, 0},
                         {}};
             p.fixed[a] = 1;
             p.at[a] = side_at(a, s);
             out.push_back(p);
           }
         }
         return out;
       }},
      {"inside of the box",
       [&](const Cell& c) {
         return std::vector<Placement>{
             {share(inside, grid.index(c), grid.cell_count()), {0, 0, 0}, {}}};
       }},
  };

  // Random sequential addition, colour by colour: a candidate is kept when
  // no point of its cell or of a neighbouring one lies within rmin.
  const auto clear = [&](const Cell& c, const Point& p) {
    bool ok = true;
    grid.for_each_near(c, 1, [&](const Cell& d) {
      if (!ok) return;
      for (const Point& o : grid.points(d)) {
        const double dx = o[0] - p[0], dy = o[1] - p[1], dz = o[2] - p[2];
        if (dx * dx + dy * dy + dz * dz < r2) {
          ok = false;
          return;
        }
      }
    });
    return ok;
  };
  for (int phase = 0; phase < 4; ++phase)
    for (int hue = 0; hue < 8; ++hue) {
      std::vector<Sent> sent;
      std::vector<int> to;
      run_collectively(comm, [&] {
        grid.for_each_owned([&](const Cell& c) {
          if (colour(c) != hue) return;
          const std::int64_t q = grid.index(c);
          const Box cell_box = grid.extent(c);
          std::int64_t k = 0;
          std::vector<Point>& mine = grid.points(c);
          for (const Placement& p : phases[phase].in_cell(c)) {
            std::int64_t placed = 0;
            const std::int64_t max_tries = 200 * p.count + 1000;
            for (std::int64_t tries = 0; placed < p.count; ++tries, ++k) {
              if (tries >= max_tries) {
                std::ostringstream s;
                s << "random lattice: could only place " << placed << " of " << p.count
                  << " points of a cell on the " << phases[phase].where
                  << " with minimum separation " << rmin << " (lower -lattice_min_separation)";
                throw InputError(s.str());
              }
              Point x;
              for (int a = 0; a < 3; ++a)
                x[a] = p.fixed[a] ? p.at[a]
                                  : cell_box.lo[a] + uniform(spec.seed, phase, q, k, a) *
                                                         (cell_box.hi[a] - cell_box.lo[a]);
              if (!clear(c, x)) continue;
              mine.push_back(x);
              ++placed;
              for (const int r : grid.ranks_near(c, 1)) sent.push_back({q, x}), to.push_back(r);
            }
          }
        });
      });
      for (const Sent& s : route(comm, sent, to)) grid.points(grid.cell_at(s.cell)).push_back(s.x);
    }

  // Node ids: cell by cell in the grid's order, in the order placed.
  std::vector<std::int64_t> first(static_cast<std::size_t>(grid.cell_count()) + 1, 0);
  grid.for_each_owned([&](const Cell& c) {
    first[static_cast<std::size_t>(grid.index(c)) + 1] =
        static_cast<std::int64_t>(grid.points(c).size());
  });
  in_pieces(first.size(), std::uint64_t(1) << 27, [&](std::uint64_t at, int count) {
    MPI_Allreduce(MPI_IN_PLACE, first.data() + at, count, MPI_INT64_T, MPI_SUM, comm);
  });
  for (std::size_t q = 1; q < first.size(); ++q) first[q] += first[q - 1];
  const std::int64_t nodes = first.back();

  // Every point of the margin, for the triangulation (the neighbours' points
  // known so far are replaced by the complete lists).
  {
    struct Known {
      std::int64_t cell;
      Point x;
    };
    std::vector<Known> sent;
    std::vector<int> to;
    grid.for_each_owned([&](const Cell& c) {
      const std::int64_t q = grid.index(c);
      for (const int r : grid.ranks_near(c, kTriangulationMarginCells))
        for (const Point& x : grid.points(c)) sent.push_back({q, x}), to.push_back(r);
    });
    const std::vector<Known> got = route(comm, sent, to);
    for (int i = 0; i < n[0]; ++i)
      for (int j = 0; j < n[1]; ++j)
        for (int k = 0; k < n[2]; ++k)
          if (grid.known({i, j, k}) && !grid.owned({i, j, k})) grid.points({i, j, k}).clear();
    for (const Known& s : got) grid.points(grid.cell_at(s.cell)).push_back(s.x);
  }

  // The local Delaunay triangulation; vertex info: the point's index in
  // `id` and `mine` (whether it is a node of this rank's cells).
  std::vector<std::pair<Kernel::Point_3, std::int64_t>> input;
  std::vector<std::int64_t> id;
  std::vector<char> mine;
  for (int i = 0; i < n[0]; ++i)
    for (int j = 0; j < n[1]; ++j)
      for (int k = 0; k < n[2]; ++k) {
        const Cell c{i, j, k};
        if (!grid.known(c)) continue;
        const auto& list = grid.points(c);
        for (std::size_t p = 0; p < list.size(); ++p) {
          input.emplace_back(Kernel::Point_3(list[p][0], list[p][1], list[p][2]),
                             static_cast<std::int64_t>(id.size()));
          id.push_back(first[static_cast<std::size_t>(grid.index(c))] +
                       static_cast<std::int64_t>(p));
          mine.push_back(grid.owned(c) ? 1 : 0);
        }
      }
  Delaunay dt(input.begin(), input.end());
  input.clear();
  input.shrink_to_fit();

  // Certain: every tetrahedron at a node of this rank has its circumsphere,
  // within the box, inside the region this rank knows (then no point it
  // does not know can be in it); a hull facet there lies on a box face.
  const Box known = grid.known_region();
  run_collectively(comm, [&] {
    for (auto t = dt.all_cells_begin(); t != dt.all_cells_end(); ++t) {
      bool touches = false;
      for (int v = 0; v < 4; ++v)
        touches = touches || (!dt.is_infinite(t->vertex(v)) && mine[t->vertex(v)->info()]);
      if (!touches) continue;
      bool certain = true;
      if (dt.is_infinite(t)) {
        // The finite facet must lie in one face plane of the box.
        std::vector<Kernel::Point_3> f;
        for (int v = 0; v < 4; ++v)
          if (!dt.is_infinite(t->vertex(v))) f.push_back(t->vertex(v)->point());
        bool flat = false;
        for (int a = 0; a < 3 && !flat; ++a)
          for (const double side : {box.lo[a], box.hi[a]}) {
            bool all = true;
            for (const auto& p : f) all = all && p[a] == side;
            flat = flat || all;
          }
        certain = flat;
      } else {
        const Kernel::Point_3 centre =
            CGAL::circumcenter(t->vertex(0)->point(), t->vertex(1)->point(), t->vertex(2)->point(),
                               t->vertex(3)->point());
        const double radius2 = CGAL::squared_distance(centre, t->vertex(0)->point());
        // Along axis a, a point of the sphere inside the box lies within
        // sqrt(R^2 - the squared distances from the centre to the box on the
        // other axes) of the centre: tight for the flat tetrahedra of the
        // faces, whose spheres lie mostly outside the box.
        double gap[3];
        for (int a = 0; a < 3; ++a)
          gap[a] = std::max({0.0, box.lo[a] - centre[a], centre[a] - box.hi[a]});
        for (int a = 0; a < 3; ++a) {
          const double reach =
              std::sqrt(std::max(0.0, radius2 - gap[(a + 1) % 3] * gap[(a + 1) % 3] -
                                          gap[(a + 2) % 3] * gap[(a + 2) % 3]));
          const double lo = std::max(box.lo[a], centre[a] - reach);
          const double hi = std::min(box.hi[a], centre[a] + reach);
          if (lo < known.lo[a] || hi > known.hi[a]) certain = false;
        }
      }
      if (!certain) {
        const auto& p = t->vertex(dt.is_infinite(t->vertex(0)) ? 1 : 0)->point();
        std::ostringstream s;
        s << "random lattice: a margin of " << kTriangulationMarginCells
          << " generation cells is too thin to make the Delaunay edges of the nodes near (" << p.x()
          << ", " << p.y() << ", " << p.z() << ") certain on rank " << grid.rank()
          << " (a lattice this irregular needs the serial generator)";
        throw InputError(s.str());
      }
    }
  });

  // The edges of this rank's nodes: each kept by the rank of its lower id.
  struct Edge {
    std::int64_t i, j;
    Point xi, xj;
  };
  std::vector<Edge> edges;
  for (auto e = dt.finite_edges_begin(); e != dt.finite_edges_end(); ++e) {
    auto u = e->first->vertex(e->second), v = e->first->vertex(e->third);
    if (id[u->info()] > id[v->info()]) std::swap(u, v);
    if (!mine[u->info()]) continue;
    const auto& p = u->point();
    const auto& q = v->point();
    edges.push_back({id[u->info()], id[v->info()], {p.x(), p.y(), p.z()}, {q.x(), q.y(), q.z()}});
  }
  dt.clear();

  // Bond ids: edges sorted by their ends, through the ranks that hold the
  // blocks of their lower ends; then each bond to the rank of its id block.
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  const RowBlocks node_rows(nodes, ranks);
  std::vector<int> to(edges.size());
  for (std::size_t k = 0; k < edges.size(); ++k) to[k] = node_rows.rank_of(edges[k].i);
  std::vector<Edge> sorted = route(comm, edges, to);
  std::vector<Edge>().swap(edges);  // the memory back: the edges are the largest arrays here
  std::sort(sorted.begin(), sorted.end(),
            [](const Edge& a, const Edge& b) { return a.i != b.i ? a.i < b.i : a.j < b.j; });
  std::int64_t count = static_cast<std::int64_t>(sorted.size()), before = 0, bonds = 0;
  MPI_Exscan(&count, &before, 1, MPI_INT64_T, MPI_SUM, comm);
  MPI_Allreduce(&count, &bonds, 1, MPI_INT64_T, MPI_SUM, comm);
  if (grid.rank() == 0) before = 0;
  const RowBlocks bond_rows(bonds, ranks);
  to.resize(sorted.size());
  for (std::size_t k = 0; k < sorted.size(); ++k)
    to[k] = bond_rows.rank_of(before + static_cast<std::int64_t>(k));
  std::vector<Edge> block_edges = route(comm, sorted, to);  // in id order
  std::vector<Edge>().swap(sorted);

  LatticeBlock out;
  out.box = box;
  out.nodes = nodes;
  out.bonds = bonds;
  out.node_begin = node_rows.begin(grid.rank());
  out.bond_begin = bond_rows.begin(grid.rank());
  out.ends.reserve(block_edges.size());
  out.end_coords.reserve(block_edges.size());
  for (const Edge& e : block_edges) {
    out.ends.push_back({e.i, e.j});
    out.end_coords.push_back({e.xi, e.xj});
  }
  std::vector<Edge>().swap(block_edges);
  // Nodes to the ranks of their id blocks.
  struct Node {
    std::int64_t id;
    Point x;
  };
  std::vector<Node> owned;
  std::vector<int> node_to;
  grid.for_each_owned([&](const Cell& c) {
    const std::int64_t f = first[static_cast<std::size_t>(grid.index(c))];
    const auto& list = grid.points(c);
    for (std::size_t p = 0; p < list.size(); ++p) {
      owned.push_back({f + static_cast<std::int64_t>(p), list[p]});
      node_to.push_back(node_rows.rank_of(owned.back().id));
    }
  });
  std::vector<Node> block = route(comm, owned, node_to);
  std::sort(block.begin(), block.end(), [](const Node& a, const Node& b) { return a.id < b.id; });
  for (const Node& v : block) out.coords.push_back(v.x);
  return out;
}

}  // namespace lem
