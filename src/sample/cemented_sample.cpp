#include "lem/cemented_sample.hpp"

#include "lem/error.hpp"
#include "lem/voronoi.hpp"

#include <mpi.h>

#include <algorithm>
#include <set>

namespace lem {
namespace {

// Voronoi-weighted volume fractions of particle, matrix and void nodes.
std::array<double, 3> phase_fractions(const NodePhases& np, const std::vector<double>& volume,
                                      double total) {
  std::array<double, 3> f{0, 0, 0};
  for (std::size_t n = 0; n < volume.size(); ++n)
    f[np.particle[n] >= 0 ? 0 : (np.matrix[n] ? 1 : 2)] += volume[n];
  for (double& x : f) x /= total;
  return f;
}

}  // namespace

CementedSample build_cemented_sample(const CementedSampleSpec& spec) {
  CementedSample s;
  auto& st = s.stats;
  double t = MPI_Wtime();
  const Packing packing = make_packing(spec.packing);
  // Keep every sphere reaching into the cube: the sample then has the
  // packing's density (rho^p ~ 0.64) as in the paper.
  const CubeSample cube = cut_cube(packing, spec.sample_particles, CubeCut::reaching_in);
  s.particles = cube.spheres;
  st.particles = static_cast<std::int64_t>(s.particles.size());
  st.side = cube.side;
  st.rho_p_geometric = cube.region_volume_fraction;
  st.packing_seconds = MPI_Wtime() - t;

  t = MPI_Wtime();
  RandomLatticeSpec ls = spec.lattice;
  ls.box.lo = {0, 0, 0};
  ls.box.hi = {cube.side, cube.side, cube.side};
  s.lattice = make_random_lattice(ls);
  st.nodes = static_cast<std::int64_t>(s.lattice.node_count());
  st.bonds = static_cast<std::int64_t>(s.lattice.bond_count());
  st.lattice_seconds = MPI_Wtime() - t;

  t = MPI_Wtime();
  s.node_volume = voronoi_volumes(s.lattice);
  st.voronoi_seconds = MPI_Wtime() - t;

  // Particle membership does not depend on the bridges: classify once, then
  // measure the matrix on the remaining nodes for each trial bridge size.
  t = MPI_Wtime();
  const double volume = ls.box.volume();
  const AggregateGeometry bare(ls.box, s.particles, {});
  const NodePhases particles_only = bare.classify(s.lattice.nodes);
  auto measure = [&](const std::vector<Bridge>& bridges) {
    const AggregateGeometry g(ls.box, s.particles, bridges);
    double matrix = 0;
    for (std::size_t n = 0; n < s.lattice.node_count(); ++n)
      if (particles_only.particle[n] < 0 && g.matrix_at(s.lattice.nodes[n]))
        matrix += s.node_volume[n];
    return matrix / volume;
  };
  const MatrixCalibration cal = calibrate_bridges(ls.box, s.particles, spec.bridges, measure);
  s.bridges = cal.bridges;
  const AggregateGeometry geometry(ls.box, s.particles, s.bridges);
  s.node_phases = geometry.classify(s.lattice.nodes);

  s.bond_phase.resize(s.lattice.bond_count());
  std::int64_t leaving = 0;  // bonds with exactly one end in a particle
  for (std::size_t b = 0; b < s.lattice.bond_count(); ++b) {
    const auto& bond = s.lattice.bonds[b];
    const Phase phase = bond_phase(s.node_phases, bond.i, bond.j);
    s.bond_phase[b] = phase;
    ++st.bonds_per_phase[static_cast<int>(phase)];
    const bool pi = s.node_phases.particle[bond.i] >= 0, pj = s.node_phases.particle[bond.j] >= 0;
    if (pi != pj || (pi && pj && phase == Phase::pp)) ++leaving;
  }
  const auto fractions = phase_fractions(s.node_phases, s.node_volume, volume);
  st.rho_p = fractions[0];
  st.rho_m = fractions[1];
  st.rho_v = fractions[2];
  st.bonds_per_particle =
      static_cast<double>(st.bonds_per_phase[static_cast<int>(Phase::p)]) /
      static_cast<double>(std::max<std::int64_t>(1, st.particles));
  // pp bonds leave two particles (count both surfaces).
  const auto pp = st.bonds_per_phase[static_cast<int>(Phase::pp)];
  st.interface_ratio = static_cast<double>(st.bonds_per_phase[static_cast<int>(Phase::pm)]) /
                       static_cast<double>(std::max<std::int64_t>(1, leaving + pp));
  // Bridges that actually hold matrix nodes.
  std::set<std::int32_t> holding;
  for (std::size_t n = 0; n < s.lattice.node_count(); ++n)
    if (s.node_phases.matrix[n]) {
      const std::int32_t k = geometry.bridge_at(s.lattice.nodes[n]);
      if (k >= 0) holding.insert(k);
    }
  st.bridges = static_cast<std::int64_t>(holding.size());
  st.bridges_per_particle = 2.0 * static_cast<double>(holding.size()) /
                            static_cast<double>(std::max<std::int64_t>(1, st.particles));
  st.phases_seconds = MPI_Wtime() - t;
  return s;
}

Lattice mechanical_lattice(const CementedSample& sample, const PhaseTable& table) {
  const LatticeStats ls = lattice_stats(sample.lattice);
  Lattice l;
  l.box = sample.lattice.box;
  l.nodes = sample.lattice.nodes;
  for (std::size_t b = 0; b < sample.lattice.bond_count(); ++b) {
    const int phase = static_cast<int>(sample.bond_phase[b]);
    const double k = table.modulus[phase] * ls.mean_length;
    if (sample.bond_phase[b] == Phase::v || k <= 0) continue;
    l.bonds.push_back(sample.lattice.bonds[b]);
    l.stiffness.push_back(k);
  }
  return l;
}

}  // namespace lem
