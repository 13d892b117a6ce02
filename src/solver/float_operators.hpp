// The float operators of the single-precision multigrid cycle (SingleCycle,
// single_cycle.cpp); not part of the public API.  Values are stored in
// float, products are accumulated and returned in double.
#pragma once

#include "lem/base/petsc_handle.hpp"
#include "lem/system/distributed_lattice.hpp"

#include <petscmat.h>

#include <cstdint>
#include <vector>

namespace lem {

enum class ProductMode { set, residual, add };  // y = A x, y = b - A x, y += A x

/// A parallel AIJ matrix with float values in blocks: the owned columns (x's
/// own entries) and the ghost columns (gathered by a scatter), each as block
/// rows.
struct FloatBlockMatrix {
  using Kernel = void (*)(int, const std::int32_t*, const std::int32_t*, const float*,
                          const double*, const double*, double*, double);
  int br = 1, bc = 1, row_blocks = 0;
  std::vector<std::int32_t> dptr, dcol, optr, ocol;
  std::vector<float> dval, oval;
  VecScatterHandle scatter;
  VecHandle ghosts;
  Kernel kernel = nullptr;
  double nonzeros = 0;  // global, as stored by PETSc
  double local_columns = 0;

  /// Copy `A` in blocks of want_br x want_bc (1 x 1 where they do not fit).
  void build(Mat A, int want_br, int want_bc);
  void apply(Vec x, Vec y, Vec b, ProductMode mode) const;
  double memory_bytes() const;
  double bytes_per_product(bool reads_y) const;
};

/// The fine level bond by bond in float: per bond two local node indices and
/// m = sqrt(k) n (k n n^T = m m^T), the product accumulated in double.
struct FloatBondOperator {
  const DistributedLattice& lattice;
  double ground, scale;
  std::vector<std::int32_t> order;  // bonds sorted by their lower local end
  std::vector<std::int32_t> i, j;
  std::vector<float> nx, ny, nz;   // unit directions
  std::vector<float> mx, my, mz;   // sqrt(k) n, the arrays a product reads
  std::vector<std::uint8_t> free;  // per local dof
  VecHandle x_ghosted;
  mutable std::vector<double> acc;

  FloatBondOperator(const DistributedLattice& l, double g, double s);
  void read();
  void refresh();
  void apply(Vec x, Vec y, Vec b, ProductMode mode) const;
  double memory_bytes() const;
  double bytes_per_product() const;
};

}  // namespace lem
