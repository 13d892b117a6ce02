// Boundary conditions of displacement-controlled uniaxial tension (paper
// sect. 2.3): bottom nodes u_z = 0, top nodes u_z = Delta, lateral faces free.
//
// The remaining rigid motions (x, y translation, rotation about z) are removed
// with three constraints per connected piece, placed on its bottom face: they
// cannot restrain the Poisson contraction because any rigid motion is
// force-free in a linear model.  Nodes that cannot carry load (fewer bonds
// than free degrees of freedom, removed iteratively, and pieces touching no
// loaded face) are pinned: their bonds would carry zero force at equilibrium,
// so dropping them is exact and keeps the matrix non-singular.
#pragma once

#include "lem/lattice/lattice.hpp"

#include <cstdint>
#include <vector>

namespace lem {

/// Per-node degree-of-freedom flags.
enum DofFlag : std::uint8_t {
  kFixX = 1,
  kFixY = 2,
  kFixZ = 4,
  kLoadedTop = 8,  // u_z prescribed to the top displacement (else fixed values are 0)
  kPinned = 16     // carries no bond: all three displacements fixed at 0
};

/// Displacement component a (0, 1, 2) of a node with these flags is prescribed.
inline bool is_fixed(std::uint8_t flags, int component) { return flags & (1u << component); }

struct TensionConstraints {
  std::vector<std::uint8_t> dof_flags;  // per node
  std::vector<char> bond_active;        // bonds kept in the system
  std::int64_t bottom_nodes = 0, top_nodes = 0;
  std::int64_t pruned_bonds = 0;  // zero-force bonds dropped
  std::int64_t pinned_nodes = 0;
  std::int64_t loaded_pieces = 0;  // connected pieces anchored on a face
};

/// Build the constraints from the face flags; throws InputError when no piece
/// of the lattice joins the bottom face to the top face.
TensionConstraints make_tension_constraints(const Lattice& lattice,
                                            const std::vector<std::uint8_t>& faces);

}  // namespace lem
