// A cemented granular sample (paper sect. 2.2-2.3): a cube cut out of a
// jammed packing, overlaid on a random lattice, with matrix bridges sized to
// a requested matrix fraction and the phase of every node and bond.
//
// Built in two stages so that studies over the matrix fraction share the
// packing, the lattice and the Voronoi volumes:
//   build_granular_sample(spec)   packing -> cube -> lattice -> volumes -> particles
//   add_matrix(sample, bridges)   calibrated bridges -> node/bond phases -> stats
#pragma once

#include "lem/sample/aggregate.hpp"
#include "lem/lattice/lattice.hpp"
#include "lem/packing/packing.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace lem {

/// Bond properties per phase in the paper's stress units: E^phi = k^phi / a,
/// sigma^phi = f^phi / a^2 (a = mean bond length); defaults in phase.hpp.
/// E^pp = 0 removes the particle-particle bonds from the system.
struct PhaseTable {
  std::array<double, kPhaseCount> modulus = kDefaultPhaseModulus;
  std::array<double, kPhaseCount> strength = kDefaultPhaseStrength;
};

struct CementedSampleSpec {
  PackingSpec packing;                  // the periodic packing to cut from
  std::int64_t sample_particles = 516;  // sphere centres in the cube (>= 8)
  RandomLatticeSpec lattice;            // box is set to the cube; size by bonds, nodes or L_n
  /// serial: built on one rank (build_cemented_sample); cells: by every rank
  /// for its block (build_cemented_sample_block, lem/sample/parallel_sample.hpp).
  LatticeGenerator generator = LatticeGenerator::serial;
  BridgeSpec bridges;
};

/// Smallest sample and resolution accepted (a cube of 2x2x2 particles; a
/// particle resolved by fewer nodes is not a sphere any more).
inline constexpr std::int64_t kMinSampleParticles = 8;
inline constexpr double kMinNodesPerParticle = 50;

struct CementedSampleStats {
  std::int64_t particles = 0;         // spheres kept: centres inside + reaching in
  std::int64_t sample_particles = 0;  // centres inside the cube ("per particle" counts)
  std::int64_t nodes = 0, bonds = 0;
  double side = 0;
  double nodes_per_particle = 0;  // lattice nodes inside particles / sample particles
  double rho_p_geometric = 0;     // clipped sphere volume / cube volume
  double rho_m_requested = 0;
  double rho_p = 0, rho_m = 0, rho_v = 0;  // Voronoi-weighted nodes
  std::array<std::int64_t, kPhaseCount> bonds_per_phase{};
  /// Volume share of each bond phase: every node spreads its Voronoi volume
  /// evenly over its bonds (sums to 1; used for the appendix-D estimates).
  std::array<double, kPhaseCount> bond_volume_fraction{};
  double bonds_per_particle = 0;    // p bonds / sample particles (paper: ~1550)
  std::int64_t eligible_pairs = 0;  // pairs given a share of the matrix
  std::int64_t bridges = 0;         // bridges holding at least one matrix node
  /// Per particle with its centre in the cube: eligible pairs, and bridges
  /// holding matrix nodes (paper: ~9, ~6 at rho^m = 0.06).
  double eligible_per_particle = 0, bridges_per_particle = 0;
  double interface_ratio = 0;  // S^pm / S^p: pm bonds / bonds leaving a particle
  double packing_seconds = 0, lattice_seconds = 0, voronoi_seconds = 0, phases_seconds = 0;
};

struct CementedSample {
  Lattice lattice;  // every Delaunay bond; stiffness set by mechanical_lattice
  std::vector<Sphere> particles;
  std::vector<Bridge> bridges;
  NodePhases node_phases;
  std::vector<Phase> bond_phase;
  std::vector<double> node_volume;  // clipped Voronoi volumes (sum = cube volume)
  CementedSampleStats stats;
};

/// Stage 1: packing, cube, lattice, Voronoi volumes and particle membership;
/// no matrix yet (non-particle nodes are void).  Throws InputError for a
/// sample too small to cut or a resolution below kMinNodesPerParticle.
CementedSample build_granular_sample(const CementedSampleSpec& spec);

/// Stage 2: bridges calibrated to bridges.matrix_fraction, node and bond
/// phases and the statistics.  May be called again with another fraction.
/// Throws InputError if the fraction exceeds what the pore space can hold.
void add_matrix(CementedSample& sample, const BridgeSpec& bridges);

/// Both stages.
CementedSample build_cemented_sample(const CementedSampleSpec& spec);

/// Give every bond k = E^phase * a and breaking force f = sigma^phase * a^2
/// (a = mean length of all the sample's bonds), tag it with its phase, and
/// drop the void bonds (and bonds of zero modulus): the lattice the elastic
/// system is built from.
Lattice mechanical_lattice(const CementedSample& sample, const PhaseTable& table);

}  // namespace lem
