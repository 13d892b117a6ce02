// A diagnostic of the preconditioned operator (-solver_spectrum_solves):
// at chosen solves, a second, separate preconditioned CG from the same
// initial guess keeps its Lanczos vectors, and writes the Ritz values of
// M^-1 K, the residual history and the slowest Ritz vectors to files.
//
// With z_k = M^-1 r_k and rho_k = r_k . z_k, the vectors v_k = z_k /
// sqrt(rho_k) are orthonormal in the M metric and V^T K V is the Lanczos
// tridiagonal T of CG (diagonal 1/alpha_k + beta_k/alpha_{k-1}, off-diagonal
// -sqrt(beta_{k+1})/alpha_k).  The eigenpairs (theta, y) of T give Ritz
// pairs (theta, V y) of K x = theta M x: a theta far below the bulk is a
// mode the preconditioner misses, and V y shows where it lives.  The solve
// of the run is not touched; the probe costs one more solve and keeps all
// its vectors, so it is for small samples.
#pragma once

#include "lem/system/distributed_lattice.hpp"
#include "lem/base/petsc_handle.hpp"
#include "lem/system/lanczos.hpp"

#include <petscksp.h>

#include <cstdint>
#include <string>
#include <vector>

namespace lem {

/// What one preconditioned CG run tells of the preconditioned operator.
struct RitzPairs {
  std::vector<double> history;     // |M^-1 r_k| / |M^-1 b|, from k = 0
  std::vector<double> theta;       // all Ritz values, ascending
  std::vector<VecHandle> vectors;  // the slowest Ritz vectors, M-orthonormal
};

/// Preconditioned CG on K x = b from u0 with the preconditioner `pc` (set
/// up) until |M^-1 r| <= rtol |M^-1 b| (at most 2000 iterations), keeping
/// its Lanczos vectors: the Ritz values of M^-1 K and the `vectors` slowest
/// Ritz vectors.  u0 is not changed.  Memory: one vector per iteration.
/// Collective.
RitzPairs lanczos_ritz(Mat K, PC pc, Vec b, Vec u0, double rtol, int vectors);

/// Run the probe on K u = b from `u0` with the preconditioner `pc` (set up)
/// to relative residual `rtol`, and write `<prefix>_<solve>.txt` (residual
/// history, Ritz values, checks), `<prefix>_<solve>.bin` (PETSc binary: the
/// node coordinates, then the `vectors` slowest Ritz vectors, all in the
/// layout of K) and `<prefix>_<solve>_bonds.txt` (the intact bonds as pairs
/// of global node numbers, with their stiffness).  Collective.
void probe_spectrum(const DistributedLattice& lattice, Mat K, PC pc, Vec b, Vec u0, double rtol,
                    const std::string& prefix, std::int64_t solve, int vectors);

}  // namespace lem
