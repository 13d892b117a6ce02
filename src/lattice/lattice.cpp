#include "lem/lattice/lattice.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

namespace lem {

double Lattice::bond_length(std::size_t b) const {
  const Point& p = nodes[bonds[b].i];
  const Point& q = nodes[bonds[b].j];
  return std::sqrt((q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]) +
                   (q[2] - p[2]) * (q[2] - p[2]));
}

LatticeStats lattice_stats(const Lattice& lattice) {
  LatticeStats s;
  s.nodes = static_cast<std::int64_t>(lattice.node_count());
  s.bonds = static_cast<std::int64_t>(lattice.bond_count());
  if (s.bonds == 0) return s;
  double sum = 0, sum2 = 0;
  s.min_length = lattice.bond_length(0);
  s.max_length = s.min_length;
  for (std::size_t b = 0; b < lattice.bond_count(); ++b) {
    const double l = lattice.bond_length(b);
    sum += l;
    sum2 += l * l;
    s.min_length = std::min(s.min_length, l);
    s.max_length = std::max(s.max_length, l);
  }
  const double n = static_cast<double>(s.bonds);
  s.mean_length = sum / n;
  s.std_length = std::sqrt(std::max(0.0, sum2 / n - s.mean_length * s.mean_length));
  s.mean_coordination = 2.0 * n / static_cast<double>(s.nodes);
  s.mesh_density = std::pow(n, -1.0 / 3.0);
  return s;
}

std::uint8_t faces_of(const Point& p, const Box& box, double tol) {
  const double eps = tol * std::min({box.length(0), box.length(1), box.length(2)});
  std::uint8_t flags = 0;
  for (int a = 0; a < 3; ++a) {
    if (p[a] <= box.lo[a] + eps) flags |= static_cast<std::uint8_t>(1 << (2 * a));
    if (p[a] >= box.hi[a] - eps) flags |= static_cast<std::uint8_t>(1 << (2 * a + 1));
  }
  return flags;
}

std::vector<std::uint8_t> face_flags(const Lattice& lattice, double tol) {
  std::vector<std::uint8_t> flags(lattice.node_count(), 0);
  for (std::size_t n = 0; n < lattice.node_count(); ++n)
    flags[n] = faces_of(lattice.nodes[n], lattice.box, tol);
  return flags;
}

std::string empty_face_problem(std::int64_t bottom, std::int64_t top) {
  if (bottom > 0 && top > 0) return "";
  const char* face = bottom == 0 && top == 0 ? "neither the bottom nor the top face"
                     : bottom == 0           ? "the bottom face"
                                             : "the top face";
  return std::string("tension: no node lies on ") + face +
         " of the box (within 1e-9 of its shortest side): the box does not fit the nodes (an "
         "edited box_lo/box_hi, or coordinates rounded when the file was copied)";
}

double face_share(std::uint8_t faces_i, std::uint8_t faces_j) {
  return std::ldexp(1.0, -std::popcount(unsigned(faces_i & faces_j)));
}

void halve_face_bonds(Lattice& lattice) {
  const auto faces = face_flags(lattice);
  for (std::size_t b = 0; b < lattice.bond_count(); ++b) {
    const Bond& bond = lattice.bonds[b];
    const double share = face_share(faces[bond.i], faces[bond.j]);
    if (share == 1.0) continue;
    lattice.stiffness[b] *= share;
    if (!lattice.strength.empty()) lattice.strength[b] *= share;
  }
}

Lattice make_fcc_lattice(std::array<int, 3> cells, double a, double k) {
  return make_fcc_block({2 * cells[0], 2 * cells[1], 2 * cells[2]}, a, k);
}

Lattice make_fcc_block(std::array<int, 3> half_cells, double a, double k) {
  // Sites are the points of a grid of spacing h = c/2 (c = a*sqrt(2), the cube
  // side) whose integer coordinates have an even sum.
  const double h = a / std::sqrt(2.0);
  const int n[3] = {half_cells[0] + 1, half_cells[1] + 1, half_cells[2] + 1};
  std::vector<std::int32_t> site(static_cast<std::size_t>(n[0]) * n[1] * n[2], -1);
  auto at = [&](int i, int j, int l) -> std::int32_t& {
    return site[(static_cast<std::size_t>(i) * n[1] + j) * n[2] + l];
  };
  Lattice lattice;
  lattice.box.lo = {0, 0, 0};
  lattice.box.hi = {half_cells[0] * h, half_cells[1] * h, half_cells[2] * h};
  for (int i = 0; i < n[0]; ++i)
    for (int j = 0; j < n[1]; ++j)
      for (int l = 0; l < n[2]; ++l)
        if ((i + j + l) % 2 == 0) {
          at(i, j, l) = static_cast<std::int32_t>(lattice.nodes.size());
          lattice.nodes.push_back({i * h, j * h, l * h});
        }
  // The six nearest-neighbour directions with a positive first nonzero entry.
  const int dirs[6][3] = {{1, 1, 0}, {1, -1, 0}, {1, 0, 1}, {1, 0, -1}, {0, 1, 1}, {0, 1, -1}};
  for (int i = 0; i < n[0]; ++i)
    for (int j = 0; j < n[1]; ++j)
      for (int l = 0; l < n[2]; ++l) {
        if ((i + j + l) % 2) continue;
        for (const auto& d : dirs) {
          const int p[3] = {i + d[0], j + d[1], l + d[2]};
          if (p[0] < 0 || p[0] >= n[0] || p[1] < 0 || p[1] >= n[1] || p[2] < 0 || p[2] >= n[2])
            continue;
          const std::int32_t u = at(i, j, l), v = at(p[0], p[1], p[2]);
          lattice.bonds.push_back(Bond{std::min(u, v), std::max(u, v)});
          lattice.stiffness.push_back(k);
        }
      }
  // Sort bonds (and their stiffness) into the canonical order.
  std::vector<std::size_t> order(lattice.bonds.size());
  for (std::size_t b = 0; b < order.size(); ++b) order[b] = b;
  std::sort(order.begin(), order.end(),
            [&](std::size_t x, std::size_t y) { return lattice.bonds[x] < lattice.bonds[y]; });
  std::vector<Bond> bonds(order.size());
  std::vector<double> stiffness(order.size());
  for (std::size_t b = 0; b < order.size(); ++b) {
    bonds[b] = lattice.bonds[order[b]];
    stiffness[b] = lattice.stiffness[order[b]];
  }
  lattice.bonds = std::move(bonds);
  lattice.stiffness = std::move(stiffness);
  // The block is an exact share of the infinite lattice: a bond in a face
  // is half inside it.
  halve_face_bonds(lattice);
  return lattice;
}

}  // namespace lem

namespace lem {

void add_affine_bond(AffineModuli& m, const Point& p, const Point& q, double k, double volume) {
  const double d[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
  const double l2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
  // k L^2 n_i n_j n_k n_l = k d_i d_j d_k d_l / L^2
  const double v[6] = {d[0] * d[0], d[1] * d[1], d[2] * d[2],
                       d[1] * d[2], d[0] * d[2], d[0] * d[1]};
  const double w = k / (l2 * volume);
  for (int I = 0; I < 6; ++I)
    for (int J = 0; J < 6; ++J) m.C[I][J] += w * v[I] * v[J];
}

AffineModuli affine_moduli(const Lattice& lattice) {
  AffineModuli m;
  for (std::size_t b = 0; b < lattice.bond_count(); ++b)
    add_affine_bond(m, lattice.nodes[lattice.bonds[b].i], lattice.nodes[lattice.bonds[b].j],
                    lattice.stiffness[b], lattice.box.volume());
  finish_affine_moduli(m);
  return m;
}

void finish_affine_moduli(AffineModuli& m) {
  // Compliance by Gauss-Jordan elimination with partial pivoting.
  double a[6][12] = {};
  for (int I = 0; I < 6; ++I) {
    for (int J = 0; J < 6; ++J) a[I][J] = m.C[I][J];
    a[I][6 + I] = 1;
  }
  for (int c = 0; c < 6; ++c) {
    int pivot = c;
    for (int r = c + 1; r < 6; ++r)
      if (std::fabs(a[r][c]) > std::fabs(a[pivot][c])) pivot = r;
    if (a[pivot][c] == 0) return;  // singular (e.g. empty lattice): leave zeros
    for (int k = 0; k < 12; ++k) std::swap(a[c][k], a[pivot][k]);
    const double inv = 1.0 / a[c][c];
    for (int k = 0; k < 12; ++k) a[c][k] *= inv;
    for (int r = 0; r < 6; ++r)
      if (r != c) {
        const double f = a[r][c];
        for (int k = 0; k < 12; ++k) a[r][k] -= f * a[c][k];
      }
  }
  const double s33 = a[2][6 + 2], s13 = a[0][6 + 2], s23 = a[1][6 + 2];
  m.young_z = 1.0 / s33;
  m.poisson_z = -(s13 + s23) / (2.0 * s33);
}

}  // namespace lem
