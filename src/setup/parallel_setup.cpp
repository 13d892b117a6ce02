#include "lem/setup/parallel_setup.hpp"

#include "lem/base/cell_grid.hpp"
#include "lem/lattice/cell_lattice.hpp"
#include "lem/base/collective.hpp"
#include "lem/base/error.hpp"
#include "lem/base/exact_sum.hpp"
#include "lem/base/log.hpp"
#include "lem/system/partition.hpp"
#include "lem/base/redistribute.hpp"
#include "lem/sample/sample_reader.hpp"
#include "lem/system/tension.hpp"

#include "parallel_constraints.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <type_traits>
#include <unordered_map>

namespace lem {
namespace {

int rank_in(MPI_Comm comm) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  return rank;
}

int ranks_in(MPI_Comm comm) {
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  return ranks;
}

std::int64_t exclusive_prefix(MPI_Comm comm, std::int64_t mine) {
  std::int64_t before = 0;
  MPI_Exscan(&mine, &before, 1, MPI_INT64_T, MPI_SUM, comm);
  return rank_in(comm) == 0 ? 0 : before;
}

// A node on its way to its owner.
struct NodeRecord {
  std::int64_t id;
  Point x;
  double volume;
  std::int32_t particle;
  std::uint8_t faces, pad[3];
};

// A bond of the mechanical lattice on its way to the owners of its ends.
struct BondRecord {
  std::int64_t id, i, j;  // mechanical bond id; end nodes (file rows)
  Point xi, xj;           // the ends' positions: their cells name their owners
  double k, f;
  std::uint8_t tag, pad[7];
};

// What the owner of a ghost node tells the ranks that hold it.
struct GhostRecord {
  std::int64_t global_index;
  double volume;
  std::int32_t particle;
  std::uint8_t faces, pad[3];
};

// This rank's block of node rows: where the parallel set-up starts, from a
// sample file or from the generator.
struct NodeBlock {
  Box box;
  std::int64_t nodes = 0, node_begin = 0;
  std::vector<Point> coords;
  std::vector<double> volume;          // empty: the lattice has none
  std::vector<std::int32_t> particle;  // empty: the lattice has none
  bool strengths = true;               // the bonds have breaking forces and phases
};

// Sums of the lengths of a rank's bonds, to the lattice's statistics.
struct LengthSums {
  ExactSum sum, squares;
  double shortest = std::numeric_limits<double>::infinity(), longest = 0;
  void add(const Point& p, const Point& q) {
    const double l = std::sqrt((q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]) +
                               (q[2] - p[2]) * (q[2] - p[2]));
    sum.add(l);
    squares.add(l * l);
    shortest = std::min(shortest, l);
    longest = std::max(longest, l);
  }
  /// lattice_stats of the whole lattice.  Collective.
  LatticeStats stats(MPI_Comm comm, std::int64_t nodes, std::int64_t bonds) const {
    LatticeStats s;
    s.nodes = nodes;
    s.bonds = bonds;
    if (bonds == 0) return s;
    const double n = static_cast<double>(bonds);
    s.mean_length = sum.all_ranks(comm).value() / n;
    const double mean_square = squares.all_ranks(comm).value() / n;
    s.std_length = std::sqrt(std::max(0.0, mean_square - s.mean_length * s.mean_length));
    MPI_Allreduce(&shortest, &s.min_length, 1, MPI_DOUBLE, MPI_MIN, comm);
    MPI_Allreduce(&longest, &s.max_length, 1, MPI_DOUBLE, MPI_MAX, comm);
    s.mean_coordination = 2.0 * n / static_cast<double>(s.nodes);
    s.mesh_density = std::pow(n, -1.0 / 3.0);
    return s;
  }
};

// Steps 1-2: the bonds of this rank's block of rows, checked, with their
// stiffness, strength and id (its row of /bonds); the lattice statistics.
struct BlockBonds {
  std::vector<BondRecord> bonds;
  std::int64_t kept = 0;  // mechanical bonds, all ranks
  SampleInfo info;
};

BlockBonds mechanical_bonds(MPI_Comm comm, const SampleBlock& block, const SampleOptions& o) {
  const Box& box = block.description.sample.lattice.box;
  // Lengths: statistics of every bond (void ones too).
  LengthSums lengths;
  for (const auto& [p, q] : block.end_coords) lengths.add(p, q);
  BlockBonds out;
  const LatticeStats& s = out.info.stats = lengths.stats(comm, block.nodes, block.bonds);
  out.info.cemented = block.description.sample.stats;

  // The mechanical lattice: void bonds and bonds of zero stiffness dropped,
  // the others keep their file row as id (mechanical_lattice's ids); a is
  // the mean length of every bond of the file (mechanical_lattice's a).
  const double a = s.mean_length;
  for (std::size_t k = 0; k < block.ends.size(); ++k) {
    const Phase phase = o.homogeneous ? Phase::p : block.bond_phase[k];
    const int code = static_cast<int>(phase);
    const double stiffness = o.phases.modulus[code] * a;
    if (phase == Phase::v || stiffness <= 0) continue;
    BondRecord r{};
    r.id = block.bond_begin + static_cast<std::int64_t>(k);  // the row of /bonds
    r.i = block.ends[k][0];
    r.j = block.ends[k][1];
    r.xi = block.end_coords[k][0];
    r.xj = block.end_coords[k][1];
    r.k = stiffness;
    r.f = o.phases.strength[code] * a * a;
    r.tag = static_cast<std::uint8_t>(code);
    if (o.halve_face_bonds) {
      const double share = face_share(faces_of(r.xi, box), faces_of(r.xj, box));
      r.k *= share;
      r.f *= share;
    }
    add_affine_bond(out.info.affine, r.xi, r.xj, r.k, box.volume());
    out.bonds.push_back(r);
  }
  out.kept = sum_over_ranks(comm, static_cast<std::int64_t>(out.bonds.size()));
  MPI_Allreduce(MPI_IN_PLACE, &out.info.affine.C[0][0], 36, MPI_DOUBLE, MPI_SUM, comm);
  finish_affine_moduli(out.info.affine);
  return out;
}

// Step 3: the owner rank of every position, from a METIS partition of a
// grid of cells (about 8 to 256 nodes each, and 64 cells per rank or more).
class CellOwners {
 public:
  CellOwners(MPI_Comm comm, const NodeBlock& block, const std::vector<BondRecord>& bonds)
      : grid_(block.box, cell_side(comm, block)) {
    const int ranks = ranks_in(comm);
    const std::size_t cells = grid_.cell_count();
    // Work per cell: its nodes and the ends of its bonds; bonds between
    // neighbouring cells, one count per direction (27 around a cell).
    std::vector<std::int64_t> weight(cells, 0);
    std::vector<std::int32_t> joined(27 * cells, 0);
    for (const Point& x : block.coords) ++weight[grid_.cell_of(x)];
    for (const BondRecord& b : bonds) {
      const auto ci = grid_.coordinates(b.xi), cj = grid_.coordinates(b.xj);
      const std::size_t i = grid_.index(ci[0], ci[1], ci[2]), j = grid_.index(cj[0], cj[1], cj[2]);
      ++weight[i], ++weight[j];
      if (i == j) continue;
      int d = 0;
      bool near = true;
      for (int a = 0; a < 3; ++a) {
        const int step = cj[a] - ci[a];
        near = near && std::abs(step) <= 1;
        d = 3 * d + step + 1;
      }
      if (!near) continue;  // longer than a cell: left out of the weights only
      ++joined[27 * i + d];
      ++joined[27 * j + (26 - d)];
    }
    MPI_Allreduce(MPI_IN_PLACE, weight.data(), static_cast<int>(cells), MPI_INT64_T, MPI_SUM, comm);
    in_pieces(joined.size(), std::uint64_t(1) << 28, [&](std::uint64_t start, int count) {
      MPI_Allreduce(MPI_IN_PLACE, joined.data() + start, count, MPI_INT32_T, MPI_SUM, comm);
    });
    const std::int64_t filled =
        std::count_if(weight.begin(), weight.end(), [](std::int64_t w) { return w > 0; });
    if (filled < ranks)
      throw InputError("the lattice's " + std::to_string(block.nodes) + " nodes fill " +
                       std::to_string(filled) + " cells of the partition grid, fewer than the " +
                       std::to_string(ranks) + " ranks: run it on fewer ranks");
    std::vector<std::int64_t> xadj(cells + 1, 0), adjncy, adjwgt;
    const auto& n = grid_.counts();
    for (std::size_t c = 0; c < cells; ++c) {
      const int ck = static_cast<int>(c % n[2]), cj = static_cast<int>(c / n[2] % n[1]),
                ci = static_cast<int>(c / n[2] / n[1]);
      for (int d = 0; d < 27; ++d) {
        if (d == 13 || joined[27 * c + d] == 0) continue;
        adjncy.push_back(static_cast<std::int64_t>(
            grid_.index(ci + d / 9 - 1, cj + d / 3 % 3 - 1, ck + d % 3 - 1)));
        adjwgt.push_back(joined[27 * c + d]);
      }
      xadj[c + 1] = static_cast<std::int64_t>(adjncy.size());
    }
    part_ = partition_cells(weight, xadj, adjncy, adjwgt, ranks);
  }

  int owner(const Point& x) const { return part_[grid_.cell_of(x)]; }

 private:
  static double cell_side(MPI_Comm comm, const NodeBlock& block) {
    const double nodes = static_cast<double>(std::max<std::int64_t>(block.nodes, 1));
    const double per_cell = std::clamp(nodes / (64.0 * ranks_in(comm)), 8.0, 256.0);
    return std::cbrt(block.box.volume() * per_cell / nodes);
  }

  CellGrid grid_;
  std::vector<int> part_;
};

std::uint8_t tension_flags(std::uint8_t faces) {
  if (faces & kZmax) return kFixZ | kLoadedTop;
  if (faces & kZmin) return kFixZ;
  return 0;
}

// This rank's nodes of the block sent to their owners, in the same order
// on any rank count: along the Morton curve, then by id.
std::vector<NodeRecord> route_nodes(MPI_Comm comm, const NodeBlock& block,
                                    const CellOwners& owners) {
  const Box& box = block.box;
  std::vector<NodeRecord> nodes(block.coords.size());
  std::vector<int> to(nodes.size());
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    NodeRecord& r = nodes[k];
    r = NodeRecord{};
    r.id = block.node_begin + static_cast<std::int64_t>(k);
    r.x = block.coords[k];
    r.volume = block.volume.empty() ? 0.0 : block.volume[k];
    r.particle = block.particle.empty() ? -1 : block.particle[k];
    r.faces = faces_of(r.x, box);
    to[k] = owners.owner(r.x);
  }
  std::vector<NodeRecord> owned = route(comm, nodes, to);
  nodes.clear();
  std::sort(owned.begin(), owned.end(), [&](const NodeRecord& a, const NodeRecord& b) {
    const std::uint64_t ka = morton_code(a.x, box), kb = morton_code(b.x, box);
    return ka != kb ? ka < kb : a.id < b.id;
  });
  return owned;
}

// Each bond sent to the owners of both its ends, sorted by id there.
std::vector<BondRecord> route_bonds(MPI_Comm comm, const std::vector<BondRecord>& bonds,
                                    const CellOwners& owners) {
  std::vector<BondRecord> sent;
  std::vector<int> to;
  for (const BondRecord& b : bonds) {
    const int oi = owners.owner(b.xi), oj = owners.owner(b.xj);
    sent.push_back(b), to.push_back(oi);
    if (oj != oi) sent.push_back(b), to.push_back(oj);
  }
  std::vector<BondRecord> held = route(comm, sent, to);
  sent.clear();
  std::sort(held.begin(), held.end(),
            [](const BondRecord& a, const BondRecord& b) { return a.id < b.id; });
  return held;
}

// The lattice of the owned nodes, numbered after those of the lower ranks;
// `local` maps their ids to their local indices.
DistributedLattice lattice_of_owned(MPI_Comm comm, const NodeBlock& block,
                                    const std::vector<NodeRecord>& owned,
                                    std::unordered_map<std::int64_t, int>& local) {
  DistributedLattice dl;
  dl.comm = comm;
  dl.box = block.box;
  dl.global_nodes = block.nodes;
  dl.owned = static_cast<int>(owned.size());
  dl.node_begin = exclusive_prefix(comm, dl.owned);
  for (const NodeRecord& r : owned) {
    local.emplace(r.id, dl.local_nodes());
    dl.global_index.push_back(dl.node_begin + dl.local_nodes());
    dl.node_id.push_back(r.id);
    dl.coords.push_back(r.x);
    dl.faces.push_back(r.faces);
    dl.dof_flags.push_back(tension_flags(r.faces));
    dl.node_volume.push_back(r.volume);
    dl.node_particle.push_back(r.particle);
  }
  return dl;
}

// Ghosts: ends of held bonds owned elsewhere, asked of their owners and
// added in increasing global order (their owners into `ghost_owner`).
void add_ghosts(MPI_Comm comm, const std::vector<BondRecord>& held, const CellOwners& owners,
                DistributedLattice& dl, std::unordered_map<std::int64_t, int>& local,
                std::vector<int>& ghost_owner) {
  const int rank = rank_in(comm);
  std::map<std::int64_t, int> ghosts;  // id -> owner
  for (const BondRecord& b : held) {
    if (owners.owner(b.xi) != rank) ghosts.emplace(b.i, owners.owner(b.xi));
    if (owners.owner(b.xj) != rank) ghosts.emplace(b.j, owners.owner(b.xj));
  }
  std::vector<std::int64_t> ghost_ids;
  std::vector<int> ghost_to;
  for (const auto& [id, owner] : ghosts) ghost_ids.push_back(id), ghost_to.push_back(owner);
  std::unordered_map<std::int64_t, Point> ghost_x;
  for (const BondRecord& b : held) ghost_x.emplace(b.i, b.xi), ghost_x.emplace(b.j, b.xj);
  const std::vector<GhostRecord> told =
      ask<GhostRecord>(comm, ghost_ids, ghost_to, [&](std::int64_t id) {
        const int n = local.at(id);
        GhostRecord g{};
        g.global_index = dl.global_index[n];
        g.volume = dl.node_volume[n];
        g.particle = dl.node_particle[n];
        g.faces = dl.faces[n];
        return g;
      });
  std::vector<std::size_t> order(ghost_ids.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return told[a].global_index < told[b].global_index;
  });
  ghost_owner.clear();
  for (const std::size_t g : order) {
    const std::int64_t id = ghost_ids[g];
    local.emplace(id, dl.local_nodes());
    dl.global_index.push_back(told[g].global_index);
    dl.node_id.push_back(id);
    dl.coords.push_back(ghost_x.at(id));
    dl.faces.push_back(told[g].faces);
    dl.dof_flags.push_back(tension_flags(told[g].faces));
    dl.node_volume.push_back(told[g].volume);
    dl.node_particle.push_back(told[g].particle);
    ghost_owner.push_back(ghost_to[g]);
  }
}

// Step 4: nodes and bonds at their owners, numbered; ghosts known.
DistributedLattice distribute(MPI_Comm comm, const NodeBlock& block,
                              const std::vector<BondRecord>& bonds, const CellOwners& owners,
                              std::vector<int>& ghost_owner) {
  const std::vector<NodeRecord> owned = route_nodes(comm, block, owners);
  const std::vector<BondRecord> held = route_bonds(comm, bonds, owners);
  std::unordered_map<std::int64_t, int> local;  // node id -> local index
  DistributedLattice dl = lattice_of_owned(comm, block, owned, local);
  add_ghosts(comm, held, owners, dl, local, ghost_owner);
  // Each bond reported by the owner of its lower end.
  const std::int64_t end = dl.node_begin + dl.owned;
  for (const BondRecord& b : held) {
    const int p = local.at(b.i), q = local.at(b.j);
    dl.bond_ends.push_back({p, q});
    dl.bond_id.push_back(b.id);
    dl.bond_stiffness.push_back(b.k);
    dl.bond_strength.push_back(b.f);
    dl.bond_tag.push_back(b.tag);
    const std::int64_t low = std::min(dl.global_index[p], dl.global_index[q]);
    dl.bond_reported.push_back(low >= dl.node_begin && low < end ? 1 : 0);
  }
  return dl;
}

// Steps 3-5, from this rank's nodes and bonds.
DistributedLattice partition_and_constrain(MPI_Comm comm, const NodeBlock& nodes,
                                           std::vector<BondRecord>& bonds, double a,
                                           SetupReport& report) {
  double t = MPI_Wtime();
  const CellOwners owners(comm, nodes, bonds);
  report.seconds_partition = MPI_Wtime() - t;

  t = MPI_Wtime();
  std::vector<int> ghost_owner;
  DistributedLattice dl = distribute(comm, nodes, bonds, owners, ghost_owner);
  dl.mean_bond_length = a;
  bonds.clear();
  bonds.shrink_to_fit();
  report.seconds_distribute = MPI_Wtime() - t;

  t = MPI_Wtime();
  constrain(dl, ghost_owner, report);
  report.seconds_constraints = MPI_Wtime() - t;
  // What the lattice does not have, it does not carry.
  if (nodes.volume.empty()) dl.node_volume.clear();
  if (nodes.particle.empty()) dl.node_particle.clear();
  if (!nodes.strengths) dl.bond_strength.clear(), dl.bond_tag.clear();
  return dl;
}

}  // namespace

DistributedLattice setup_sample_in_parallel(MPI_Comm comm, const SampleOptions& o,
                                            SetupReport& report) {
  LogStageScope stage("Sample setup");
  const double t = MPI_Wtime();
  SampleBlock block = read_sample_block(comm, o.sample_file);
  BlockBonds bonds = mechanical_bonds(comm, block, o);
  report.sample = bonds.info;
  NodeBlock nodes;
  nodes.box = block.description.sample.lattice.box;
  nodes.nodes = block.nodes;
  nodes.node_begin = block.node_begin;
  nodes.coords = std::move(block.coords);
  nodes.volume = std::move(block.volume);
  nodes.particle = std::move(block.particle);
  block = SampleBlock{};
  report.seconds_build = MPI_Wtime() - t;
  DistributedLattice dl =
      partition_and_constrain(comm, nodes, bonds.bonds, bonds.info.stats.mean_length, report);
  stage.pop();
  return dl;
}

DistributedLattice setup_generated_in_parallel(MPI_Comm comm, const SampleOptions& o,
                                               SetupReport& report) {
  LogStageScope stage("Sample setup");
  const double t = MPI_Wtime();
  LatticeBlock lattice = make_cell_lattice(comm, o.random);
  const Box& box = lattice.box;
  LengthSums lengths;
  std::vector<BondRecord> bonds(lattice.ends.size());
  for (std::size_t k = 0; k < bonds.size(); ++k) {
    BondRecord& r = bonds[k];
    r = BondRecord{};
    r.id = lattice.bond_begin + static_cast<std::int64_t>(k);
    r.i = lattice.ends[k][0];
    r.j = lattice.ends[k][1];
    r.xi = lattice.end_coords[k][0];
    r.xj = lattice.end_coords[k][1];
    r.k = o.random.stiffness;
    if (o.halve_face_bonds) r.k *= face_share(faces_of(r.xi, box), faces_of(r.xj, box));
    lengths.add(r.xi, r.xj);
    add_affine_bond(report.sample.affine, r.xi, r.xj, r.k, box.volume());
  }
  report.sample.stats = lengths.stats(comm, lattice.nodes, lattice.bonds);
  MPI_Allreduce(MPI_IN_PLACE, &report.sample.affine.C[0][0], 36, MPI_DOUBLE, MPI_SUM, comm);
  finish_affine_moduli(report.sample.affine);
  NodeBlock nodes;
  nodes.box = box;
  nodes.nodes = lattice.nodes;
  nodes.node_begin = lattice.node_begin;
  nodes.coords = std::move(lattice.coords);
  nodes.strengths = false;
  lattice = LatticeBlock{};
  report.seconds_build = MPI_Wtime() - t;
  DistributedLattice dl =
      partition_and_constrain(comm, nodes, bonds, report.sample.stats.mean_length, report);
  stage.pop();
  return dl;
}

}  // namespace lem
