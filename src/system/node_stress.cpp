#include "lem/system/node_stress.hpp"

#include <cmath>
#include <stdexcept>

namespace lem {

std::vector<SymTensor> node_stresses(const DistributedLattice& lattice,
                                     const std::vector<double>& bond_tension) {
  if (lattice.node_volume.size() != static_cast<std::size_t>(lattice.local_nodes()))
    throw std::logic_error("node_stresses: the lattice carries no Voronoi volumes");
  if (bond_tension.size() != static_cast<std::size_t>(lattice.local_bonds()))
    throw std::logic_error("node_stresses: one tension per local bond expected");
  // Moments first, divided by the volumes at the end.  A rank holds every
  // bond touching an owned node, so owned sums are complete without exchange.
  std::vector<SymTensor> s(lattice.owned, SymTensor{});
  for (int b = 0; b < lattice.local_bonds(); ++b) {
    if (bond_tension[b] == 0) continue;
    const auto [p, q] = lattice.bond_ends[b];
    Point d;
    for (int a = 0; a < 3; ++a) d[a] = lattice.coords[q][a] - lattice.coords[p][a];
    const double length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    // (T l / 2) n n^T = (T / 2l) d d^T.
    const double c = 0.5 * bond_tension[b] / length;
    const SymTensor m{c * d[0] * d[0], c * d[0] * d[1], c * d[0] * d[2],
                      c * d[1] * d[1], c * d[1] * d[2], c * d[2] * d[2]};
    for (int end : {p, q})
      if (end < lattice.owned)
        for (int k = 0; k < 6; ++k) s[end][k] += m[k];
  }
  for (int n = 0; n < lattice.owned; ++n) {
    const double v = lattice.node_volume[n];
    for (double& x : s[n]) x = v > 0 ? x / v : 0.0;
  }
  return s;
}

SymTensor volume_average(const DistributedLattice& lattice,
                         const std::vector<SymTensor>& stresses) {
  SymTensor local{}, total{};
  for (int n = 0; n < lattice.owned; ++n)
    for (int k = 0; k < 6; ++k) local[k] += lattice.node_volume[n] * stresses[n][k];
  MPI_Allreduce(local.data(), total.data(), 6, MPI_DOUBLE, MPI_SUM, lattice.comm);
  for (double& x : total) x /= lattice.box.volume();
  return total;
}

}  // namespace lem
