#include "lem/sample/cemented_sample.hpp"

#include "lem/base/error.hpp"
#include "lem/lattice/voronoi.hpp"

#include "sample_stages.hpp"

#include <mpi.h>

#include <algorithm>
#include <numbers>
#include <sstream>
#include <vector>

namespace lem {
namespace {

// Voronoi-weighted volume fractions of particle, matrix and void nodes.
std::array<double, 3> node_fractions(const NodePhases& np, const std::vector<double>& volume,
                                     double total) {
  std::array<double, 3> f{0, 0, 0};
  for (std::size_t n = 0; n < volume.size(); ++n)
    f[np.particle[n] >= 0 ? 0 : (np.matrix[n] ? 1 : 2)] += volume[n];
  for (double& x : f) x /= total;
  return f;
}

// Stop before meshing when the particles would be resolved by too few nodes.
void check_resolution(const CementedSampleSpec& spec, const CubeSample& cube) {
  double particle_volume = 0;
  for (std::int64_t k = 0; k < cube.centres_inside; ++k)
    particle_volume += 4.0 / 3.0 * std::numbers::pi * std::pow(cube.spheres[k].radius, 3);
  particle_volume /= static_cast<double>(cube.centres_inside);
  const double cube_volume = cube.side * cube.side * cube.side;
  const double nodes = static_cast<double>(target_node_count(spec.lattice));
  const double per_particle = nodes * particle_volume / cube_volume;
  if (per_particle >= kMinNodesPerParticle) return;
  const double bonds_needed = 7.5 * kMinNodesPerParticle * cube_volume / particle_volume;
  std::ostringstream s;
  s << "lattice too coarse for the particles: about " << static_cast<long long>(per_particle)
    << " nodes per particle, at least " << kMinNodesPerParticle << " needed; ask for at least "
    << static_cast<long long>(bonds_needed) << " bonds (-lattice_bonds) for " << cube.centres_inside
    << " particles";
  throw InputError(s.str());
}

}  // namespace

namespace sample_stages {

Box cut_granular_cube(const CementedSampleSpec& spec, CementedSample& s) {
  if (spec.sample_particles < kMinSampleParticles)
    throw InputError("a cubic sample needs at least " + std::to_string(kMinSampleParticles) +
                     " particles, " + std::to_string(spec.sample_particles) + " requested");
  if (spec.sample_particles > spec.packing.count)
    throw InputError("the sample's " + std::to_string(spec.sample_particles) +
                     " particles exceed the " + std::to_string(spec.packing.count) +
                     " spheres of the packing it is cut from");
  validate(spec.packing);
  target_node_count(spec.lattice);  // a lattice size is given, before the packing runs

  auto& st = s.stats;
  const double t = MPI_Wtime();
  const Packing packing = make_packing(spec.packing);
  // Keep every sphere reaching into the cube: the sample then has the
  // packing's density (rho^p ~ 0.64) as in the paper.
  const CubeSample cube = cut_cube(packing, spec.sample_particles, CubeCut::reaching_in);
  check_resolution(spec, cube);
  s.particles = cube.spheres;
  st.particles = static_cast<std::int64_t>(s.particles.size());
  st.sample_particles = cube.centres_inside;
  st.side = cube.side;
  st.rho_p_geometric = cube.region_volume_fraction;
  st.packing_seconds = MPI_Wtime() - t;
  return Box{{0, 0, 0}, {cube.side, cube.side, cube.side}};
}

int ends_leaving_particles(Phase phase, bool first_in_particle, bool second_in_particle) {
  if (phase == Phase::pp) return 2;  // leaves both particles
  return first_in_particle != second_in_particle ? 1 : 0;
}

void set_count_statistics(CementedSampleStats& st, const std::vector<Bridge>& bridges,
                          const std::vector<int>& holding, std::int64_t leaving) {
  const double per = 1.0 / static_cast<double>(std::max<std::int64_t>(1, st.sample_particles));
  st.bonds_per_particle = static_cast<double>(st.bonds_per_phase[static_cast<int>(Phase::p)]) * per;
  st.interface_ratio = static_cast<double>(st.bonds_per_phase[static_cast<int>(Phase::pm)]) /
                       static_cast<double>(std::max<std::int64_t>(1, leaving));
  // Bridges per particle: bridge ends on the particles whose centres are in
  // the cube (the first sample_particles), per such particle.  A bridge is
  // "holding" when it contains at least one matrix node (thin bridges hidden
  // in a contact neck hold none).
  std::int64_t eligible_ends = 0, holding_ends = 0;
  for (std::size_t k = 0; k < bridges.size(); ++k) {
    const int ends = (bridges[k].i < st.sample_particles) + (bridges[k].j < st.sample_particles);
    eligible_ends += ends;
    if (holding[k]) holding_ends += ends;
  }
  st.bridges = std::count(holding.begin(), holding.end(), 1);
  st.eligible_per_particle = static_cast<double>(eligible_ends) * per;
  st.bridges_per_particle = static_cast<double>(holding_ends) * per;
}

}  // namespace sample_stages

CementedSample build_granular_sample(const CementedSampleSpec& spec) {
  CementedSample s;
  auto& st = s.stats;
  const Box box = sample_stages::cut_granular_cube(spec, s);

  double t = MPI_Wtime();
  RandomLatticeSpec ls = spec.lattice;
  ls.box = box;
  s.lattice = make_random_lattice(ls);
  st.nodes = static_cast<std::int64_t>(s.lattice.node_count());
  st.bonds = static_cast<std::int64_t>(s.lattice.bond_count());
  st.lattice_seconds = MPI_Wtime() - t;

  t = MPI_Wtime();
  s.node_volume = voronoi_volumes(s.lattice);
  st.voronoi_seconds = MPI_Wtime() - t;

  t = MPI_Wtime();
  s.node_phases = AggregateGeometry(ls.box, s.particles, {}).classify(s.lattice.nodes);
  const auto inside = std::count_if(s.node_phases.particle.begin(), s.node_phases.particle.end(),
                                    [](std::int32_t p) { return p >= 0; });
  st.nodes_per_particle = static_cast<double>(inside) /
                          static_cast<double>(std::max<std::int64_t>(1, st.sample_particles));
  st.phases_seconds = MPI_Wtime() - t;
  return s;
}

void add_matrix(CementedSample& s, const BridgeSpec& spec) {
  auto& st = s.stats;
  const double t = MPI_Wtime();
  const Box& box = s.lattice.box;
  const double volume = box.volume();
  // Particle membership does not depend on the bridges: measure the matrix
  // on the other nodes only, for each trial bridge size.
  std::vector<std::size_t> outside;
  for (std::size_t n = 0; n < s.lattice.node_count(); ++n)
    if (s.node_phases.particle[n] < 0) outside.push_back(n);
  auto measure = [&](const std::vector<Bridge>& bridges) {
    const AggregateGeometry g(box, s.particles, bridges);
    double matrix = 0;
    for (std::size_t n : outside)
      if (g.matrix_at(s.lattice.nodes[n])) matrix += s.node_volume[n];
    return matrix / volume;
  };
  const MatrixCalibration cal = calibrate_bridges(box, s.particles, spec, measure);
  s.bridges = cal.bridges;
  st.rho_m_requested = spec.matrix_fraction;
  st.eligible_pairs = static_cast<std::int64_t>(s.bridges.size());
  const AggregateGeometry geometry(box, s.particles, s.bridges);
  s.node_phases = geometry.classify(s.lattice.nodes);

  // Bond phases, and each bond's share of the volume: every node spreads
  // its Voronoi volume evenly over its bonds.
  const std::size_t bonds = s.lattice.bond_count();
  std::vector<int> degree(s.lattice.node_count(), 0);
  for (const auto& b : s.lattice.bonds) ++degree[b.i], ++degree[b.j];
  s.bond_phase.resize(bonds);
  st.bonds_per_phase.fill(0);
  st.bond_volume_fraction.fill(0);
  std::int64_t leaving = 0;  // bond ends leaving a particle surface
  for (std::size_t b = 0; b < bonds; ++b) {
    const auto& bond = s.lattice.bonds[b];
    const Phase phase = bond_phase(s.node_phases, bond.i, bond.j, spec.void_bonds);
    const int k = static_cast<int>(phase);
    s.bond_phase[b] = phase;
    ++st.bonds_per_phase[k];
    st.bond_volume_fraction[k] +=
        (s.node_volume[bond.i] / degree[bond.i] + s.node_volume[bond.j] / degree[bond.j]) / volume;
    leaving += sample_stages::ends_leaving_particles(phase, s.node_phases.particle[bond.i] >= 0,
                                                     s.node_phases.particle[bond.j] >= 0);
  }
  const auto fractions = node_fractions(s.node_phases, s.node_volume, volume);
  st.rho_p = fractions[0];
  st.rho_m = fractions[1];
  st.rho_v = fractions[2];
  std::vector<int> holding(s.bridges.size(), 0);
  for (std::size_t n = 0; n < s.lattice.node_count(); ++n)
    if (s.node_phases.matrix[n])
      for (std::int32_t k : geometry.bridges_at(s.lattice.nodes[n])) holding[k] = 1;
  sample_stages::set_count_statistics(st, s.bridges, holding, leaving);
  st.phases_seconds += MPI_Wtime() - t;
}

CementedSample build_cemented_sample(const CementedSampleSpec& spec) {
  CementedSample s = build_granular_sample(spec);
  add_matrix(s, spec.bridges);
  return s;
}

Lattice mechanical_lattice(const CementedSample& sample, const PhaseTable& table) {
  const LatticeStats ls = lattice_stats(sample.lattice);
  Lattice l;
  l.box = sample.lattice.box;
  l.nodes = sample.lattice.nodes;
  l.node_volume = sample.node_volume;
  l.node_particle = sample.node_phases.particle;
  // One a for k, f and the load increment: the mean length of every bond of
  // the file, void ones included (they are elements of the lattice).
  const double a = ls.mean_length;
  l.element_length = a;
  for (std::size_t b = 0; b < sample.lattice.bond_count(); ++b) {
    const int phase = static_cast<int>(sample.bond_phase[b]);
    const double k = table.modulus[phase] * a;
    if (sample.bond_phase[b] == Phase::v || k <= 0) continue;
    l.bond_id.push_back(static_cast<std::int64_t>(b));  // the row of /bonds
    l.bonds.push_back(sample.lattice.bonds[b]);
    l.stiffness.push_back(k);
    l.strength.push_back(table.strength[phase] * a * a);
    l.tag.push_back(static_cast<std::uint8_t>(phase));
  }
  return l;
}

}  // namespace lem
