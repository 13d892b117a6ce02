// Voronoi volume of every lattice node, clipped to the sample box: the |V^i|
// of the node stress sigma^i = (1/|V^i|) sum_j r^ij (x) f^ij (paper eq. 1,
// appendix C) and the weight of a node when measuring phase volume fractions.
//
// The Voronoi neighbours of a node are among its Delaunay neighbours, so the
// cell of node i is the box cut by the bisector half-space of every bond ij;
// no geometric search is needed.  The cells partition the box: the volumes
// sum to the box volume up to rounding (below 1e-13 relative in the tests).
#pragma once

#include "lem/lattice/lattice.hpp"

#include <memory>
#include <vector>

namespace lem {

/// Volume of {x in box : |x - node| <= |x - q| for every q in neighbours}.
/// Neighbours that give no face of the cell are harmless (only cost time).
/// Throws InputError if a neighbour coincides with the node.
double clipped_cell_volume(const Box& box, const Point& node, const std::vector<Point>& neighbours);

/// clipped_cell_volume for many nodes of one box, one after the other,
/// reusing its work space (the cells of a million nodes without a million
/// allocations).
class ClippedCells {
 public:
  explicit ClippedCells(const Box& box);
  ~ClippedCells();
  ClippedCells(const ClippedCells&) = delete;
  ClippedCells& operator=(const ClippedCells&) = delete;
  double volume(const Point& node, const std::vector<Point>& neighbours);

 private:
  struct Work;
  std::unique_ptr<Work> work_;
};

/// Box-clipped Voronoi volume of every node, using every bond of the lattice
/// (whatever its stiffness) as a Voronoi-neighbour candidate.  Exact for
/// Delaunay lattices (make_random_lattice); for other bond sets it is the cell
/// of the bond graph, which is larger than the true Voronoi cell when a
/// Voronoi neighbour is not bonded.  Serial.
std::vector<double> voronoi_volumes(const Lattice& lattice);

}  // namespace lem
