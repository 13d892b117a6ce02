// Uses lem3d as a library: PETSc and MPI start-up, an FCC lattice (lattice
// module), its affine moduli, and a bond phase name (base module).  Prints
// one line; exits 1 if the values are not the closed-form ones.
#include "lem/lattice/lattice.hpp"
#include "lem/base/phase.hpp"

#include <petscsys.h>

#include <cmath>
#include <cstdio>

int main(int argc, char** argv) {
  if (PetscInitialize(&argc, &argv, nullptr, nullptr) != 0) return 1;
  const lem::Lattice fcc = lem::make_fcc_lattice({2, 2, 2}, 1.0, 1.0);
  const lem::LatticeStats stats = lem::lattice_stats(fcc);
  const lem::AffineModuli moduli = lem::affine_moduli(fcc);
  std::printf("lem3d consumer: FCC 2x2x2: %lld nodes, %lld bonds, nu_z = %.6f, phase %s\n",
              static_cast<long long>(stats.nodes), static_cast<long long>(stats.bonds),
              moduli.poisson_z, lem::phase_name(lem::Phase::pm));
  // 2x2x2 cubic cells: 63 nodes, 240 nearest-neighbour bonds; nu = 1/3 (docs/model/theory.md).
  const bool ok =
      stats.nodes == 63 && stats.bonds == 240 && std::abs(moduli.poisson_z - 1.0 / 3.0) < 1e-9;
  PetscFinalize();
  return ok ? 0 : 1;
}
