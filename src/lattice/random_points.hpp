// What the two random lattice generators share (random_lattice.cpp, serial;
// cell_lattice.cpp, parallel): the size checks and counts of the hard-core
// point process, and the Delaunay triangulation of its points.
#pragma once

#include "lem/lattice/lattice.hpp"

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <cstdint>

namespace lem {

using DelaunayKernel = CGAL::Exact_predicates_inexact_constructions_kernel;
/// Vertex info: an index of the caller's.
using Delaunay = CGAL::Delaunay_triangulation_3<
    DelaunayKernel, CGAL::Triangulation_data_structure_3<
                        CGAL::Triangulation_vertex_base_with_info_3<std::int64_t, DelaunayKernel>,
                        CGAL::Delaunay_triangulation_cell_base_3<DelaunayKernel>>>;

/// How many points the process places: the 8 corners, on each edge parallel
/// to axis a, on each face normal to axis a, and inside, at the density of
/// the bulk for `target` nodes of mean spacing `spacing`.  Throws InputError
/// when the box is too small for two spacings per side or the faces take
/// every node.
struct PointCounts {
  double spacing = 0;
  std::int64_t edge[3] = {0, 0, 0}, face[3] = {0, 0, 0}, inside = 0;
};
PointCounts point_counts(const Box& box, std::int64_t target);

}  // namespace lem
