// A cemented granular sample (paper sect. 2.2-2.3): a cube cut out of a
// jammed packing, overlaid on a random lattice, with matrix bridges sized to
// a requested matrix fraction and the phase of every node and bond.
#pragma once

#include "lem/aggregate.hpp"
#include "lem/lattice.hpp"
#include "lem/packing.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace lem {

/// Bond properties per phase in the paper's stress units: E^phi = k^phi / a,
/// sigma^phi = f^phi / a^2 (a = mean bond length).  Defaults of the paper:
/// E^p = 3 E^m = 3 E^pm, sigma^p = sigma^m, sigma^pp = 0 (bare contacts).
struct PhaseTable {
  std::array<double, kPhaseCount> modulus{3.0, 1.0, 0.0, 1.0, 1.0};   // p, m, v, pp, pm
  std::array<double, kPhaseCount> strength{1.0, 1.0, 0.0, 0.0, 0.6};  // p, m, v, pp, pm
};

struct CementedSampleSpec {
  PackingSpec packing;               // the periodic packing to cut from
  std::int64_t sample_particles = 516;
  RandomLatticeSpec lattice;         // box is set to the cube; size by bonds or L_n
  BridgeSpec bridges;
};

struct CementedSampleStats {
  std::int64_t particles = 0, nodes = 0, bonds = 0, bridges = 0;
  double side = 0;
  double rho_p_geometric = 0;        // clipped sphere volume / cube volume
  double rho_p = 0, rho_m = 0, rho_v = 0;  // Voronoi-weighted nodes
  std::array<std::int64_t, kPhaseCount> bonds_per_phase{};
  double bonds_per_particle = 0;     // p bonds / particles (paper: ~1550)
  double bridges_per_particle = 0;   // 2 * bridges holding matrix nodes / particles
  double interface_ratio = 0;        // S^pm / S^p: pm bonds / bonds leaving a particle
  double packing_seconds = 0, lattice_seconds = 0, voronoi_seconds = 0, phases_seconds = 0;
};

struct CementedSample {
  Lattice lattice;                   // every Delaunay bond; stiffness set by apply_phases
  std::vector<Sphere> particles;
  std::vector<Bridge> bridges;
  NodePhases node_phases;
  std::vector<Phase> bond_phase;
  std::vector<double> node_volume;   // clipped Voronoi volumes (sum = cube volume)
  CementedSampleStats stats;
};

CementedSample build_cemented_sample(const CementedSampleSpec& spec);

/// Give every bond k = E^phase * a and drop the void bonds: the lattice the
/// elastic system is built from.
Lattice mechanical_lattice(const CementedSample& sample, const PhaseTable& table);

}  // namespace lem
