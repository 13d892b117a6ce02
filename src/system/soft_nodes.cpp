// The soft directions of single nodes (lem/system/soft_nodes.hpp), read
// from each owned node's own 3x3 block of intact bonds.
#include "lem/system/soft_nodes.hpp"

#include "bond_operator.hpp"

#include "lem/system/tension.hpp"

#include <cmath>
#include <cstdint>

namespace lem {
namespace {

constexpr double kMechanism = 1e-6;

// Eigenvalues and unit eigenvectors (columns of v, v[3 * row + column]) of a
// symmetric 3x3 matrix a, by cyclic Jacobi rotations (a is overwritten).
void symmetric_eigen3(double a[9], double values[3], double v[9]) {
  for (int i = 0; i < 9; ++i) v[i] = (i % 4 == 0) ? 1.0 : 0.0;
  for (int sweep = 0; sweep < 50; ++sweep) {
    const double off = a[1] * a[1] + a[2] * a[2] + a[5] * a[5];
    const double diag = a[0] * a[0] + a[4] * a[4] + a[8] * a[8];
    if (off <= 1e-30 * diag) break;
    for (int p = 0; p < 2; ++p)
      for (int q = p + 1; q < 3; ++q) {
        const double apq = a[3 * p + q];
        if (apq == 0.0) continue;
        const double theta = (a[3 * q + q] - a[3 * p + p]) / (2.0 * apq);
        const double t =
            (theta >= 0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1));
        const double c = 1.0 / std::sqrt(t * t + 1), s = t * c;
        for (int k = 0; k < 3; ++k) {  // a <- a J (columns p, q)
          const double akp = a[3 * k + p], akq = a[3 * k + q];
          a[3 * k + p] = c * akp - s * akq;
          a[3 * k + q] = s * akp + c * akq;
        }
        for (int k = 0; k < 3; ++k) {  // a <- J^T a (rows p, q)
          const double apk = a[3 * p + k], aqk = a[3 * q + k];
          a[3 * p + k] = c * apk - s * aqk;
          a[3 * q + k] = s * apk + c * aqk;
        }
        for (int k = 0; k < 3; ++k) {  // v <- v J
          const double vkp = v[3 * k + p], vkq = v[3 * k + q];
          v[3 * k + p] = c * vkp - s * vkq;
          v[3 * k + q] = s * vkp + c * vkq;
        }
      }
  }
  for (int i = 0; i < 3; ++i) values[i] = a[4 * i];
}

}  // namespace

std::vector<SoftDirection> find_soft_directions(const DistributedLattice& l, double ground,
                                                double threshold) {
  // Each owned node's block sum_b k_b n_b n_b^T over its intact bonds (every
  // bond of an owned node is local).
  std::vector<std::array<double, 9>> blocks(l.owned, std::array<double, 9>{});
  for (int b = 0; b < l.local_bonds(); ++b) {
    const double k = l.bond_stiffness[b];
    if (!(k > 0)) continue;
    double n[3];
    bond_direction(l, b, n);
    for (const int node : l.bond_ends[b]) {
      if (node >= l.owned) continue;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) blocks[node][3 * i + j] += k * n[i] * n[j];
    }
  }
  std::vector<SoftDirection> soft;
  for (int node = 0; node < l.owned; ++node) {
    const std::uint8_t flags = l.dof_flags[node];
    double scale[3], s[9], mu[3], y[9];
    bool any_free = false;
    for (int i = 0; i < 3; ++i) {
      const bool fixed = is_fixed(flags, i);
      any_free = any_free || !fixed;
      const double d = blocks[node][4 * i] + ground;
      scale[i] = (fixed || !(d > 0)) ? 0.0 : 1.0 / std::sqrt(d);
    }
    if (!any_free) continue;
    // D^-1/2 B D^-1/2 on the free dofs; a fixed dof (or one without
    // stiffness) keeps 1 on its diagonal (never soft) and no coupling.
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        s[3 * i + j] = scale[i] * (blocks[node][3 * i + j] + (i == j ? ground : 0.0)) * scale[j];
    for (int i = 0; i < 3; ++i)
      if (scale[i] == 0.0) s[4 * i] = 1.0;
    symmetric_eigen3(s, mu, y);
    for (int c = 0; c < 3; ++c) {
      // Below kMechanism the direction is held by the ground spring alone (a
      // node left with one or two bonds): the load does not move it and CG
      // leaves it alone; a coarse unknown of that stiffness would only
      // carry rounding into the field.
      if (!(mu[c] < threshold) || mu[c] < kMechanism) continue;
      SoftDirection d;
      d.node = node;
      double norm2 = 0;
      for (int i = 0; i < 3; ++i) {
        d.vector[i] = scale[i] * y[3 * i + c];
        norm2 += d.vector[i] * d.vector[i];
      }
      if (!(norm2 > 0)) continue;
      for (double& x : d.vector) x /= std::sqrt(norm2);
      soft.push_back(d);
    }
  }
  return soft;
}

}  // namespace lem
