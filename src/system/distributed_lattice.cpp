#include "lem/system/distributed_lattice.hpp"

#include "lem/base/byte_stream.hpp"
#include "lem/base/collective.hpp"
#include "lem/base/error.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>

namespace lem {
namespace {

// Minimal byte-buffer serialisation of the per-rank pieces.
class Packer {
 public:
  template <class T>
  void put(const std::vector<T>& v) {
    const std::uint64_t n = v.size();
    append(&n, sizeof(n));
    append(v.data(), n * sizeof(T));
  }
  std::vector<char> bytes;

 private:
  void append(const void* p, std::size_t n) {
    const auto* c = static_cast<const char*>(p);
    bytes.insert(bytes.end(), c, c + n);
  }
};

class Unpacker {
 public:
  explicit Unpacker(const std::vector<char>& b) : bytes_(b) {}
  template <class T>
  void get(std::vector<T>& v) {
    std::uint64_t n = 0;
    std::memcpy(&n, bytes_.data() + pos_, sizeof(n));
    pos_ += sizeof(n);
    v.resize(n);
    // An empty vector's data() may be null, which memcpy may not be given
    // even for no bytes (UBSan).
    if (n > 0) std::memcpy(v.data(), bytes_.data() + pos_, n * sizeof(T));
    pos_ += n * sizeof(T);
  }

 private:
  const std::vector<char>& bytes_;
  std::size_t pos_ = 0;
};

struct Piece {
  std::vector<std::int64_t> global_index, node_id;
  std::vector<Point> coords;
  std::vector<std::uint8_t> dof_flags, faces;
  std::vector<double> node_volume;
  std::vector<std::int32_t> node_particle;
  std::vector<std::array<int, 2>> bond_ends;
  std::vector<std::int64_t> bond_id;
  std::vector<double> bond_stiffness, bond_strength;
  std::vector<std::uint8_t> bond_tag;
  std::vector<char> bond_reported;
  std::vector<std::int64_t> owned;  // [owned count]

  std::vector<char> pack() const {
    Packer p;
    p.put(global_index), p.put(node_id), p.put(coords), p.put(dof_flags), p.put(faces);
    p.put(node_volume), p.put(node_particle);
    p.put(bond_ends), p.put(bond_id), p.put(bond_stiffness), p.put(bond_strength), p.put(bond_tag);
    p.put(bond_reported), p.put(owned);
    return std::move(p.bytes);
  }
  void unpack(const std::vector<char>& bytes) {
    Unpacker u(bytes);
    u.get(global_index), u.get(node_id), u.get(coords), u.get(dof_flags), u.get(faces);
    u.get(node_volume), u.get(node_particle);
    u.get(bond_ends), u.get(bond_id), u.get(bond_stiffness), u.get(bond_strength), u.get(bond_tag);
    u.get(bond_reported), u.get(owned);
  }
};

// Build rank r's piece on the root.
Piece make_piece(int r, const Lattice& lattice, const TensionConstraints& tc,
                 const Partition& partition, const std::vector<std::uint8_t>& faces,
                 const std::vector<std::int64_t>& old_of_new,
                 const std::vector<std::int32_t>& rank_bonds) {
  Piece piece;
  const std::int64_t begin = partition.offsets[r], end = partition.offsets[r + 1];
  std::map<std::int64_t, int> ghost_slot;  // new index -> provisional slot
  for (auto b : rank_bonds)
    for (std::int32_t n : {lattice.bonds[b].i, lattice.bonds[b].j}) {
      const std::int64_t g = partition.new_index[n];
      if (g < begin || g >= end) ghost_slot.emplace(g, 0);
    }
  const int owned = static_cast<int>(end - begin);
  int slot = owned;
  for (auto& [g, s] : ghost_slot) s = slot++;  // ghosts in increasing global order
  auto add_node = [&](std::int64_t g) {
    const std::int64_t n = old_of_new[g];
    piece.global_index.push_back(g);
    piece.node_id.push_back(n);
    piece.coords.push_back(lattice.nodes[n]);
    piece.dof_flags.push_back(tc.dof_flags[n]);
    piece.faces.push_back(faces[n]);
    if (!lattice.node_volume.empty()) piece.node_volume.push_back(lattice.node_volume[n]);
    if (!lattice.node_particle.empty()) piece.node_particle.push_back(lattice.node_particle[n]);
  };
  for (std::int64_t g = begin; g < end; ++g) add_node(g);
  for (const auto& [g, s] : ghost_slot) add_node(g);
  auto local = [&](std::int32_t n) {
    const std::int64_t g = partition.new_index[n];
    return (g >= begin && g < end) ? static_cast<int>(g - begin) : ghost_slot.at(g);
  };
  for (auto b : rank_bonds) {
    const auto& bond = lattice.bonds[b];
    piece.bond_ends.push_back({local(bond.i), local(bond.j)});
    piece.bond_id.push_back(lattice.bond_id.empty() ? static_cast<std::int64_t>(b)
                                                    : lattice.bond_id[b]);
    piece.bond_stiffness.push_back(lattice.stiffness[b]);
    if (!lattice.strength.empty()) piece.bond_strength.push_back(lattice.strength[b]);
    if (!lattice.tag.empty()) piece.bond_tag.push_back(lattice.tag[b]);
    const std::int64_t low = std::min(partition.new_index[bond.i], partition.new_index[bond.j]);
    piece.bond_reported.push_back(low >= begin && low < end ? 1 : 0);
  }
  piece.owned = {owned};
  return piece;
}


// The numbers every rank needs of the whole lattice: a (the lattice's own, or
// that of the elements it was cut from), the node and active-bond counts and
// the box.
void lattice_header(const Lattice& lattice, const TensionConstraints& constraints,
                    double header[9]) {
  double length_sum = 0;
  for (std::size_t b = 0; b < lattice.bond_count(); ++b) length_sum += lattice.bond_length(b);
  std::int64_t active = 0;
  for (char a : constraints.bond_active) active += a;
  const double bonds = static_cast<double>(std::max<std::size_t>(1, lattice.bond_count()));
  header[0] = lattice.element_length > 0 ? lattice.element_length : length_sum / bonds;
  header[1] = static_cast<double>(lattice.node_count());
  header[2] = static_cast<double>(active);
  for (int a = 0; a < 3; ++a) {
    header[3 + a] = lattice.box.lo[a];
    header[6 + a] = lattice.box.hi[a];
  }
}

// The active bonds of each rank: those with an end it owns.
std::vector<std::vector<std::int32_t>> bonds_by_rank(const Lattice& lattice,
                                                     const TensionConstraints& constraints,
                                                     const Partition& partition, int size) {
  std::vector<std::vector<std::int32_t>> rank_bonds(size);
  for (std::size_t b = 0; b < lattice.bond_count(); ++b) {
    if (!constraints.bond_active[b]) continue;
    const int oi = partition.owner[lattice.bonds[b].i];
    const int oj = partition.owner[lattice.bonds[b].j];
    rank_bonds[oi].push_back(static_cast<std::int32_t>(b));
    if (oj != oi) rank_bonds[oj].push_back(static_cast<std::int32_t>(b));
  }
  return rank_bonds;
}

// This rank's part of the lattice from its piece and the shared header.
void take_piece(DistributedLattice& dl, const double header[9], Piece&& piece) {
  int rank = 0;
  MPI_Comm_rank(dl.comm, &rank);
  dl.mean_bond_length = header[0];
  dl.global_nodes = static_cast<std::int64_t>(header[1]);
  dl.global_bonds = static_cast<std::int64_t>(header[2]);
  for (int a = 0; a < 3; ++a) {
    dl.box.lo[a] = header[3 + a];
    dl.box.hi[a] = header[6 + a];
  }
  dl.owned = static_cast<int>(piece.owned.at(0));
  // Blocks follow rank order, so the block start is the sum over lower ranks.
  std::int64_t owned64 = dl.owned, begin = 0;
  MPI_Exscan(&owned64, &begin, 1, MPI_INT64_T, MPI_SUM, dl.comm);
  dl.node_begin = rank == 0 ? 0 : begin;
  dl.global_index = std::move(piece.global_index);
  dl.node_id = std::move(piece.node_id);
  dl.coords = std::move(piece.coords);
  dl.dof_flags = std::move(piece.dof_flags);
  dl.faces = std::move(piece.faces);
  dl.node_volume = std::move(piece.node_volume);
  dl.node_particle = std::move(piece.node_particle);
  dl.bond_ends = std::move(piece.bond_ends);
  dl.bond_id = std::move(piece.bond_id);
  dl.bond_stiffness = std::move(piece.bond_stiffness);
  dl.bond_strength = std::move(piece.bond_strength);
  dl.bond_tag = std::move(piece.bond_tag);
  dl.bond_reported = std::move(piece.bond_reported);
}

}  // namespace

DistributedLattice distribute_lattice(MPI_Comm comm, const Lattice& lattice,
                                      const TensionConstraints& constraints,
                                      const Partition& partition,
                                      const std::vector<std::uint8_t>& faces) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  DistributedLattice dl;
  dl.comm = comm;
  double header[9] = {};
  std::vector<char> mine;
  // Rank 0 builds and sends the pieces while the others wait for theirs: a
  // failure there must not leave them waiting.  It sends kFailed to every
  // rank still waiting, and all agree on its error.
  constexpr std::uint64_t kFailed = ~std::uint64_t(0);
  std::exception_ptr error;
  if (rank == 0) {
    int next = size - 1;  // the pieces go from the last rank down
    try {
      if (partition.parts != size)
        throw std::logic_error("distribute_lattice: partition has a different number of parts");
      lattice_header(lattice, constraints, header);
      std::vector<std::int64_t> old_of_new(lattice.node_count());
      for (std::size_t n = 0; n < lattice.node_count(); ++n)
        old_of_new[partition.new_index[n]] = static_cast<std::int64_t>(n);
      std::vector<std::vector<std::int32_t>> rank_bonds =
          bonds_by_rank(lattice, constraints, partition, size);
      for (; next >= 0; --next) {
        auto bytes =
            make_piece(next, lattice, constraints, partition, faces, old_of_new, rank_bonds[next])
                .pack();
        rank_bonds[next].clear();
        rank_bonds[next].shrink_to_fit();
        if (next == 0) {
          mine = std::move(bytes);
        } else {
          const std::uint64_t n = bytes.size();
          MPI_Send(&n, 1, MPI_UINT64_T, next, 0, comm);
          send_bytes(comm, bytes.data(), n, next, 1);
        }
      }
    } catch (...) {
      error = std::current_exception();
      for (int r = 1; r <= next; ++r) MPI_Send(&kFailed, 1, MPI_UINT64_T, r, 0, comm);
    }
  } else {
    std::uint64_t n = 0;
    MPI_Recv(&n, 1, MPI_UINT64_T, 0, 0, comm, MPI_STATUS_IGNORE);
    if (n != kFailed) {
      mine.resize(n);
      receive_bytes(comm, mine.data(), n, 0, 1);
    }
  }
  agree_on_error(comm, error);
  MPI_Bcast(header, 9, MPI_DOUBLE, 0, comm);
  Piece piece;
  piece.unpack(mine);
  take_piece(dl, header, std::move(piece));
  return dl;
}

void bond_direction(const DistributedLattice& l, int bond, double n[3]) {
  const auto [p, q] = l.bond_ends[bond];
  double length2 = 0;
  for (int a = 0; a < 3; ++a) {
    n[a] = l.coords[q][a] - l.coords[p][a];
    length2 += n[a] * n[a];
  }
  const double inv = 1.0 / std::sqrt(length2);
  for (int a = 0; a < 3; ++a) n[a] *= inv;
}

}  // namespace lem
