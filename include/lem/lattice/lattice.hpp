// Lattice stage: node coordinates and the bond list, built on one rank.
//
// A Lattice is plain data.  Bonds are unique pairs (i < j) sorted
// lexicographically; a bond's global id is its index in that list, or its
// entry of `bond_id` when the lattice was cut from a larger list (a sample
// file's mechanical bonds), and never depends on how the lattice is later
// partitioned.
#pragma once

#include "lem/base/geometry.hpp"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace lem {

struct Bond {
  std::int32_t i, j;  // node indices, i < j
  friend bool operator<(const Bond& a, const Bond& b) {
    return a.i < b.i || (a.i == b.i && a.j < b.j);
  }
  friend bool operator==(const Bond& a, const Bond& b) { return a.i == b.i && a.j == b.j; }
};

struct Lattice {
  Box box;
  std::vector<Point> nodes;
  std::vector<Bond> bonds;        // sorted, unique, i < j
  std::vector<double> stiffness;  // Hooke constant k of each bond (absolute units)
  /// Optional per bond (empty, or one per bond): breaking force (tension),
  /// and a tag carried along for the results (the phase of a cemented sample).
  std::vector<double> strength;
  std::vector<std::uint8_t> tag;
  /// Optional per node (empty, or one per node): the box-clipped Voronoi
  /// volume |V^i| that turns bond forces into node stresses (paper eq. 1).
  std::vector<double> node_volume;
  /// Optional per node (empty, or one per node): the particle it lies in,
  /// -1 outside every particle (cemented samples); the solver's
  /// per-particle coarse space (-solver_particle_deflation) is built on it.
  std::vector<std::int32_t> node_particle;
  /// Optional per bond (empty, or one per bond): the bond's id in every
  /// output, when the lattice was cut from a larger list of bonds (the
  /// mechanical bonds of a sample file: the bond's row of its /bonds).
  /// Empty: the bond's index.  Increasing, so the order of ids is the
  /// order of the list.
  std::vector<std::int64_t> bond_id;
  /// The paper's a, "the average length of the elements" (sect. 2.2), when
  /// the lattice was cut from a larger list of elements (a sample file's
  /// void bonds are elements too).  0: the mean length of its own bonds.
  double element_length = 0;

  std::size_t node_count() const { return nodes.size(); }
  std::size_t bond_count() const { return bonds.size(); }
  double bond_length(std::size_t b) const;
};

struct LatticeStats {
  std::int64_t nodes = 0, bonds = 0;
  double mean_length = 0, min_length = 0, max_length = 0, std_length = 0;
  double mean_coordination = 0;  // 2 * bonds / nodes
  double mesh_density = 0;       // L_n = M^(-1/3), M = number of bonds (paper sect. 3)
};
LatticeStats lattice_stats(const Lattice& lattice);

/// Size of a random lattice: exactly one of the three is used, in this order
/// of precedence: nodes, bonds, mesh density L_n = M^(-1/3).
/// How a random lattice is made: serial (make_random_lattice, on one rank)
/// or cells (make_cell_lattice, by every rank for its cells of a grid).
enum class LatticeGenerator { serial, cells };

struct RandomLatticeSpec {
  Box box;
  std::int64_t nodes = 0;
  std::int64_t bonds = 0;
  double mesh_density = 0;
  /// Minimum node separation as a fraction of the mean spacing (V/N)^(1/3).
  double min_separation = 0.5;
  std::uint64_t seed = 1;
  double stiffness = 1.0;  // k of every bond
};

/// Nodes needed for a target bond count (random Delaunay lattices with a
/// minimum separation have about 7.7 bonds per node in the bulk, fewer at
/// the faces).
std::int64_t nodes_for_bond_count(std::int64_t bonds);
/// The node count make_random_lattice aims at for `spec`.
std::int64_t target_node_count(const RandomLatticeSpec& spec);

/// Nodes a spec asks for: its node count, else from its bond count, else
/// from its mesh density L_n = M^(-1/3).  Throws InputError if none is set.
std::int64_t target_node_count(const RandomLatticeSpec& spec);

/// Random points with a minimum separation, including points on the six faces,
/// the twelve edges and the eight corners of the box (so that the loaded faces
/// are flat), joined by the edges of their Delaunay tetrahedralisation (CGAL).
Lattice make_random_lattice(const RandomLatticeSpec& spec);

/// Face-centred-cubic nearest-neighbour spring lattice of `cells` cubic unit
/// cells per axis, bond length `a`, Hooke constant `k`.  Bonds lying in a face
/// of the block get k/2 and bonds along an edge k/4: the block is then exactly
/// a share of the infinite lattice, and a homogeneous strain is an exact
/// equilibrium even with free faces (see docs/model/theory.md).
Lattice make_fcc_lattice(std::array<int, 3> cells, double a, double k);
/// The same block measured in half cells (spacings of c/2 = a/sqrt 2) per
/// axis: make_fcc_lattice(cells) is make_fcc_block(2 cells).  With an odd
/// count the two faces normal to that axis carry the two different site
/// patterns of an FCC plane, so their node centroids differ (a test of
/// measures that average over faces); the block is still an exact share of
/// the infinite lattice.
Lattice make_fcc_block(std::array<int, 3> half_cells, double a, double k);

/// Bit flags of the box faces a node lies on (within tol * shortest side).
enum Face : std::uint8_t { kXmin = 1, kXmax = 2, kYmin = 4, kYmax = 8, kZmin = 16, kZmax = 32 };
std::vector<std::uint8_t> face_flags(const Lattice& lattice, double tol = 1e-9);
/// The Face bits of one point.
std::uint8_t faces_of(const Point& p, const Box& box, double tol = 1e-9);
/// Why the lattice cannot be pulled between its z faces when `bottom` or
/// `top` nodes lie on them ("" if both are some): a box that does not fit
/// its nodes (an edited box, rounded coordinates) leaves a face empty,
/// which would otherwise read as a disconnected sample.
std::string empty_face_problem(std::int64_t bottom, std::int64_t top);
/// What halve_face_bonds keeps of a bond whose ends touch these faces: 1/2
/// per face the two share.
double face_share(std::uint8_t faces_i, std::uint8_t faces_j);

/// Scale the stiffness and the breaking force of every bond lying in a box
/// face by 1/2 per face it lies in (1/4 on an edge).  Such a bond has only
/// half its surroundings inside the box, as the box-clipped Voronoi cells of
/// its nodes do; at full stiffness the faces form a stiff skin.  The FCC
/// block is built this way; random and sample lattices only on request
/// (-lattice_face_bonds halved).
void halve_face_bonds(Lattice& lattice);

}  // namespace lem

namespace lem {

/// Affine (Voigt) estimate of the elastic moduli: every bond follows the
/// macroscopic strain, C_ijkl = (1/V) sum_b k L^2 n_i n_j n_k n_l.  Exact for
/// lattices where each node is a centre of symmetry (FCC), an upper bound
/// otherwise.  Voigt order xx, yy, zz, yz, xz, xy.
struct AffineModuli {
  double C[6][6] = {};
  double young_z = 0;    // 1 / S_zzzz, S = C^-1
  double poisson_z = 0;  // -(S_xxzz + S_yyzz) / (2 S_zzzz)
};
AffineModuli affine_moduli(const Lattice& lattice);
/// Its parts, for a lattice held in pieces: one bond's term of C (box volume
/// `volume`), then the moduli from the summed C.
void add_affine_bond(AffineModuli& m, const Point& p, const Point& q, double k, double volume);
void finish_affine_moduli(AffineModuli& m);

}  // namespace lem
