// A uniform grid of cells over a box, for finding what lies near a point:
// cells are at least `min_side` wide, so everything within min_side of a
// point lies in the 3 x 3 x 3 cells around the point's own.  Positions
// outside the box count in the nearest cell.  The grid only numbers cells;
// its users keep their own per-cell storage (lists, linked lists).
#pragma once

#include "lem/base/geometry.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

namespace lem {

class CellGrid {
 public:
  /// min_side > 0.
  CellGrid(const Box& box, double min_side) : lo_(box.lo) {
    for (int a = 0; a < 3; ++a) {
      const double length = box.length(a);
      // At least one cell (also for min_side = infinity); the upper bound
      // keeps the count defined for a min_side of (almost) zero.
      n_[a] = static_cast<int>(std::clamp(std::floor(length / min_side), 1.0, 1024.0));
      per_length_[a] = length > 0 ? n_[a] / length : 0.0;
    }
  }

  std::size_t cell_count() const { return static_cast<std::size_t>(n_[0]) * n_[1] * n_[2]; }
  /// Cells along each axis.
  const std::array<int, 3>& counts() const { return n_; }

  /// The cell holding `p`.
  std::size_t cell_of(const Point& p) const {
    const auto c = coordinates(p);
    return index(c[0], c[1], c[2]);
  }

  /// Calls visit(cell) for the cells within one cell of `p`'s, until visit
  /// returns false; returns false if it was stopped.
  template <class Visit>
  bool for_each_cell_near(const Point& p, Visit&& visit) const {
    const auto c = coordinates(p);
    for (int i = std::max(0, c[0] - 1); i <= std::min(n_[0] - 1, c[0] + 1); ++i)
      for (int j = std::max(0, c[1] - 1); j <= std::min(n_[1] - 1, c[1] + 1); ++j)
        for (int k = std::max(0, c[2] - 1); k <= std::min(n_[2] - 1, c[2] + 1); ++k)
          if (!visit(index(i, j, k))) return false;
    return true;
  }

  /// Calls visit(cell) for every cell that the box [lo, hi] touches.
  template <class Visit>
  void for_each_cell_touching(const Point& lo, const Point& hi, Visit&& visit) const {
    const auto c0 = coordinates(lo), c1 = coordinates(hi);
    for (int i = c0[0]; i <= c1[0]; ++i)
      for (int j = c0[1]; j <= c1[1]; ++j)
        for (int k = c0[2]; k <= c1[2]; ++k) visit(index(i, j, k));
  }

  /// The cell holding `p`, as (i, j, k); its index is index(i, j, k).
  std::array<int, 3> coordinates(const Point& p) const {
    std::array<int, 3> c{};
    for (int a = 0; a < 3; ++a)
      c[a] = static_cast<int>(std::clamp(std::floor((p[a] - lo_[a]) * per_length_[a]), 0.0,
                                         static_cast<double>(n_[a] - 1)));
    return c;
  }
  std::size_t index(int i, int j, int k) const {
    return (static_cast<std::size_t>(i) * n_[1] + j) * n_[2] + k;
  }

 private:
  Point lo_;
  std::array<int, 3> n_{1, 1, 1};
  std::array<double, 3> per_length_{0.0, 0.0, 0.0};
};

}  // namespace lem
