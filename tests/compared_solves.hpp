// Helpers of the MPI tests that solve one lattice two ways and compare the
// fields: the lattice distributed as a tension test, and the largest
// difference of bond tensions between two solves.
#pragma once

#include "lem/setup/setup.hpp"
#include "lem/system/elastic_system.hpp"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>

/// `lattice` set up for a tension test on `comm` (read on rank 0).
inline lem::DistributedLattice distributed(MPI_Comm comm, const lem::Lattice& lattice) {
  lem::SetupReport report;
  return lem::setup_tension_lattice(
      comm,
      [&](lem::SampleInfo& info) {
        info.stats = lem::lattice_stats(lattice);
        info.affine = lem::affine_moduli(lattice);
        return lattice;
      },
      report);
}

/// Largest difference of bond tensions of two solves of the same lattice
/// (bonds matched by global id), relative to the largest tension, over all
/// ranks of `la`'s communicator.  Unlike displacements, tensions are
/// defined where bonds were broken and nodes left loose.
inline double worst_tension_difference(const lem::DistributedLattice& la,
                                       const lem::ElasticSystem& a,
                                       const lem::DistributedLattice& lb,
                                       const lem::ElasticSystem& b) {
  std::map<std::int64_t, double> by_id;
  const auto tb = b.bond_tensions();
  for (int i = 0; i < lb.local_bonds(); ++i) by_id[lb.bond_id[i]] = tb[i];
  const auto ta = a.bond_tensions();
  double worst[2] = {0, 0};  // difference, largest tension
  for (int i = 0; i < la.local_bonds(); ++i) {
    worst[0] = std::max(worst[0], std::fabs(ta[i] - by_id.at(la.bond_id[i])));
    worst[1] = std::max(worst[1], std::fabs(ta[i]));
  }
  MPI_Allreduce(MPI_IN_PLACE, worst, 2, MPI_DOUBLE, MPI_MAX, la.comm);
  return worst[0] / worst[1];
}
