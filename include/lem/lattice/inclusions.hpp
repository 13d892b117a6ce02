// Simple two-phase samples for the convergence study of the paper (sect. 3,
// fig. 6): equal spheres placed at random without overlap in the box, either
// stiffer than the matrix or empty (pores).
#pragma once

#include "lem/lattice/lattice.hpp"

#include <cstdint>
#include <vector>

namespace lem {

struct InclusionSpec {
  double volume_fraction = 0.2;
  double radius = 0.1;  // in units of the smallest box side
  std::uint64_t seed = 7;
};

/// Spheres in a periodic arrangement over the box: centres uniform in the box,
/// no two overlapping under the minimum-image convention, so the volume
/// fraction inside the box is exactly count * (4/3) pi r^3 / V.
struct Inclusions {
  Box box;
  double radius = 0;
  std::vector<Point> centres;
  bool contains(const Point& p) const;
  double volume_fraction() const;
};

/// Random sequential addition; throws InputError if the fraction cannot be
/// reached (too high for the radius, or spheres larger than the box allows).
Inclusions place_inclusions(const Box& box, const InclusionSpec& spec);

/// Bonds with both ends inside an inclusion get k * ratio (stiff inclusions;
/// bonds across the interface keep the matrix stiffness, as E^pm = E^m in the
/// paper).
void stiffen_inclusions(Lattice& lattice, const Inclusions& inclusions, double ratio);

/// Pores: void bonds are removed from the lattice (they carry nothing); bond
/// ids are renumbered.  A bond is void if any end is inside a pore (the
/// "any_end" rule, default) or, with `both_ends`, only if both are: the two
/// rules bracket the true pore volume at a finite resolution.  The paper
/// states only that void bonds carry nothing (f^v = 0), not which rule.
void carve_pores(Lattice& lattice, const Inclusions& pores, bool both_ends = false);

/// Fraction of nodes inside the inclusions (a lattice estimate of the volume
/// fraction).
double node_fraction_inside(const Lattice& lattice, const Inclusions& inclusions);

}  // namespace lem
