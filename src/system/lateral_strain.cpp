#include "lem/system/lateral_strain.hpp"

#include "lem/system/tension.hpp"

#include <mpi.h>

#include <cmath>

namespace lem {
namespace {

// Sums over the free nodes of one face: count, in-face coordinates t1, t2
// (relative to the box centre), the normal displacement u, and the products
// t1 t1, t1 t2, t2 t2, t1 u, t2 u.
enum Sum { kCount, kT1, kT2, kU, kT11, kT12, kT22, kT1U, kT2U, kSums };

// Strain along `axis` from the sums of its low and high faces.
double fitted_strain(const double* lo, const double* hi, double length) {
  if (lo[kCount] == 0 || hi[kCount] == 0) return 0;
  // Covariances within each face, pooled over the two faces.
  auto pooled = [&](Sum ab, Sum a, Sum b) {
    return (lo[ab] - lo[a] * lo[b] / lo[kCount]) + (hi[ab] - hi[a] * hi[b] / hi[kCount]);
  };
  const double c11 = pooled(kT11, kT1, kT1), c12 = pooled(kT12, kT1, kT2),
               c22 = pooled(kT22, kT2, kT2), c1u = pooled(kT1U, kT1, kU),
               c2u = pooled(kT2U, kT2, kU);
  // Slopes of u along the faces; a direction in which the nodes do not
  // spread (a degenerate face) gets none.
  double h1 = 0, h2 = 0;
  const double det = c11 * c22 - c12 * c12;
  if (c11 > 0 && c22 > 0 && det > 1e-12 * c11 * c22) {
    h1 = (c22 * c1u - c12 * c2u) / det;
    h2 = (c11 * c2u - c12 * c1u) / det;
  } else if (c11 > 0) {
    h1 = c1u / c11;
  } else if (c22 > 0) {
    h2 = c2u / c22;
  }
  auto level = [&](const double* s) {  // mean u taken to t = 0
    return (s[kU] - h1 * s[kT1] - h2 * s[kT2]) / s[kCount];
  };
  return (level(hi) - level(lo)) / length;
}

}  // namespace

LateralStrain lateral_strains(const DistributedLattice& l, const double* u) {
  // sums[axis][side][Sum], axis 0: x faces (normal u_x, in-face y, z),
  // axis 1: y faces (normal u_y, in-face x, z).
  double sums[2][2][kSums] = {};
  const std::uint8_t bits[2][2] = {{kXmin, kXmax}, {kYmin, kYmax}};
  const int in_face[2][2] = {{1, 2}, {0, 2}};
  Point centre;
  for (int a = 0; a < 3; ++a) centre[a] = 0.5 * (l.box.lo[a] + l.box.hi[a]);
  for (int n = 0; n < l.owned; ++n) {
    if (l.dof_flags[n] & kPinned) continue;
    for (int axis = 0; axis < 2; ++axis)
      for (int side = 0; side < 2; ++side) {
        if (!(l.faces[n] & bits[axis][side])) continue;
        const double t1 = l.coords[n][in_face[axis][0]] - centre[in_face[axis][0]];
        const double t2 = l.coords[n][in_face[axis][1]] - centre[in_face[axis][1]];
        const double un = u[3 * n + axis];
        double* s = sums[axis][side];
        s[kCount] += 1;
        s[kT1] += t1;
        s[kT2] += t2;
        s[kU] += un;
        s[kT11] += t1 * t1;
        s[kT12] += t1 * t2;
        s[kT22] += t2 * t2;
        s[kT1U] += t1 * un;
        s[kT2U] += t2 * un;
      }
  }
  double totals[2][2][kSums];
  MPI_Allreduce(&sums[0][0][0], &totals[0][0][0], 4 * kSums, MPI_DOUBLE, MPI_SUM, l.comm);
  LateralStrain e;
  e.xx = fitted_strain(totals[0][0], totals[0][1], l.box.length(0));
  e.yy = fitted_strain(totals[1][0], totals[1][1], l.box.length(1));
  return e;
}

}  // namespace lem
