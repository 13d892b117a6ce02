// Cell-list search of close pairs in a periodic cubic box (packing stage,
// private header).  Cost is linear in the particle count: each particle is
// compared only with those of its own and the 26 neighbouring cells, each
// pair once (half stencil).
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

namespace lem::packing_detail {

/// Minimum-image displacement along one axis, valid when positions are
/// wrapped into [0, L) up to a drift much smaller than L/2.
inline double min_image(double d, double L, double half) {
  if (d > half) return d - L;
  if (d < -half) return d + L;
  return d;
}

/// Call visit(i, j) once for every unordered pair whose centre distance is
/// below r[i] + r[j] + extra (minimum image).  `x` holds 3n coordinates
/// wrapped into [0, L); requires 2 max(r) + extra < L / 2 so that a pair has
/// at most one close image.  The visiting order depends only on the input.
template <class Visit>
void for_each_close_pair(const std::vector<double>& x, const std::vector<double>& r, double L,
                         double rmax, double extra, Visit&& visit) {
  const std::int64_t n = static_cast<std::int64_t>(r.size());
  const double half = 0.5 * L;
  const double reach = 2.0 * rmax + extra;
  auto test = [&](std::int64_t i, std::int64_t j) {
    const double dx = min_image(x[3 * j] - x[3 * i], L, half);
    const double dy = min_image(x[3 * j + 1] - x[3 * i + 1], L, half);
    const double dz = min_image(x[3 * j + 2] - x[3 * i + 2], L, half);
    const double cut = r[i] + r[j] + extra;
    if (dx * dx + dy * dy + dz * dz < cut * cut) visit(i, j);
  };
  const auto m = static_cast<std::int64_t>(std::floor(L / reach));
  if (m < 3) {  // small box: every pair
    for (std::int64_t i = 0; i < n; ++i)
      for (std::int64_t j = i + 1; j < n; ++j) test(i, j);
    return;
  }
  // Counting sort of the particles into m^3 cells.
  const std::int64_t cells = m * m * m;
  std::vector<std::int64_t> start(cells + 1, 0), order(n), cell_of(n);
  const double scale = static_cast<double>(m) / L;
  auto axis_cell = [&](double c) {
    auto k = static_cast<std::int64_t>(c * scale);
    return k < 0 ? 0 : (k >= m ? m - 1 : k);
  };
  for (std::int64_t i = 0; i < n; ++i) {
    cell_of[i] = axis_cell(x[3 * i]) + m * (axis_cell(x[3 * i + 1]) + m * axis_cell(x[3 * i + 2]));
    ++start[cell_of[i] + 1];
  }
  for (std::int64_t c = 0; c < cells; ++c) start[c + 1] += start[c];
  {
    std::vector<std::int64_t> fill(start.begin(), start.end() - 1);
    for (std::int64_t i = 0; i < n; ++i) order[fill[cell_of[i]]++] = i;
  }
  // Half stencil: the 13 offsets that come first in (z, y, x) order are left
  // out, their pairs being found from the other cell.
  static const int stencil[13][3] = {{1, 0, 0},  {-1, 1, 0}, {0, 1, 0},  {1, 1, 0}, {-1, -1, 1},
                                     {0, -1, 1}, {1, -1, 1}, {-1, 0, 1}, {0, 0, 1}, {1, 0, 1},
                                     {-1, 1, 1}, {0, 1, 1},  {1, 1, 1}};
  auto wrap = [m](std::int64_t k) { return k < 0 ? k + m : (k >= m ? k - m : k); };
  for (std::int64_t cz = 0; cz < m; ++cz)
    for (std::int64_t cy = 0; cy < m; ++cy)
      for (std::int64_t cx = 0; cx < m; ++cx) {
        const std::int64_t c = cx + m * (cy + m * cz);
        for (std::int64_t a = start[c]; a < start[c + 1]; ++a)
          for (std::int64_t b = a + 1; b < start[c + 1]; ++b) test(order[a], order[b]);
        for (const auto& s : stencil) {
          const std::int64_t d = wrap(cx + s[0]) + m * (wrap(cy + s[1]) + m * wrap(cz + s[2]));
          for (std::int64_t a = start[c]; a < start[c + 1]; ++a)
            for (std::int64_t b = start[d]; b < start[d + 1]; ++b) test(order[a], order[b]);
        }
      }
}

}  // namespace lem::packing_detail
