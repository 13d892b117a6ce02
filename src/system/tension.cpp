#include "lem/system/tension.hpp"

#include "lem/base/error.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <deque>

namespace lem {
namespace {

int free_dofs(std::uint8_t flags) {
  return 3 - std::popcount(static_cast<unsigned>(flags & (kFixX | kFixY | kFixZ)));
}

// Node -> incident bond lists (CSR).
struct Incidence {
  std::vector<std::int64_t> start;
  std::vector<std::int32_t> bonds;
};

Incidence incidence(const Lattice& lattice) {
  Incidence inc;
  inc.start.assign(lattice.node_count() + 1, 0);
  for (const auto& b : lattice.bonds) {
    ++inc.start[b.i + 1];
    ++inc.start[b.j + 1];
  }
  for (std::size_t n = 0; n < lattice.node_count(); ++n) inc.start[n + 1] += inc.start[n];
  inc.bonds.resize(static_cast<std::size_t>(inc.start.back()));
  std::vector<std::int64_t> fill(inc.start.begin(), inc.start.end() - 1);
  for (std::size_t b = 0; b < lattice.bond_count(); ++b) {
    inc.bonds[fill[lattice.bonds[b].i]++] = static_cast<std::int32_t>(b);
    inc.bonds[fill[lattice.bonds[b].j]++] = static_cast<std::int32_t>(b);
  }
  return inc;
}

// The nodes joined to `seed` by active bonds, marked `label` in `piece`.
std::vector<std::size_t> collect_piece(const Lattice& lattice, const Incidence& inc,
                                       const TensionConstraints& tc, std::size_t seed,
                                       std::int32_t label, std::vector<std::int32_t>& piece) {
  std::vector<std::size_t> members{seed};
  piece[seed] = label;
  for (std::size_t q = 0; q < members.size(); ++q) {
    const std::size_t n = members[q];
    for (auto k = inc.start[n]; k < inc.start[n + 1]; ++k) {
      const std::int32_t b = inc.bonds[k];
      if (!tc.bond_active[b]) continue;
      const auto m = static_cast<std::size_t>(static_cast<std::size_t>(lattice.bonds[b].i) == n
                                                  ? lattice.bonds[b].j
                                                  : lattice.bonds[b].i);
      if (piece[m] < 0) {
        piece[m] = label;
        members.push_back(m);
      }
    }
  }
  return members;
}

// Anchor a held piece against x/y translation and z rotation on one face:
// its node A nearest the face's centroid fixed in x and y, and the node
// farthest from A fixed across the line A-far (the component with the
// larger lever arm).
void anchor(const Lattice& lattice, const std::vector<std::size_t>& face, TensionConstraints& tc) {
  double cx = 0, cy = 0;
  for (auto n : face) {
    cx += lattice.nodes[n][0];
    cy += lattice.nodes[n][1];
  }
  cx /= static_cast<double>(face.size());
  cy /= static_cast<double>(face.size());
  auto dist2 = [&](std::size_t n, double x, double y) {
    const double dx = lattice.nodes[n][0] - x, dy = lattice.nodes[n][1] - y;
    return dx * dx + dy * dy;
  };
  const std::size_t a = *std::min_element(face.begin(), face.end(), [&](auto p, auto q) {
    return dist2(p, cx, cy) < dist2(q, cx, cy);
  });
  const double ax = lattice.nodes[a][0], ay = lattice.nodes[a][1];
  const std::size_t far = *std::max_element(face.begin(), face.end(), [&](auto p, auto q) {
    return dist2(p, ax, ay) < dist2(q, ax, ay);
  });
  tc.dof_flags[a] |= kFixX | kFixY;
  const double dx = std::fabs(lattice.nodes[far][0] - ax),
               dy = std::fabs(lattice.nodes[far][1] - ay);
  tc.dof_flags[far] |= (dx >= dy) ? kFixY : kFixX;
}

}  // namespace

TensionConstraints make_tension_constraints(const Lattice& lattice,
                                            const std::vector<std::uint8_t>& faces) {
  const std::size_t nodes = lattice.node_count();
  const auto on_face = [&](Face f) {
    return std::count_if(faces.begin(), faces.end(), [f](std::uint8_t x) { return (x & f) != 0; });
  };
  if (const std::string problem = empty_face_problem(on_face(kZmin), on_face(kZmax));
      !problem.empty())
    throw InputError(problem);
  TensionConstraints tc;
  tc.dof_flags.assign(nodes, 0);
  for (std::size_t n = 0; n < nodes; ++n) {
    if (faces[n] & kZmin) tc.dof_flags[n] = kFixZ;
    if (faces[n] & kZmax) tc.dof_flags[n] = kFixZ | kLoadedTop;
  }
  tc.bond_active.assign(lattice.bond_count(), 0);
  for (std::size_t b = 0; b < lattice.bond_count(); ++b)
    tc.bond_active[b] = lattice.stiffness[b] > 0 ? 1 : 0;

  const Incidence inc = incidence(lattice);
  std::vector<int> degree(nodes, 0);
  for (std::size_t b = 0; b < lattice.bond_count(); ++b)
    if (tc.bond_active[b]) {
      ++degree[lattice.bonds[b].i];
      ++degree[lattice.bonds[b].j];
    }
  auto other_end = [&](std::int32_t b, std::size_t n) {
    return static_cast<std::size_t>(lattice.bonds[b].i) == n ? lattice.bonds[b].j
                                                             : lattice.bonds[b].i;
  };
  std::vector<char> pinned(nodes, 0);
  auto pin = [&](std::size_t n) {
    pinned[n] = 1;
    tc.dof_flags[n] = kFixX | kFixY | kFixZ | kPinned;
  };

  // 1. A node with fewer bonds than free dofs has a zero-energy mode and its
  //    bonds carry no force at equilibrium: drop them, repeatedly.
  std::deque<std::size_t> queue;
  for (std::size_t n = 0; n < nodes; ++n)
    if (degree[n] < free_dofs(tc.dof_flags[n])) queue.push_back(n);
  while (!queue.empty()) {
    const std::size_t n = queue.front();
    queue.pop_front();
    if (pinned[n]) continue;
    pin(n);
    for (auto k = inc.start[n]; k < inc.start[n + 1]; ++k) {
      const std::int32_t b = inc.bonds[k];
      if (!tc.bond_active[b]) continue;
      tc.bond_active[b] = 0;
      ++tc.pruned_bonds;
      const std::size_t m = other_end(b, n);
      if (--degree[m] < free_dofs(tc.dof_flags[m]) && !pinned[m]) queue.push_back(m);
    }
  }

  // 2. Connected pieces.  A piece needs three z-constrained nodes to be held
  //    (fewer: it can only carry zero forces, so it is pinned); it is then
  //    anchored against x/y translation and z rotation on its bottom face
  //    (or its top face if it has no bottom node).
  std::vector<std::int32_t> piece(nodes, -1);
  std::int32_t pieces = 0;
  for (std::size_t seed = 0; seed < nodes; ++seed) {
    if (pinned[seed] || piece[seed] >= 0) continue;
    const std::vector<std::size_t> members = collect_piece(lattice, inc, tc, seed, pieces, piece);
    ++pieces;
    std::vector<std::size_t> bottom, top;
    for (auto n : members) {
      if (faces[n] & kZmin) bottom.push_back(n);
      if (faces[n] & kZmax) top.push_back(n);
    }
    if (bottom.size() + top.size() < 3) {
      for (auto n : members) {
        for (auto k = inc.start[n]; k < inc.start[n + 1]; ++k)
          if (tc.bond_active[inc.bonds[k]]) {
            tc.bond_active[inc.bonds[k]] = 0;
            ++tc.pruned_bonds;
          }
        pin(n);
      }
      continue;
    }
    if (!bottom.empty() && !top.empty()) ++tc.loaded_pieces;
    anchor(lattice, bottom.empty() ? top : bottom, tc);
  }
  for (std::size_t n = 0; n < nodes; ++n) {
    if (pinned[n]) {
      ++tc.pinned_nodes;
      continue;
    }
    if (faces[n] & kZmin) ++tc.bottom_nodes;
    if (faces[n] & kZmax) ++tc.top_nodes;
  }
  if (tc.loaded_pieces == 0)
    throw InputError("tension: no connected piece of the lattice joins the bottom face to the "
                     "top face (sample disconnected)");
  return tc;
}

}  // namespace lem
