// A random lattice made in parallel, the same on any rank count: hard-core
// random points (the process of make_random_lattice: corners, then edges,
// faces and inside of the box at the density of the bulk) placed cell by
// cell of a grid, each cell's candidates drawn from a counter-based stream
// keyed by the cell, so that no point depends on which rank drew it; the
// cells of one of 8 colours are never neighbours and are filled at once,
// every rank its own, before the points near its cells' faces go to the
// ranks of the neighbouring cells.  Each rank then triangulates its cells'
// points with those of a margin of cells around them (CGAL) and keeps the
// Delaunay edges of its nodes, checked to be those of the whole lattice.
// Its points differ from make_random_lattice's (another random stream),
// not its statistics.
#pragma once

#include "lem/lattice/lattice.hpp"

#include <mpi.h>

#include <array>
#include <cstdint>
#include <vector>

namespace lem {

/// This rank's share of a lattice: a block of its node ids and a block of
/// its bond ids (lem::RowBlocks over the ranks).  Node ids follow the cells
/// of the generation grid; bonds are sorted by their ends (i < j).
struct LatticeBlock {
  Box box;
  std::int64_t nodes = 0, bonds = 0;              // of the whole lattice
  std::int64_t node_begin = 0, bond_begin = 0;    // this rank's first ids
  std::vector<Point> coords;                      // nodes node_begin, ...
  std::vector<std::array<std::int64_t, 2>> ends;  // bonds bond_begin, ...
  std::vector<std::array<Point, 2>> end_coords;
};

/// Cells of the generation grid are at least this many mean spacings wide
/// (about 64 points each), and each rank triangulates a margin of this many
/// cells around its own.
inline constexpr double kGenerationCellSpacings = 4.0;
inline constexpr int kTriangulationMarginCells = 2;

/// Collective.  The same lattice (coordinates and bonds, bit for bit) for
/// the same spec on any number of ranks.  Throws InputError for the cases
/// make_random_lattice refuses, and when a rank's margin is too thin to
/// make its Delaunay edges certain.
LatticeBlock make_cell_lattice(MPI_Comm comm, const RandomLatticeSpec& spec);

}  // namespace lem
