// The lattice generated in parallel (make_cell_lattice) at 1 to 4 ranks:
// the same nodes and bonds, bit for bit, on every rank count that divides
// the ranks of the test; its bonds are exactly the Delaunay edges of its
// points (CGAL, serially); no two points closer than the minimum
// separation; its size and coordination those of the serial generator.
#include "lem/lattice/cell_lattice.hpp"
#include "lem/base/collective.hpp"
#include "lem/lattice/lattice.hpp"

#include "../world.hpp"

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

using namespace lem;

namespace {

RandomLatticeSpec spec_of(std::int64_t bonds, std::uint64_t seed) {
  RandomLatticeSpec s;
  s.box.hi = {1.0, 1.2, 0.9};
  s.bonds = bonds;
  s.seed = seed;
  return s;
}

struct NodeRow {
  std::int64_t id;
  Point x;
};

struct BondRow {
  std::int64_t id, i, j;
};

// The whole lattice of `comm`'s blocks, on every rank of `comm` (a test may gather).
void gather(MPI_Comm comm, const LatticeBlock& b, std::vector<NodeRow>& nodes,
            std::vector<BondRow>& bonds) {
  std::vector<NodeRow> n;
  for (std::size_t k = 0; k < b.coords.size(); ++k)
    n.push_back({b.node_begin + static_cast<std::int64_t>(k), b.coords[k]});
  std::vector<BondRow> m;
  for (std::size_t k = 0; k < b.ends.size(); ++k)
    m.push_back({b.bond_begin + static_cast<std::int64_t>(k), b.ends[k][0], b.ends[k][1]});
  nodes = allgather(comm, n);
  bonds = allgather(comm, m);
}

// An order-free fingerprint of every bit of the lattice.
std::uint64_t fingerprint(const std::vector<NodeRow>& nodes, const std::vector<BondRow>& bonds) {
  std::uint64_t h = 0;
  for (const NodeRow& n : nodes) {
    std::uint64_t bits[3];
    std::memcpy(bits, n.x.data(), sizeof(bits));
    h += (static_cast<std::uint64_t>(n.id) + 1) * 0x9e3779b97f4a7c15ULL ^ bits[0] ^ (bits[1] << 1) ^
         (bits[2] << 2);
  }
  for (const BondRow& b : bonds)
    h += (static_cast<std::uint64_t>(b.id) * 1000003ULL) ^ (static_cast<std::uint64_t>(b.i) << 20) ^
         static_cast<std::uint64_t>(b.j);
  return h;
}

}  // namespace

TEST(CellLattice, TheSameLatticeOnEveryRankCount) {
  const RandomLatticeSpec spec = spec_of(30000, 7);
  std::vector<std::uint64_t> prints;
  for (int size = world_size(); size >= 1; --size) {
    if (world_size() % size != 0) continue;
    MPI_Comm part;
    MPI_Comm_split(PETSC_COMM_WORLD, world_rank() / size, world_rank(), &part);
    const LatticeBlock b = make_cell_lattice(part, spec);
    std::vector<NodeRow> nodes;
    std::vector<BondRow> bonds;
    gather(part, b, nodes, bonds);
    prints.push_back(fingerprint(nodes, bonds));
    EXPECT_EQ(static_cast<std::int64_t>(nodes.size()), b.nodes);
    EXPECT_EQ(static_cast<std::int64_t>(bonds.size()), b.bonds);
    MPI_Comm_free(&part);
  }
  for (std::size_t k = 1; k < prints.size(); ++k)
    EXPECT_EQ(prints[k], prints[0]) << "rank count number " << k;
}

TEST(CellLattice, BondsAreTheDelaunayEdgesOfItsPoints) {
  const RandomLatticeSpec spec = spec_of(30000, 11);
  const LatticeBlock b = make_cell_lattice(PETSC_COMM_WORLD, spec);
  std::vector<NodeRow> nodes;
  std::vector<BondRow> bonds;
  gather(PETSC_COMM_WORLD, b, nodes, bonds);
  std::sort(nodes.begin(), nodes.end(), [](auto& p, auto& q) { return p.id < q.id; });
  std::sort(bonds.begin(), bonds.end(), [](auto& p, auto& q) { return p.id < q.id; });
  ASSERT_EQ(static_cast<std::int64_t>(nodes.size()), target_node_count(spec));
  for (std::size_t k = 0; k < nodes.size(); ++k)
    ASSERT_EQ(nodes[k].id, static_cast<std::int64_t>(k));

  using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
  using Vb = CGAL::Triangulation_vertex_base_with_info_3<std::int64_t, Kernel>;
  using Tds =
      CGAL::Triangulation_data_structure_3<Vb, CGAL::Delaunay_triangulation_cell_base_3<Kernel>>;
  std::vector<std::pair<Kernel::Point_3, std::int64_t>> input;
  for (const NodeRow& n : nodes) input.emplace_back(Kernel::Point_3(n.x[0], n.x[1], n.x[2]), n.id);
  const CGAL::Delaunay_triangulation_3<Kernel, Tds> dt(input.begin(), input.end());
  std::vector<std::array<std::int64_t, 2>> edges;
  for (auto e = dt.finite_edges_begin(); e != dt.finite_edges_end(); ++e) {
    const std::int64_t i = e->first->vertex(e->second)->info(),
                       j = e->first->vertex(e->third)->info();
    edges.push_back({std::min(i, j), std::max(i, j)});
  }
  std::sort(edges.begin(), edges.end());
  ASSERT_EQ(edges.size(), bonds.size());
  for (std::size_t k = 0; k < bonds.size(); ++k) {
    ASSERT_EQ(bonds[k].id, static_cast<std::int64_t>(k));
    ASSERT_EQ(bonds[k].i, edges[k][0]) << "bond " << k;
    ASSERT_EQ(bonds[k].j, edges[k][1]) << "bond " << k;
  }

  // Hard core: no bond (nearest neighbours among them) shorter than rmin.
  const double spacing = std::cbrt(spec.box.volume() / static_cast<double>(nodes.size()));
  double shortest = 1e300;
  for (const BondRow& m : bonds) {
    const Point &p = nodes[m.i].x, &q = nodes[m.j].x;
    shortest =
        std::min(shortest, std::sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                                     (p[2] - q[2]) * (p[2] - q[2])));
  }
  EXPECT_GE(shortest, spec.min_separation * spacing * (1 - 1e-12));
  // The serial generator's lattice of the same spec: the same nodes, bonds
  // within 1 %.
  const Lattice serial = make_random_lattice(spec);
  EXPECT_EQ(serial.node_count(), nodes.size());
  EXPECT_NEAR(static_cast<double>(bonds.size()), static_cast<double>(serial.bond_count()),
              0.01 * static_cast<double>(serial.bond_count()));
}
