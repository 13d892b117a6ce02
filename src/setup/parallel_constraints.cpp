// The tension constraints of a lattice set up in parallel
// (parallel_constraints.hpp).
#include "parallel_constraints.hpp"

#include "lem/base/collective.hpp"
#include "lem/base/error.hpp"
#include "lem/system/pieces.hpp"
#include "lem/base/redistribute.hpp"
#include "lem/system/tension.hpp"

#include <cmath>
#include <map>
#include <type_traits>
#include <unordered_map>

namespace lem {
namespace {

// Per piece of the lattice, summed over the ranks (few pieces).
struct PieceFaces {
  std::int64_t bottom = 0, top = 0;
  double bottom_x = 0, bottom_y = 0, top_x = 0, top_y = 0;
  bool on_bottom() const { return bottom > 0; }
  double x() const { return on_bottom() ? bottom_x / double(bottom) : top_x / double(top); }
  double y() const { return on_bottom() ? bottom_y / double(bottom) : top_y / double(top); }
};

// The node of each piece that `better` prefers (of the nodes on the piece's
// anchoring face), over all ranks; ties go to the lowest id.
struct Pick {
  std::int64_t piece, id;
  double score, x, y;
};

template <class Score>
std::map<std::int64_t, Pick> pick_nodes(const DistributedLattice& l,
                                        const std::vector<std::int64_t>& label,
                                        const std::map<std::int64_t, PieceFaces>& pieces,
                                        Score&& score) {
  std::map<std::int64_t, Pick> best;
  const auto take = [&](const Pick& p) {
    auto [it, fresh] = best.emplace(p.piece, p);
    if (!fresh &&
        (p.score < it->second.score || (p.score == it->second.score && p.id < it->second.id)))
      it->second = p;
  };
  for (int n = 0; n < l.owned; ++n) {
    if (label[n] < 0) continue;
    const auto it = pieces.find(label[n]);
    if (it == pieces.end()) continue;
    const std::uint8_t face = it->second.on_bottom() ? kZmin : kZmax;
    if (!(l.faces[n] & face)) continue;
    take({label[n], l.node_id[n], score(label[n], l.coords[n]), l.coords[n][0], l.coords[n][1]});
  }
  std::vector<Pick> mine;
  for (const auto& [piece, p] : best) mine.push_back(p);
  best.clear();
  for (const Pick& p : allgather(l.comm, mine)) take(p);
  return best;
}

// Per piece (by label), its nodes on the bottom and top faces and their
// x and y summed, over all ranks.
std::map<std::int64_t, PieceFaces> piece_faces(const DistributedLattice& l,
                                               const std::vector<std::int64_t>& label) {
  struct Sums {
    std::int64_t piece, bottom, top;
    double bottom_x, bottom_y, top_x, top_y;
  };
  std::map<std::int64_t, Sums> mine;
  for (int n = 0; n < l.owned; ++n) {
    if (label[n] < 0) continue;
    auto [it, fresh] = mine.emplace(label[n], Sums{label[n], 0, 0, 0, 0, 0, 0});
    Sums& s = it->second;
    if (l.faces[n] & kZmin) ++s.bottom, s.bottom_x += l.coords[n][0], s.bottom_y += l.coords[n][1];
    if (l.faces[n] & kZmax) ++s.top, s.top_x += l.coords[n][0], s.top_y += l.coords[n][1];
  }
  std::vector<Sums> list;
  for (const auto& [piece, s] : mine) list.push_back(s);
  std::map<std::int64_t, PieceFaces> pieces;
  for (const Sums& s : allgather(l.comm, list)) {
    PieceFaces& p = pieces[s.piece];
    p.bottom += s.bottom, p.top += s.top;
    p.bottom_x += s.bottom_x, p.bottom_y += s.bottom_y, p.top_x += s.top_x, p.top_y += s.top_y;
  }
  return pieces;
}

// A piece with fewer than three nodes on the loaded faces carries no load:
// it is dropped. Throws InputError when no piece left joins the faces.
void keep_loaded_pieces(std::map<std::int64_t, PieceFaces>& pieces) {
  std::int64_t loaded = 0;
  for (auto it = pieces.begin(); it != pieces.end();) {
    const PieceFaces& p = it->second;
    if (p.bottom + p.top >= 3) {
      loaded += p.bottom > 0 && p.top > 0;
      ++it;
      continue;
    }
    it = pieces.erase(it);
  }
  if (loaded == 0)
    throw InputError("tension: no connected piece of the lattice joins the bottom face to the "
                     "top face (sample disconnected)");
}

// Anchors: the node nearest the centroid of the piece's face holds x and
// y; the node farthest from it, the component across the line between them.
void anchor_pieces(DistributedLattice& l, const std::vector<std::int64_t>& label,
                   const std::map<std::int64_t, PieceFaces>& pieces) {
  const auto anchors = pick_nodes(l, label, pieces, [&](std::int64_t piece, const Point& x) {
    const PieceFaces& p = pieces.at(piece);
    return (x[0] - p.x()) * (x[0] - p.x()) + (x[1] - p.y()) * (x[1] - p.y());
  });
  const auto far = pick_nodes(l, label, pieces, [&](std::int64_t piece, const Point& x) {
    const Pick& a = anchors.at(piece);
    return -((x[0] - a.x) * (x[0] - a.x) + (x[1] - a.y) * (x[1] - a.y));
  });
  for (int n = 0; n < l.owned; ++n) {
    if (label[n] < 0 || pieces.count(label[n]) == 0) continue;
    const Pick& a = anchors.at(label[n]);
    const Pick& f = far.at(label[n]);
    if (l.node_id[n] == a.id) l.dof_flags[n] |= kFixX | kFixY;
    if (l.node_id[n] == f.id)
      l.dof_flags[n] |= std::fabs(f.x - a.x) >= std::fabs(f.y - a.y) ? kFixY : kFixX;
  }
}

// Ghost copies take their owners' flags.
void flags_to_ghosts(DistributedLattice& l, const std::vector<int>& ghost_owner) {
  std::unordered_map<std::int64_t, int> owned_index;
  for (int n = 0; n < l.owned; ++n) owned_index.emplace(l.node_id[n], n);
  const std::vector<std::int64_t> ghost_ids(l.node_id.begin() + l.owned, l.node_id.end());
  const std::vector<std::uint8_t> flags =
      ask<std::uint8_t>(l.comm, ghost_ids, ghost_owner,
                        [&](std::int64_t id) { return l.dof_flags[owned_index.at(id)]; });
  std::copy(flags.begin(), flags.end(), l.dof_flags.begin() + l.owned);
}

// The lattice's owned nodes, with no bond and no ghost.
DistributedLattice owned_nodes_of(const DistributedLattice& l) {
  DistributedLattice k;
  k.comm = l.comm, k.box = l.box, k.mean_bond_length = l.mean_bond_length;
  k.global_nodes = l.global_nodes, k.node_begin = l.node_begin, k.owned = l.owned;
  const auto owned_part = [&](const auto& v) {
    return std::decay_t<decltype(v)>(v.begin(), v.begin() + l.owned);
  };
  k.global_index = owned_part(l.global_index), k.node_id = owned_part(l.node_id);
  k.coords = owned_part(l.coords), k.dof_flags = owned_part(l.dof_flags);
  k.faces = owned_part(l.faces), k.node_volume = owned_part(l.node_volume);
  k.node_particle = owned_part(l.node_particle);
  return k;
}

// Only the bonds between nodes that are not `out` stay, and the ghosts
// they reach; counts into `report`.
void keep_system_bonds(DistributedLattice& l, const std::vector<char>& out, SetupReport& report) {
  std::int64_t pruned = 0, kept = 0, cut = 0, pinned = 0, bottom = 0, top = 0;
  std::vector<int> renumber(l.local_nodes(), -1);
  for (int n = 0; n < l.owned; ++n) renumber[n] = n;
  DistributedLattice k = owned_nodes_of(l);
  for (int b = 0; b < l.local_bonds(); ++b) {
    const auto [p, q] = l.bond_ends[b];
    if (out[p] || out[q]) {
      pruned += l.bond_reported[b];
      continue;
    }
    k.bond_ends.push_back({p, q});
    k.bond_id.push_back(l.bond_id[b]);
    k.bond_stiffness.push_back(l.bond_stiffness[b]);
    k.bond_strength.push_back(l.bond_strength[b]);
    k.bond_tag.push_back(l.bond_tag[b]);
    k.bond_reported.push_back(l.bond_reported[b]);
    kept += l.bond_reported[b];
    cut += l.bond_reported[b] && (p >= l.owned || q >= l.owned);
    for (const int n : {p, q}) renumber[n] = 0;  // marked: still needed
  }
  for (int n = l.owned; n < l.local_nodes(); ++n) {
    if (renumber[n] < 0) continue;
    renumber[n] = k.local_nodes();
    k.global_index.push_back(l.global_index[n]);
    k.node_id.push_back(l.node_id[n]);
    k.coords.push_back(l.coords[n]);
    k.dof_flags.push_back(l.dof_flags[n]);
    k.faces.push_back(l.faces[n]);
    k.node_volume.push_back(l.node_volume[n]);
    k.node_particle.push_back(l.node_particle[n]);
  }
  for (int n = 0; n < l.owned; ++n) renumber[n] = n;
  for (auto& e : k.bond_ends) e = {renumber[e[0]], renumber[e[1]]};
  for (int n = 0; n < l.owned; ++n) {
    if (l.dof_flags[n] & kPinned) {
      ++pinned;
      continue;
    }
    bottom += (l.faces[n] & kZmin) != 0;
    top += (l.faces[n] & kZmax) != 0;
  }
  l = std::move(k);
  l.global_bonds = sum_over_ranks(l.comm, kept);
  report.active_bonds = l.global_bonds;
  report.pruned_bonds = sum_over_ranks(l.comm, pruned);
  report.pinned_nodes = sum_over_ranks(l.comm, pinned);
  report.bottom_nodes = sum_over_ranks(l.comm, bottom);
  report.top_nodes = sum_over_ranks(l.comm, top);
  report.edge_cut = sum_over_ranks(l.comm, cut);
}

}  // namespace

void constrain(DistributedLattice& l, const std::vector<int>& ghost_owner, SetupReport& report) {
  std::int64_t on_face[2] = {0, 0};  // owned nodes on the bottom and top faces
  for (int n = 0; n < l.owned; ++n)
    on_face[0] += (l.faces[n] & kZmin) != 0, on_face[1] += (l.faces[n] & kZmax) != 0;
  if (const std::string problem = empty_face_problem(sum_over_ranks(l.comm, on_face[0]),
                                                     sum_over_ranks(l.comm, on_face[1]));
      !problem.empty())
    throw InputError(problem);
  const PieceFinder finder(l);
  std::vector<char> out = finder.underconnected();
  const std::vector<std::int64_t> label = finder.labels(out);
  std::map<std::int64_t, PieceFaces> pieces = piece_faces(l, label);
  keep_loaded_pieces(pieces);
  for (int n = 0; n < l.local_nodes(); ++n)
    if (label[n] >= 0 && pieces.count(label[n]) == 0) out[n] = 1;
  for (int n = 0; n < l.local_nodes(); ++n)
    if (out[n]) l.dof_flags[n] = kFixX | kFixY | kFixZ | kPinned;
  anchor_pieces(l, label, pieces);
  flags_to_ghosts(l, ghost_owner);
  keep_system_bonds(l, out, report);
}

}  // namespace lem
