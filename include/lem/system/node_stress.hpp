// Node stresses of a solved lattice (paper eq. 1 and appendix C):
//   sigma^i = (1 / |V^i|) sum_j r^ij (x) f^ij,
// r^ij from node i to the midpoint of bond ij, f^ij the bond's force on i.
// For a central spring of tension T, length l and direction n this is
// (T l / 2) n (x) n per bond end, so tension is positive.
//
// Summed with the weights |V^i|, the node stresses give the virial of the bond
// forces, which at equilibrium equals the moment of the external forces: the
// volume average of sigma_zz^i is the applied stress (reaction / area) and the
// lateral components average to zero on free faces (C.5).
#pragma once

#include "lem/system/distributed_lattice.hpp"

#include <array>
#include <vector>

namespace lem {

/// Symmetric tensor in XDMF's Tensor6 order: xx, xy, xz, yy, yz, zz.
using SymTensor = std::array<double, 6>;
enum TensorComponent { kXX = 0, kXY = 1, kXZ = 2, kYY = 3, kYZ = 4, kZZ = 5 };

/// Stress of every owned node from the tensions of the local bonds
/// (ElasticSystem::bond_tensions).  Needs the lattice's Voronoi volumes
/// (sample files carry them); nodes of zero volume get zero stress.
/// Throws std::logic_error when the lattice has no volumes.
std::vector<SymTensor> node_stresses(const DistributedLattice& lattice,
                                     const std::vector<double>& bond_tension);

/// Volume average sum_i |V^i| sigma^i / |box| over all ranks (collective).
SymTensor volume_average(const DistributedLattice& lattice, const std::vector<SymTensor>& stresses);

}  // namespace lem
