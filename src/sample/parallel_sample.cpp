#include "lem/sample/parallel_sample.hpp"

#include "lem/lattice/cell_lattice.hpp"
#include "lem/base/error.hpp"
#include "lem/base/exact_sum.hpp"
#include "lem/base/collective.hpp"
#include "lem/base/redistribute.hpp"
#include "lem/lattice/voronoi.hpp"

#include "sample_stages.hpp"

#include <algorithm>
#include <array>
#include <stdexcept>

namespace lem {
namespace {

/// One end of a bond as seen from the other: sent to the rank of `node`.
struct Neighbour {
  std::int64_t node = 0, other = 0;
  Point at{};
};

/// Each node of this rank's block with its Delaunay neighbours (sorted by
/// id, so that nothing depends on which rank held which bond), in
/// compressed rows: the neighbours of node row n are first[n] .. first[n+1]-1.
struct NeighbourRows {
  std::vector<std::size_t> first;
  std::vector<Neighbour> items;
};

NeighbourRows gather_neighbours(MPI_Comm comm, const SampleBlock& b) {
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  const RowBlocks node_blocks(b.nodes, ranks);
  std::vector<Neighbour> received;
  {
    std::vector<Neighbour> out;
    std::vector<int> to;
    out.reserve(2 * b.ends.size());
    to.reserve(2 * b.ends.size());
    for (std::size_t k = 0; k < b.ends.size(); ++k)
      for (int side = 0; side < 2; ++side) {
        out.push_back({b.ends[k][side], b.ends[k][1 - side], b.end_coords[k][1 - side]});
        to.push_back(node_blocks.rank_of(b.ends[k][side]));
      }
    received = route(comm, out, to);
  }
  // By node row (a counting sort), then each row's few by id.
  NeighbourRows rows;
  rows.first.assign(b.coords.size() + 1, 0);
  for (const Neighbour& e : received) ++rows.first[e.node - b.node_begin + 1];
  for (std::size_t n = 0; n < b.coords.size(); ++n) rows.first[n + 1] += rows.first[n];
  rows.items.resize(received.size());
  std::vector<std::size_t> next(rows.first.begin(), rows.first.end() - 1);
  for (const Neighbour& e : received) rows.items[next[e.node - b.node_begin]++] = e;
  std::vector<Neighbour>().swap(received);
  for (std::size_t n = 0; n < b.coords.size(); ++n)
    std::sort(rows.items.begin() + rows.first[n], rows.items.begin() + rows.first[n + 1],
              [](const Neighbour& x, const Neighbour& y) { return x.other < y.other; });
  return rows;
}

// The lattice of the block (the cells generator in the sample's box).
void make_block_lattice(MPI_Comm comm, const CementedSampleSpec& spec, const Box& box,
                        SampleBlock& b) {
  CementedSampleStats& st = b.description.sample.stats;
  const double t = MPI_Wtime();
  RandomLatticeSpec ls = spec.lattice;
  ls.box = box;
  LatticeBlock lattice = make_cell_lattice(comm, ls);
  b.nodes = st.nodes = lattice.nodes;
  b.bonds = st.bonds = lattice.bonds;
  b.node_begin = lattice.node_begin;
  b.bond_begin = lattice.bond_begin;
  b.coords = std::move(lattice.coords);
  b.ends = std::move(lattice.ends);
  b.end_coords = std::move(lattice.end_coords);
  st.lattice_seconds = MPI_Wtime() - t;
}

// Voronoi volumes: the cell of a node is the box cut by the bisectors of
// its Delaunay neighbours.
void set_voronoi_volumes(const NeighbourRows& neighbours, const Box& box, SampleBlock& b) {
  b.volume.resize(b.coords.size());
  ClippedCells cells(box);
  std::vector<Point> around;
  for (std::size_t n = 0; n < b.coords.size(); ++n) {
    around.clear();
    for (std::size_t e = neighbours.first[n]; e < neighbours.first[n + 1]; ++e)
      around.push_back(neighbours.items[e].at);
    b.volume[n] = cells.volume(b.coords[n], around);
  }
}

// The bridges sized so that the matrix measured on the nodes outside the
// particles (`bare`) is the requested fraction; the sums are exact, so that
// every rank takes the same bisection steps.
MatrixCalibration calibrate_block_bridges(MPI_Comm comm, const SampleBlock& b, const Box& box,
                                          const NodePhases& bare) {
  const CementedSample& s = b.description.sample;
  std::vector<std::size_t> outside;
  for (std::size_t n = 0; n < b.coords.size(); ++n)
    if (bare.particle[n] < 0) outside.push_back(n);
  const auto measure = [&](const std::vector<Bridge>& bridges) {
    const AggregateGeometry g(box, s.particles, bridges);
    ExactSum matrix;
    for (const std::size_t n : outside)
      if (g.matrix_at(b.coords[n])) matrix.add(b.volume[n]);
    return matrix.all_ranks(comm).value() / box.volume();
  };
  return calibrate_bridges(box, s.particles, b.description.spec.bridges, measure);
}

// The phase of node `id` at `x`: this rank's own classification when the
// node is in its block, else the same function of the same point as on
// the node's rank (the nodes of other blocks that bonds reach are few).
class EndPhases {
 public:
  struct EndPhase {
    std::int32_t particle;
    bool matrix;
  };
  EndPhases(const AggregateGeometry& geometry, const NodePhases& own, std::int64_t node_begin)
      : geometry_(geometry), own_(own), node_begin_(node_begin) {}
  EndPhase operator()(std::int64_t id, const Point& x) const {
    const std::int64_t row = id - node_begin_;
    if (row >= 0 && row < static_cast<std::int64_t>(own_.particle.size()))
      return EndPhase{own_.particle[row], own_.matrix[row] != 0};
    const std::int32_t p = geometry_.particle_at(x);
    return EndPhase{p, p < 0 && geometry_.matrix_at(x)};
  }

 private:
  const AggregateGeometry& geometry_;
  const NodePhases& own_;
  std::int64_t node_begin_;
};

// The bonds of each phase, then the bond ends leaving particles, then the
// nodes inside particles (of `bare`), summed over the ranks.
using PhaseCounts = std::array<std::int64_t, kPhaseCount + 2>;

// The phase of every bond of the block, and their counts.
PhaseCounts set_bond_phases(MPI_Comm comm, const EndPhases& end_phase, const NodePhases& bare,
                            VoidRule rule, SampleBlock& b) {
  PhaseCounts counts{};
  b.bond_phase.resize(b.ends.size());
  for (std::size_t k = 0; k < b.ends.size(); ++k) {
    const auto i = end_phase(b.ends[k][0], b.end_coords[k][0]);
    const auto j = end_phase(b.ends[k][1], b.end_coords[k][1]);
    const Phase phase = bond_phase(i.particle, i.matrix, j.particle, j.matrix, rule);
    b.bond_phase[k] = phase;
    ++counts[static_cast<int>(phase)];
    counts[kPhaseCount] +=
        sample_stages::ends_leaving_particles(phase, i.particle >= 0, j.particle >= 0);
  }
  for (std::size_t n = 0; n < b.coords.size(); ++n)
    counts[kPhaseCount + 1] += bare.particle[n] >= 0;
  MPI_Allreduce(MPI_IN_PLACE, counts.data(), static_cast<int>(counts.size()), MPI_INT64_T, MPI_SUM,
                comm);
  return counts;
}

// Volume fractions: of the node phases, and of the bond phases with every
// node spreading its volume evenly over its bonds. Returns, for each
// bridge, whether any rank's matrix node lies in it.
std::vector<int> set_volume_fractions(MPI_Comm comm, const SampleBlock& b,
                                      const NeighbourRows& neighbours, const NodePhases& own,
                                      const AggregateGeometry& geometry, const EndPhases& end_phase,
                                      VoidRule rule, CementedSampleStats& st) {
  const double volume = b.description.sample.lattice.box.volume();
  std::array<ExactSum, 3> node_sums;
  std::array<ExactSum, kPhaseCount> bond_sums;
  std::vector<int> holding(b.description.sample.bridges.size(), 0);
  for (std::size_t n = 0; n < b.coords.size(); ++n) {
    const bool in_matrix = own.matrix[n] != 0;
    node_sums[own.particle[n] >= 0 ? 0 : (in_matrix ? 1 : 2)].add(b.volume[n]);
    if (in_matrix)
      for (std::int32_t k : geometry.bridges_at(b.coords[n])) holding[k] = 1;
    const std::size_t degree = neighbours.first[n + 1] - neighbours.first[n];
    for (std::size_t e = neighbours.first[n]; e < neighbours.first[n + 1]; ++e) {
      const auto q = end_phase(neighbours.items[e].other, neighbours.items[e].at);
      const Phase phase = bond_phase(own.particle[n], in_matrix, q.particle, q.matrix, rule);
      bond_sums[static_cast<int>(phase)].add(b.volume[n] / static_cast<double>(degree));
    }
  }
  st.rho_p = node_sums[0].all_ranks(comm).value() / volume;
  st.rho_m = node_sums[1].all_ranks(comm).value() / volume;
  st.rho_v = node_sums[2].all_ranks(comm).value() / volume;
  for (int k = 0; k < kPhaseCount; ++k)
    st.bond_volume_fraction[k] = bond_sums[k].all_ranks(comm).value() / volume;
  MPI_Allreduce(MPI_IN_PLACE, holding.data(), static_cast<int>(holding.size()), MPI_INT, MPI_MAX,
                comm);
  return holding;
}

}  // namespace

SampleBlock build_cemented_sample_block(MPI_Comm comm, const CementedSampleSpec& spec) {
  if (spec.generator != LatticeGenerator::cells)
    throw std::invalid_argument("build_cemented_sample_block: the lattice generator must be cells");
  SampleBlock b;
  b.description.spec = spec;
  CementedSample& s = b.description.sample;
  CementedSampleStats& st = s.stats;
  // The packing is small and deterministic: every rank makes the same one.
  const Box box = sample_stages::cut_granular_cube(spec, s);
  s.lattice.box = box;
  make_block_lattice(comm, spec, box, b);

  // Voronoi volumes, from the neighbours that the ranks of its bonds send
  // each node.
  double t = MPI_Wtime();
  const NeighbourRows neighbours = gather_neighbours(comm, b);
  set_voronoi_volumes(neighbours, box, b);
  st.voronoi_seconds = MPI_Wtime() - t;

  // Particle membership, the bridges, then the phases of nodes and bonds.
  t = MPI_Wtime();
  const NodePhases bare = AggregateGeometry(box, s.particles, {}).classify(b.coords);
  s.bridges = calibrate_block_bridges(comm, b, box, bare).bridges;
  st.rho_m_requested = spec.bridges.matrix_fraction;
  st.eligible_pairs = static_cast<std::int64_t>(s.bridges.size());
  const AggregateGeometry geometry(box, s.particles, s.bridges);
  NodePhases own = geometry.classify(b.coords);
  const EndPhases end_phase(geometry, own, b.node_begin);
  const VoidRule rule = spec.bridges.void_bonds;
  const PhaseCounts counts = set_bond_phases(comm, end_phase, bare, rule, b);
  for (int k = 0; k < kPhaseCount; ++k) st.bonds_per_phase[k] = counts[k];
  st.nodes_per_particle = static_cast<double>(counts[kPhaseCount + 1]) /
                          static_cast<double>(std::max<std::int64_t>(1, st.sample_particles));
  const std::vector<int> holding =
      set_volume_fractions(comm, b, neighbours, own, geometry, end_phase, rule, st);
  sample_stages::set_count_statistics(st, s.bridges, holding, counts[kPhaseCount]);
  b.particle = std::move(own.particle);
  b.matrix = std::move(own.matrix);
  st.phases_seconds = MPI_Wtime() - t;
  // a time written to the file must be the same on every rank
  st.packing_seconds = max_over_ranks(comm, st.packing_seconds);
  st.lattice_seconds = max_over_ranks(comm, st.lattice_seconds);
  st.voronoi_seconds = max_over_ranks(comm, st.voronoi_seconds);
  st.phases_seconds = max_over_ranks(comm, st.phases_seconds);
  return b;
}

}  // namespace lem
