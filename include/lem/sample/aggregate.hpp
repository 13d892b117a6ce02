// Cemented aggregate geometry (paper sect. 2.2): particles (spheres) glued by
// a matrix of truncated conical bridges between near neighbours, and the
// phase of every lattice node and bond.
//
// Bridge of an eligible pair (i, j) (gap <= max_gap): the frustum whose axis
// joins the two centres, with radius lambda_ij * r_i at centre i and
// lambda_ij * r_j at centre j; the matrix is the part of the frustum outside
// every particle.  Its cross-section is proportional to the particles' sizes,
// and each pair receives a share of the total matrix volume proportional to
// its mean square diameter (d_i^2 + d_j^2)/2, as in the paper; lambda_ij is
// solved so that the bridge's own volume (outside its two particles) equals
// that share.  Bridges overlap and percolate as the matrix fraction grows;
// a global factor on the shares is then calibrated so that the matrix volume
// measured on the sample equals the requested fraction.
#pragma once

#include "lem/base/cell_grid.hpp"
#include "lem/lattice/lattice.hpp"
#include "lem/packing/packing.hpp"
#include "lem/base/phase.hpp"

#include <cstdint>
#include <functional>
#include <vector>

namespace lem {

struct Bridge {
  std::int32_t i = 0, j = 0;  // particle indices, i < j
  double lambda = 0;          // frustum radius / particle radius at each centre
};

/// Which bonds the pores make void.  The paper states only that void bonds
/// carry nothing (f^v = 0), not how a bond with one end in a pore is
/// classified.
///   any_end    a bond with at least one end in a pore is void (the default;
///              the pores grow by half a bond, the solid shrinks);
///   both_ends  only a bond with both ends in pores is void; a bond from a
///              particle or matrix node into a pore takes that node's phase
///              (p or m: the solid grows by half a bond).
enum class VoidRule { any_end, both_ends };

/// The option words of a VoidRule ("any_end", "both_ends").
const char* void_rule_name(VoidRule rule);

struct BridgeSpec {
  double matrix_fraction = 0.13;  // requested rho^m
  /// Eligible pairs: surface gap <= max_gap (a length, like the radii).  The
  /// paper states gap <= d_min, which here makes ~29 pairs per particle
  /// eligible; its ~9 matrix bridges per particle match a gap of 0.15 d_min
  /// (docs/model/cemented-samples.md), the default.
  double max_gap = 0.15;
  double max_lambda = 3.0;  // widest bridge allowed (pore-space limit)
  /// Not a property of the bridges but of the phases the matrix stage
  /// assigns: the bonds made void by the pores.
  VoidRule void_bonds = VoidRule::any_end;
};

/// Pairs of particles whose surfaces are at most `max_gap` apart (cell list).
std::vector<Bridge> eligible_pairs(const std::vector<Sphere>& particles, double max_gap);

/// Volume of bridge (i, j) of size lambda outside particles i and j
/// (exact up to the 1D quadrature along the axis).
double bridge_volume(const Sphere& a, const Sphere& b, double lambda);

/// Node classification: particle index, or -1 with a matrix flag.
struct NodePhases {
  std::vector<std::int32_t> particle;  // -1 if not inside a particle
  std::vector<char> matrix;            // inside a bridge (and no particle)
};

/// Spatial index over particles and bridges answering "what is at x".
class AggregateGeometry {
 public:
  AggregateGeometry(const Box& box, std::vector<Sphere> particles, std::vector<Bridge> bridges);
  std::int32_t particle_at(const Point& x) const;              // -1 if none
  bool matrix_at(const Point& x) const;                        // inside some bridge
  std::vector<std::int32_t> bridges_at(const Point& x) const;  // every bridge containing x
  NodePhases classify(const std::vector<Point>& nodes) const;
  const std::vector<Sphere>& particles() const { return particles_; }
  const std::vector<Bridge>& bridges() const { return bridges_; }

 private:
  const std::vector<std::int32_t>& cell_items(const Point& x, bool bridges) const;
  bool in_bridge(std::int32_t k, const Point& x) const;
  std::vector<Sphere> particles_;
  std::vector<Bridge> bridges_;
  CellGrid grid_;  // cells of at least a particle diameter
  std::vector<std::vector<std::int32_t>> particle_cells_, bridge_cells_;
};

/// Phase of a bond from the phases of its end nodes (paper sect. 2.2), the
/// pores making bonds void by `rule`.
Phase bond_phase(const NodePhases& nodes, std::int32_t a, std::int32_t b,
                 VoidRule rule = VoidRule::any_end);
/// The same from the classification of its two ends (particle index or -1,
/// and the matrix flag of each).
Phase bond_phase(std::int32_t particle_a, bool matrix_a, std::int32_t particle_b, bool matrix_b,
                 VoidRule rule);

/// Result of sizing the bridges for a requested matrix fraction.
struct MatrixCalibration {
  std::vector<Bridge> bridges;  // with their lambda
  double share_factor = 1;      // shares actually given / requested total
  double matrix_fraction = 0;   // measured (weighted nodes)
  int iterations = 0;
};

/// Size the bridges so that the matrix fraction measured with `measure`
/// (a function of the bridges returning rho^m, e.g. Voronoi-weighted nodes)
/// equals spec.matrix_fraction to `tolerance`.  Throws InputError when the
/// fraction exceeds what the pore space can hold with lambda <= max_lambda.
MatrixCalibration calibrate_bridges(
    const Box& box, const std::vector<Sphere>& particles, const BridgeSpec& spec,
    const std::function<double(const std::vector<Bridge>&)>& measure, double tolerance = 1e-3);

}  // namespace lem
