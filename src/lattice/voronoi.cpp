// Box-clipped Voronoi cells by successive half-space clipping of a convex
// polyhedron that starts as the box.
//
// The polyhedron is a list of planar faces, each a cycle of vertex indices
// ordered counter-clockwise seen from outside.  Every combinatorial decision
// of a clip is taken from one sign per vertex (in / on / out, with a relative
// tolerance), and a cut edge gets one new vertex shared by both its faces, so
// the clipped surface stays closed whatever the rounding: the cap face is
// assembled from the on-plane edges of the kept faces, and the volume follows
// from the divergence theorem (a fan of tetrahedra from the node).
#include "lem/lattice/voronoi.hpp"

#include "lem/base/error.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <utility>

namespace lem {
namespace {

Point sub(const Point& a, const Point& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const Point& a, const Point& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
double triple(const Point& a, const Point& b, const Point& c) {
  return a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2]) +
         a[2] * (b[0] * c[1] - b[1] * c[0]);
}

// Largest coordinate magnitude or side of the box: the length scale of the
// rounding errors in the signed distances.
double length_scale(const Box& box) {
  double s = 0;
  for (int a = 0; a < 3; ++a)
    s = std::max({s, std::abs(box.lo[a]), std::abs(box.hi[a]), box.length(a)});
  return s;
}

// Vertices closer to a plane than this fraction of the length scale count as
// on it: they are kept unmoved instead of spawning sliver edges.  Far above
// rounding (1e-16) and far below anything that changes a volume measurably.
constexpr double kRelTol = 1e-12;

// Make `v` hold at least n elements.  Scratch arrays only grow, and their
// sizes are tracked apart, so reuse costs no allocation or initialisation.
template <class T>
T* grow(std::vector<T>& v, std::size_t n) {
  if (v.size() < n) v.resize(2 * n);
  return v.data();
}

class ConvexCell {
 public:
  void reset(const Box& box) {
    Poly& c = cur_;
    Point* vert = grow(c.vert, 8);
    for (int k = 0; k < 8; ++k)  // vertex k has x = hi iff bit 0, y iff bit 1, z iff bit 2
      vert[k] = {(k & 1) ? box.hi[0] : box.lo[0], (k & 2) ? box.hi[1] : box.lo[1],
                 (k & 4) ? box.hi[2] : box.lo[2]};
    // Counter-clockwise seen from outside: -x, +x, -y, +y, -z, +z.
    static constexpr int kFaces[24] = {0, 4, 6, 2, 1, 3, 7, 5, 0, 1, 5, 4,
                                       2, 6, 7, 3, 0, 2, 3, 1, 4, 5, 7, 6};
    std::copy(kFaces, kFaces + 24, grow(c.idx, 24));
    int* begin = grow(c.begin, 7);
    for (int f = 0; f <= 6; ++f) begin[f] = 4 * f;
    c.nv = 8;
    c.nf = 6;
  }

  bool empty() const { return cur_.nf == 0; }

  /// Keep {x : (x - m).n <= 0}; `tol` is in the units of (x - m).n.
  void clip(const Point& n, const Point& m, double tol) {
    const Poly& a = cur_;
    if (a.nf == 0) return;
    const std::size_t nv = a.nv, nf = a.nf, ni = a.begin[nf];
    double* const dist = grow(dist_, nv);
    std::int8_t* const side = grow(side_, nv);
    bool any_out = false, any_in = false;
    for (std::size_t v = 0; v < nv; ++v) {
      const double d = dot(n, sub(a.vert[v], m));
      const std::int8_t s = d > tol ? 1 : (d < -tol ? -1 : 0);
      any_out |= s > 0;
      any_in |= s < 0;
      dist[v] = s ? d : 0.0;
      side[v] = s;
    }
    if (!any_out) return;  // the plane misses the cell or only touches it
    if (!any_in) {         // nothing strictly inside: the cell is gone
      cur_.nf = 0;
      return;
    }

    // Sizes of the new lists, bounded without assuming exact convexity (the
    // signs around a face may alternate when it is nearly in the plane): at
    // most one cut point per face corner, so faces at most double; every cap
    // edge is an edge of a kept face, and every cap has at least 3 of them.
    Poly& b = next_;
    Point* const vert = grow(b.vert, nv + ni);
    char* const on = grow(on_plane_, nv + ni);
    int* const out = grow(b.idx, 4 * ni);
    int* const begin = grow(b.begin, nf + ni + 2);
    std::pair<int, int>* const cap = grow(cap_edges_, 2 * ni);
    grow(cuts_, ni);

    // Kept vertices (in or on) first, renumbered; cut points are appended by
    // cut_vertex.
    int* const remap = grow(remap_, nv);
    std::size_t kept = 0;
    for (std::size_t v = 0; v < nv; ++v) {
      remap[v] = static_cast<int>(kept);
      vert[kept] = a.vert[v];
      on[kept] = side[v] == 0;
      kept += side[v] <= 0;
    }
    b.nv = kept;
    ncuts_ = 0;
    std::fill_n(grow(first_cut_, nv), nv, -1);
    std::size_t ncap = 0;
    const int* const in = a.idx.data();
    std::size_t top = 0, faces = 0;
    begin[0] = 0;
    for (std::size_t f = 0; f < nf; ++f) {
      const int fb = a.begin[f], fe = a.begin[f + 1];
      const std::size_t start = top;
      // Edge (prev, cur): its cut point, then cur if kept.  `touched` says
      // whether the new face has a vertex on the plane.
      int prev = in[fe - 1];
      bool touched = false;
      for (int k = fb; k < fe; ++k) {
        const int cur = in[k];
        const int sc = side[cur];
        if (side[prev] * sc < 0) {
          out[top++] = cut_vertex(prev, cur);
          touched = true;
        }
        touched |= sc == 0;
        out[top] = remap[cur];
        top += sc <= 0;
        prev = cur;
      }
      if (top - start < 3) {  // the face was cut away (or shrank to an edge on the plane)
        top = start;
        continue;
      }
      // An edge of a kept face lying on the plane bounds the cap, which runs
      // through it the other way.
      if (touched) {
        int p = out[top - 1];
        for (std::size_t k = start; k < top; ++k) {
          const int q = out[k];
          if (on[p] && on[q]) cap[ncap++] = {q, p};
          p = q;
        }
      }
      begin[++faces] = static_cast<int>(top);
    }
    add_cap_faces(ncap, top, faces);
    b.nf = faces;
    std::swap(cur_, next_);
  }

  /// Divergence theorem: sum of the tetrahedra (ref, fan triangle) over faces.
  double volume(const Point& ref) const {
    const Poly& c = cur_;
    double v6 = 0;
    for (std::size_t f = 0; f < c.nf; ++f) {
      const int fb = c.begin[f], fe = c.begin[f + 1];
      const Point a = sub(c.vert[c.idx[fb]], ref);
      Point prev = sub(c.vert[c.idx[fb + 1]], ref);
      for (int k = fb + 2; k < fe; ++k) {
        const Point next = sub(c.vert[c.idx[k]], ref);
        v6 += triple(a, prev, next);
        prev = next;
      }
    }
    return v6 / 6.0;
  }

 private:
  // Faces are cycles of vertex indices, concatenated in idx; face f is
  // idx[begin[f] .. begin[f + 1]).  Only the first nv / nf entries are live.
  struct Poly {
    std::vector<Point> vert;
    std::vector<int> idx, begin;
    std::size_t nv = 0, nf = 0;
  };

  // The point where the plane cuts edge uw (one end strictly in, one strictly
  // out), created once and shared by the two faces of the edge.  Interpolated
  // from the inside end so both faces get the same coordinates.
  int cut_vertex(int u, int w) {
    const bool flip = side_[u] > 0;
    const int i = flip ? w : u, o = flip ? u : w;
    for (int c = first_cut_[i]; c >= 0; c = cuts_[c].next)
      if (cuts_[c].out == o) return cuts_[c].id;
    const double t = dist_[i] / (dist_[i] - dist_[o]);
    const Point& a = cur_.vert[i];
    const Point& b = cur_.vert[o];
    const int id = static_cast<int>(next_.nv++);
    next_.vert[id] = {a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])};
    on_plane_[id] = 1;
    cuts_[ncuts_] = {o, id, first_cut_[i]};
    first_cut_[i] = static_cast<int>(ncuts_++);
    return id;
  }

  // Chain the cap edges into cycles, appended as faces to next_ from `top`.
  // For an exactly convex cell there is one cycle and every cap vertex has
  // one outgoing edge; near-degenerate rounding can give several cycles or a
  // 2-cycle (an edge reported by both its faces), which are kept or dropped
  // as they come, so the surface stays closed and the volume right.
  void add_cap_faces(std::size_t ne, std::size_t& top, std::size_t& faces) {
    if (ne < 3) return;
    const std::pair<int, int>* const cap = cap_edges_.data();
    int* const out = next_.idx.data();
    // Fast path: successor table over the new vertices.
    int* const succ = grow(succ_, next_.nv);
    std::fill(succ, succ + next_.nv, -1);
    bool simple = true;
    for (std::size_t e = 0; e < ne; ++e) {
      if (succ[cap[e].first] >= 0) simple = false;
      succ[cap[e].first] = cap[e].second;
    }
    if (simple) {
      for (std::size_t e = 0; e < ne; ++e) {
        int cur = cap[e].first;
        if (succ[cur] < 0) continue;  // already in a cycle
        const std::size_t start = top;
        while (cur >= 0 && succ[cur] >= 0) {
          out[top++] = cur;
          const int nxt = succ[cur];
          succ[cur] = -1;
          cur = nxt;
        }
        close_cap(start, top, faces);
      }
      return;
    }
    // General walk, quadratic in the (few) edges.
    char* const used = grow(used_, ne);
    std::fill(used, used + ne, 0);
    for (std::size_t e0 = 0; e0 < ne; ++e0) {
      if (used[e0]) continue;
      used[e0] = 1;
      const std::size_t start = top;
      const int first = cap[e0].first;
      out[top++] = first;
      int cur = cap[e0].second;
      while (cur != first) {
        out[top++] = cur;
        std::size_t nxt = ne;
        for (std::size_t e = 0; e < ne; ++e)
          if (!used[e] && cap[e].first == cur) {
            nxt = e;
            break;
          }
        if (nxt == ne) break;  // open chain (should not happen): close it as is
        used[nxt] = 1;
        cur = cap[nxt].second;
      }
      close_cap(start, top, faces);
    }
  }

  void close_cap(std::size_t start, std::size_t& top, std::size_t& faces) {
    if (top - start < 3) {
      top = start;
      return;
    }
    next_.begin[++faces] = static_cast<int>(top);
  }

  Poly cur_, next_;
  std::vector<double> dist_;
  std::vector<std::int8_t> side_;
  std::vector<int> remap_, succ_;
  std::vector<char> on_plane_, used_;
  // Cut points made so far in this clip, listed per inside end of the edge.
  struct Cut {
    int out, id, next;  // outside end, new vertex, next cut from the same inside end
  };
  std::vector<Cut> cuts_;
  std::vector<int> first_cut_;
  std::size_t ncuts_ = 0;
  std::vector<std::pair<int, int>> cap_edges_;
};

// Clip `cell` (reset to the box) by the bisectors of node and each neighbour.
// Nearest neighbours first: they cut the most, so later planes see a small
// cell or miss it.
double cell_volume(ConvexCell& cell, const Box& box, double scale, const Point& node,
                   std::vector<std::pair<double, Point>>& neighbours) {
  for (auto& [d2, q] : neighbours) {
    const Point n = sub(q, node);
    d2 = dot(n, n);
  }
  std::sort(neighbours.begin(), neighbours.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  cell.reset(box);
  for (const auto& [d2, q] : neighbours) {
    if (d2 == 0) {
      std::ostringstream s;
      s << "Voronoi cells: two nodes coincide at (" << node[0] << ", " << node[1] << ", " << node[2]
        << ")";
      throw InputError(s.str());
    }
    // Bisector of node and q.  n and m are the same (up to the sign of n,
    // which is exact) when the cell of q is clipped by node, so the two
    // cells meet without gap or overlap beyond the tolerance.
    const Point n = sub(q, node);
    const Point m{0.5 * (node[0] + q[0]), 0.5 * (node[1] + q[1]), 0.5 * (node[2] + q[2])};
    cell.clip(n, m, kRelTol * scale * std::sqrt(d2));
    if (cell.empty()) return 0.0;
  }
  return cell.volume(node);
}

}  // namespace

struct ClippedCells::Work {
  Box box;
  double scale = 0;
  ConvexCell cell;
  std::vector<std::pair<double, Point>> list;
};

ClippedCells::ClippedCells(const Box& box) : work_(std::make_unique<Work>()) {
  work_->box = box;
  work_->scale = length_scale(box);
}

ClippedCells::~ClippedCells() = default;

double ClippedCells::volume(const Point& node, const std::vector<Point>& neighbours) {
  Work& w = *work_;
  w.list.clear();
  for (const Point& q : neighbours) w.list.emplace_back(0.0, q);
  return cell_volume(w.cell, w.box, w.scale, node, w.list);
}

double clipped_cell_volume(const Box& box, const Point& node,
                           const std::vector<Point>& neighbours) {
  return ClippedCells(box).volume(node, neighbours);
}

std::vector<double> voronoi_volumes(const Lattice& lattice) {
  const std::size_t n = lattice.node_count();
  // Neighbour lists (both directions) in compressed-row form.
  std::vector<std::size_t> begin(n + 1, 0);
  for (const Bond& b : lattice.bonds) {
    if (b.i < 0 || b.j < 0 || static_cast<std::size_t>(b.i) >= n ||
        static_cast<std::size_t>(b.j) >= n) {
      std::ostringstream s;
      s << "Voronoi cells: bond (" << b.i << ", " << b.j << ") names a node outside 0.." << n
        << "-1";
      throw InputError(s.str());
    }
    ++begin[b.i + 1];
    ++begin[b.j + 1];
  }
  for (std::size_t i = 0; i < n; ++i) begin[i + 1] += begin[i];
  std::vector<std::int32_t> adj(begin[n]);
  {
    std::vector<std::size_t> fill(begin.begin(), begin.end() - 1);
    for (const Bond& b : lattice.bonds) {
      adj[fill[b.i]++] = b.j;
      adj[fill[b.j]++] = b.i;
    }
  }

  ClippedCells cells(lattice.box);
  std::vector<Point> around;
  std::vector<double> volumes(n);
  for (std::size_t i = 0; i < n; ++i) {
    around.clear();
    for (std::size_t k = begin[i]; k < begin[i + 1]; ++k) around.push_back(lattice.nodes[adj[k]]);
    volumes[i] = cells.volume(lattice.nodes[i], around);
  }
  return volumes;
}

}  // namespace lem
