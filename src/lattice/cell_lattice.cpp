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

// The four phases of the point process in the order they place: the box's
// corners, its edges, its faces and its inside, each cell its share.
std::array<Phase, 4> placement_phases(const Box& box, const Grid& grid, const PointCounts& counts) {
  const Cell n = grid.counts();
  const auto side_at = [box](int a, int s) { return s ? box.hi[a] : box.lo[a]; };
  const auto on_side = [n](const Cell& c, int a, int s) { return c[a] == (s ? n[a] - 1 : 0); };
  const auto corners = [=](const Cell& c) {
    std::vector<Placement> out;
    for (int k = 0; k < 8; ++k) {
      const int s[3] = {k & 1, (k >> 1) & 1, (k >> 2) & 1};
      if (on_side(c, 0, s[0]) && on_side(c, 1, s[1]) && on_side(c, 2, s[2]))
        out.push_back({1, {1, 1, 1}, {side_at(0, s[0]), side_at(1, s[1]), side_at(2, s[2])}});
    }
    return out;
  };
  const auto edges = [=](const Cell& c) {
    std::vector<Placement> out;
    for (int a = 0; a < 3; ++a) {  // edges parallel to axis a
      const int b = (a + 1) % 3, d = (a + 2) % 3;
      for (int s = 0; s < 4; ++s) {
        if (!on_side(c, b, s & 1) || !on_side(c, d, (s >> 1) & 1)) continue;
        Placement p{share(counts.edge[a], c[a], n[a]), {1, 1, 1}, {}};
        p.fixed[a] = 0;
        p.at[b] = side_at(b, s & 1);
        p.at[d] = side_at(d, (s >> 1) & 1);
        out.push_back(p);
      }
    }
    return out;
  };
  const auto faces = [=](const Cell& c) {
    std::vector<Placement> out;
    for (int a = 0; a < 3; ++a) {  // faces normal to axis a
      const int b = (a + 1) % 3, d = (a + 2) % 3;
      for (int s = 0; s < 2; ++s) {
        if (!on_side(c, a, s)) continue;
        Placement p{share(counts.face[a], std::int64_t(c[b]) * n[d] + c[d],
                          std::int64_t(n[b]) * n[d]),
                    {0, 0, 0},
                    {}};
        p.fixed[a] = 1;
        p.at[a] = side_at(a, s);
        out.push_back(p);
      }
    }
    return out;
  };
  const std::int64_t inside = counts.inside;
  const auto bulk = [&grid, inside](const Cell& c) {
    return std::vector<Placement>{{share(inside, grid.index(c), grid.cell_count()), {0, 0, 0}, {}}};
  };
  return {Phase{"box corners", corners}, Phase{"box edges", edges}, Phase{"box faces", faces},
          Phase{"inside of the box", bulk}};
}

// Whether no point of c or of a neighbouring cell lies within sqrt(r2) of p.
bool clear_of_others(Grid& grid, const Cell& c, const Point& p, double r2) {
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
}

// A new point that other ranks must learn: its cell and position.
struct Sent {
  std::int64_t cell;
  Point x;
};

// One phase's points in one cell of this rank, by random sequential
// addition: a candidate is kept when it is clear of the points known; each
// kept point is added to `sent` for the ranks next to the cell.
void place_in_cell(Grid& grid, const Cell& c, const Phase& phase, int phase_index,
                   std::uint64_t seed, double rmin, std::vector<Sent>& sent, std::vector<int>& to) {
  const std::int64_t q = grid.index(c);
  const Box cell_box = grid.extent(c);
  std::int64_t k = 0;
  std::vector<Point>& mine = grid.points(c);
  for (const Placement& p : phase.in_cell(c)) {
    std::int64_t placed = 0;
    const std::int64_t max_tries = 200 * p.count + 1000;
    for (std::int64_t tries = 0; placed < p.count; ++tries, ++k) {
      if (tries >= max_tries) {
        std::ostringstream s;
        s << "random lattice: could only place " << placed << " of " << p.count
          << " points of a cell on the " << phase.where << " with minimum separation " << rmin
          << " (lower -lattice_min_separation)";
        throw InputError(s.str());
      }
      Point x;
      for (int a = 0; a < 3; ++a)
        x[a] = p.fixed[a] ? p.at[a]
                          : cell_box.lo[a] + uniform(seed, phase_index, q, k, a) *
                                                 (cell_box.hi[a] - cell_box.lo[a]);
      if (!clear_of_others(grid, c, x, rmin * rmin)) continue;
      mine.push_back(x);
      ++placed;
      for (const int r : grid.ranks_near(c, 1)) sent.push_back({q, x}), to.push_back(r);
    }
  }
}

// The hard-core points, phase by phase and colour by colour: the cells of
// one colour are never neighbours, so every rank places in its cells of a
// colour at once, then tells the ranks next to them what it placed.
void place_points(MPI_Comm comm, Grid& grid, const std::array<Phase, 4>& phases, std::uint64_t seed,
                  double rmin) {
  for (int phase = 0; phase < 4; ++phase)
    for (int hue = 0; hue < 8; ++hue) {
      std::vector<Sent> sent;
      std::vector<int> to;
      run_collectively(comm, [&] {
        grid.for_each_owned([&](const Cell& c) {
          if (colour(c) == hue) place_in_cell(grid, c, phases[phase], phase, seed, rmin, sent, to);
        });
      });
      for (const Sent& s : route(comm, sent, to)) grid.points(grid.cell_at(s.cell)).push_back(s.x);
    }
}

// Node ids: cell by cell in the grid's order, in the order placed. Entry q
// is the first id of cell q; the last entry is the node count.
std::vector<std::int64_t> first_node_ids(MPI_Comm comm, Grid& grid) {
  std::vector<std::int64_t> first(static_cast<std::size_t>(grid.cell_count()) + 1, 0);
  grid.for_each_owned([&](const Cell& c) {
    first[static_cast<std::size_t>(grid.index(c)) + 1] =
        static_cast<std::int64_t>(grid.points(c).size());
  });
  in_pieces(first.size(), std::uint64_t(1) << 27, [&](std::uint64_t at, int count) {
    MPI_Allreduce(MPI_IN_PLACE, first.data() + at, count, MPI_INT64_T, MPI_SUM, comm);
  });
  for (std::size_t q = 1; q < first.size(); ++q) first[q] += first[q - 1];
  return first;
}

// Calls visit(cell) for every cell whose points this rank knows.
template <class Visit>
void for_each_known(const Grid& grid, Visit&& visit) {
  const Cell n = grid.counts();
  for (int i = 0; i < n[0]; ++i)
    for (int j = 0; j < n[1]; ++j)
      for (int k = 0; k < n[2]; ++k)
        if (grid.known({i, j, k})) visit(Cell{i, j, k});
}

// Every point of the margin, for the triangulation (the neighbours' points
// known so far are replaced by the complete lists).
void learn_margin(MPI_Comm comm, Grid& grid) {
  std::vector<Sent> sent;
  std::vector<int> to;
  grid.for_each_owned([&](const Cell& c) {
    const std::int64_t q = grid.index(c);
    for (const int r : grid.ranks_near(c, kTriangulationMarginCells))
      for (const Point& x : grid.points(c)) sent.push_back({q, x}), to.push_back(r);
  });
  const std::vector<Sent> got = route(comm, sent, to);
  for_each_known(grid, [&](const Cell& c) {
    if (!grid.owned(c)) grid.points(c).clear();
  });
  for (const Sent& s : got) grid.points(grid.cell_at(s.cell)).push_back(s.x);
}

// The points a rank triangulates; a vertex's info is its index in `id`
// (its node id) and `mine` (whether it is a node of this rank's cells).
struct KnownPoints {
  std::vector<std::pair<DelaunayKernel::Point_3, std::int64_t>> input;
  std::vector<std::int64_t> id;
  std::vector<char> mine;
};

KnownPoints known_points(Grid& grid, const std::vector<std::int64_t>& first) {
  KnownPoints out;
  for_each_known(grid, [&](const Cell& c) {
    const auto& list = grid.points(c);
    for (std::size_t p = 0; p < list.size(); ++p) {
      out.input.emplace_back(Kernel::Point_3(list[p][0], list[p][1], list[p][2]),
                             static_cast<std::int64_t>(out.id.size()));
      out.id.push_back(first[static_cast<std::size_t>(grid.index(c))] +
                       static_cast<std::int64_t>(p));
      out.mine.push_back(grid.owned(c) ? 1 : 0);
    }
  });
  return out;
}

// Whether the finite facet of a hull tetrahedron lies in one face plane of
// the box.
bool facet_on_box_face(const Delaunay& dt, Delaunay::Cell_handle t, const Box& box) {
  std::vector<Kernel::Point_3> f;
  for (int v = 0; v < 4; ++v)
    if (!dt.is_infinite(t->vertex(v))) f.push_back(t->vertex(v)->point());
  for (int a = 0; a < 3; ++a)
    for (const double side : {box.lo[a], box.hi[a]}) {
      bool all = true;
      for (const auto& p : f) all = all && p[a] == side;
      if (all) return true;
    }
  return false;
}

// Whether the part within the box of a finite tetrahedron's circumsphere
// lies in the region `known`.
bool sphere_known(Delaunay::Cell_handle t, const Box& box, const Box& known) {
  const Kernel::Point_3 centre = CGAL::circumcenter(t->vertex(0)->point(), t->vertex(1)->point(),
                                                    t->vertex(2)->point(), t->vertex(3)->point());
  const double radius2 = CGAL::squared_distance(centre, t->vertex(0)->point());
  // Along axis a, a point of the sphere inside the box lies within
  // sqrt(R^2 - the squared distances from the centre to the box on the
  // other axes) of the centre: tight for the flat tetrahedra of the
  // faces, whose spheres lie mostly outside the box.
  double gap[3];
  for (int a = 0; a < 3; ++a)
    gap[a] = std::max({0.0, box.lo[a] - centre[a], centre[a] - box.hi[a]});
  for (int a = 0; a < 3; ++a) {
    const double reach = std::sqrt(std::max(0.0, radius2 - gap[(a + 1) % 3] * gap[(a + 1) % 3] -
                                                     gap[(a + 2) % 3] * gap[(a + 2) % 3]));
    const double lo = std::max(box.lo[a], centre[a] - reach);
    const double hi = std::min(box.hi[a], centre[a] + reach);
    if (lo < known.lo[a] || hi > known.hi[a]) return false;
  }
  return true;
}

// Certain: every tetrahedron at a node of this rank has its circumsphere,
// within the box, inside the region this rank knows (then no point it
// does not know can be in it); a hull facet there lies on a box face.
void check_certain(MPI_Comm comm, const Delaunay& dt, const std::vector<char>& mine, const Box& box,
                   const Grid& grid) {
  const Box known = grid.known_region();
  run_collectively(comm, [&] {
    for (auto t = dt.all_cells_begin(); t != dt.all_cells_end(); ++t) {
      bool touches = false;
      for (int v = 0; v < 4; ++v)
        touches = touches || (!dt.is_infinite(t->vertex(v)) && mine[t->vertex(v)->info()]);
      if (!touches) continue;
      const bool certain =
          dt.is_infinite(t) ? facet_on_box_face(dt, t, box) : sphere_known(t, box, known);
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
}

struct Edge {
  std::int64_t i, j;
  Point xi, xj;
};

// The edges of this rank's nodes: each kept by the rank of its lower id.
std::vector<Edge> own_edges(const Delaunay& dt, const KnownPoints& points) {
  std::vector<Edge> edges;
  for (auto e = dt.finite_edges_begin(); e != dt.finite_edges_end(); ++e) {
    auto u = e->first->vertex(e->second), v = e->first->vertex(e->third);
    if (points.id[u->info()] > points.id[v->info()]) std::swap(u, v);
    if (!points.mine[u->info()]) continue;
    const auto& p = u->point();
    const auto& q = v->point();
    edges.push_back(
        {points.id[u->info()], points.id[v->info()], {p.x(), p.y(), p.z()}, {q.x(), q.y(), q.z()}});
  }
  return edges;
}

// Bond ids: edges sorted by their ends, through the ranks that hold the
// blocks of their lower ends; then each bond to the rank of its id block.
// Fills the bonds of `out` (its node count set); takes the edges' memory.
void number_bonds(MPI_Comm comm, std::vector<Edge>& edges, LatticeBlock& out) {
  int rank = 0, ranks = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &ranks);
  const RowBlocks node_rows(out.nodes, ranks);
  std::vector<int> to(edges.size());
  for (std::size_t k = 0; k < edges.size(); ++k) to[k] = node_rows.rank_of(edges[k].i);
  std::vector<Edge> sorted = route(comm, edges, to);
  std::vector<Edge>().swap(edges);  // the memory back: the edges are the largest arrays here
  std::sort(sorted.begin(), sorted.end(),
            [](const Edge& a, const Edge& b) { return a.i != b.i ? a.i < b.i : a.j < b.j; });
  std::int64_t count = static_cast<std::int64_t>(sorted.size()), before = 0, bonds = 0;
  MPI_Exscan(&count, &before, 1, MPI_INT64_T, MPI_SUM, comm);
  MPI_Allreduce(&count, &bonds, 1, MPI_INT64_T, MPI_SUM, comm);
  if (rank == 0) before = 0;
  const RowBlocks bond_rows(bonds, ranks);
  to.resize(sorted.size());
  for (std::size_t k = 0; k < sorted.size(); ++k)
    to[k] = bond_rows.rank_of(before + static_cast<std::int64_t>(k));
  std::vector<Edge> block_edges = route(comm, sorted, to);  // in id order
  std::vector<Edge>().swap(sorted);

  out.bonds = bonds;
  out.bond_begin = bond_rows.begin(rank);
  out.ends.reserve(block_edges.size());
  out.end_coords.reserve(block_edges.size());
  for (const Edge& e : block_edges) {
    out.ends.push_back({e.i, e.j});
    out.end_coords.push_back({e.xi, e.xj});
  }
}

// Nodes to the ranks of their id blocks: the node rows of `out` (its node
// count set).
void gather_node_block(MPI_Comm comm, Grid& grid, const std::vector<std::int64_t>& first,
                       LatticeBlock& out) {
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  const RowBlocks node_rows(out.nodes, ranks);
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
  out.node_begin = node_rows.begin(grid.rank());
  for (const Node& v : block) out.coords.push_back(v.x);
}

}  // namespace

static_assert(kTriangulationMarginCells >= 1,
              "the random sequential addition reads the cells next to a rank's own");

LatticeBlock make_cell_lattice(MPI_Comm comm, const RandomLatticeSpec& spec) {
  const PointCounts counts = point_counts(spec.box, target_node_count(spec));
  const double rmin = spec.min_separation * counts.spacing;
  Grid grid(comm, spec.box, std::max(rmin, kGenerationCellSpacings * counts.spacing));
  place_points(comm, grid, placement_phases(spec.box, grid, counts), spec.seed, rmin);
  const std::vector<std::int64_t> first = first_node_ids(comm, grid);
  learn_margin(comm, grid);

  KnownPoints points = known_points(grid, first);
  Delaunay dt(points.input.begin(), points.input.end());
  std::vector<std::pair<Kernel::Point_3, std::int64_t>>().swap(points.input);
  check_certain(comm, dt, points.mine, spec.box, grid);
  std::vector<Edge> edges = own_edges(dt, points);
  dt.clear();

  LatticeBlock out;
  out.box = spec.box;
  out.nodes = first.back();
  number_bonds(comm, edges, out);
  gather_node_block(comm, grid, first, out);
  return out;
}

}  // namespace lem
