// Least-squares straight line, used by the studies that compare trends with
// the paper's linear fits.
#pragma once

#include <cmath>
#include <cstddef>
#include <vector>

namespace lem {

struct LineFit {
  double intercept = 0, slope = 0;
  double max_residual = 0;  // largest |y - line(x)|
  double at(double x) const { return intercept + slope * x; }
};

/// y = intercept + slope x through the points (at least two, distinct x).
inline LineFit fit_line(const std::vector<double>& x, const std::vector<double>& y) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = static_cast<double>(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    sx += x[i], sy += y[i], sxx += x[i] * x[i], sxy += x[i] * y[i];
  }
  LineFit f;
  f.slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
  f.intercept = (sy - f.slope * sx) / n;
  for (std::size_t i = 0; i < x.size(); ++i)
    f.max_residual = std::max(f.max_residual, std::fabs(y[i] - f.at(x[i])));
  return f;
}

}  // namespace lem
