#include "sample_checks.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <utility>
#include <vector>

namespace lem {

std::string value_text(double v) {
  std::ostringstream s;
  s.precision(10);
  s << v;
  return s.str();
}

namespace {

double box_side(const Box& box) { return std::max({box.length(0), box.length(1), box.length(2)}); }

// Appended piece by piece: GCC 12 warns (-Wrestrict, a false positive) on
// "(" + std::string.
std::string point_text(const Point& p) {
  std::string text = "(";
  for (int a = 0; a < 3; ++a) {
    text += value_text(p[a]);
    text += a < 2 ? ", " : ")";
  }
  return text;
}

}  // namespace

// The values a mechanical run relies on: a NaN or a node far outside the box
// would otherwise surface far from its cause (a "disconnected" sample, a
// diverged solve) or not at all (a wrong stress).
std::string first_box_problem(const Box& box) {
  for (int a = 0; a < 3; ++a)
    if (!std::isfinite(box.lo[a]) || !std::isfinite(box.hi[a]) || !(box.lo[a] < box.hi[a]))
      return ("attributes box_lo " + point_text(box.lo) + " and box_hi " + point_text(box.hi) +
              " do not describe a box");
  return {};
}

std::string first_node_problem(const Box& box, const std::vector<Point>& nodes,
                               const std::vector<double>& volume, std::int64_t first_row) {
  // Nodes lie on the faces up to the rounding of whoever wrote them.
  const double slack = 1e-9 * box_side(box);
  for (std::size_t i = 0; i < nodes.size(); ++i)
    for (int a = 0; a < 3; ++a) {
      const std::string row = std::to_string(first_row + static_cast<std::int64_t>(i));
      if (!std::isfinite(nodes[i][a]))
        return ("/nodes/coordinates row " + row + " = " + point_text(nodes[i]) + " is not finite");
      if (nodes[i][a] < box.lo[a] - slack || nodes[i][a] > box.hi[a] + slack)
        return ("/nodes/coordinates row " + row + " = " + point_text(nodes[i]) +
                " lies outside the box " + point_text(box.lo) + " - " + point_text(box.hi) +
                " (attributes box_lo, box_hi)");
    }
  for (std::size_t i = 0; i < volume.size(); ++i)
    if (!(std::isfinite(volume[i]) && volume[i] > 0))
      return ("/nodes/volume row " + std::to_string(first_row + static_cast<std::int64_t>(i)) +
              " = " + value_text(volume[i]) + " is not a finite positive volume");
  return {};
}

std::string volume_sum_problem(const Box& box, double volume) {
  // Clipped Voronoi cells tile the box.
  const double box_volume = box.volume();
  if (std::fabs(volume - box_volume) > 1e-6 * box_volume)
    return ("/nodes/volume sums to " + value_text(volume) + ", not to the volume of the box, " +
            value_text(box_volume));
  return {};
}

std::string zero_length_problem(const Box& box, std::int64_t row, std::int64_t i, std::int64_t j,
                                const Point& p, const Point& q) {
  const double length = std::sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                                  (p[2] - q[2]) * (p[2] - q[2]));
  if (length > 1e-12 * box_side(box)) return {};
  return ("/bonds/connectivity row " + std::to_string(row) + " joins nodes " + std::to_string(i) +
          " and " + std::to_string(j) + ", which coincide at " + point_text(p) +
          " (a bond of zero length)");
}

std::string first_description_problem(const CementedSample& s) {
  for (std::size_t k = 0; k < s.particles.size(); ++k) {
    const Point& c = s.particles[k].centre;
    if (!std::isfinite(c[0]) || !std::isfinite(c[1]) || !std::isfinite(c[2]))
      return ("/particles/centres row " + std::to_string(k) + " = " + point_text(c) +
              " is not finite");
  }
  for (std::size_t k = 0; k < s.bridges.size(); ++k)
    if (!(std::isfinite(s.bridges[k].lambda) && s.bridges[k].lambda > 0))
      return ("/bridges/lambda row " + std::to_string(k) + " = " + value_text(s.bridges[k].lambda) +
              " is not a finite positive ratio");
  return {};
}

std::string first_geometry_problem(const CementedSample& s) {
  const Box& box = s.lattice.box;
  std::string problem = first_box_problem(box);
  if (problem.empty()) problem = first_node_problem(box, s.lattice.nodes, s.node_volume, 0);
  if (!problem.empty()) return problem;
  double volume = 0;
  for (const double v : s.node_volume) volume += v;
  if (!s.lattice.nodes.empty() && !(problem = volume_sum_problem(box, volume)).empty())
    return problem;

  // Bonds: ends already checked to be 0 <= i < j < N.
  const auto& nodes = s.lattice.nodes;
  const auto& bonds = s.lattice.bonds;
  for (std::size_t b = 0; b < bonds.size(); ++b) {
    problem = zero_length_problem(box, static_cast<std::int64_t>(b), bonds[b].i, bonds[b].j,
                                  nodes[bonds[b].i], nodes[bonds[b].j]);
    if (!problem.empty()) return problem;
  }
  // The first row that repeats an earlier one.
  std::vector<std::pair<std::uint64_t, std::size_t>> keys(bonds.size());
  for (std::size_t b = 0; b < bonds.size(); ++b)
    keys[b] = {(static_cast<std::uint64_t>(bonds[b].i) << 32) |
                   static_cast<std::uint32_t>(bonds[b].j),
               b};
  std::sort(keys.begin(), keys.end());
  std::size_t repeat = bonds.size(), original = 0;
  for (std::size_t k = 1, start = 0; k < keys.size(); ++k) {
    if (keys[k].first != keys[k - 1].first) {
      start = k;  // a new pair; keys[start] is its first row
    } else if (keys[k].second < repeat) {
      repeat = keys[k].second;
      original = keys[start].second;
    }
  }
  if (repeat < bonds.size())
    return repeated_bond_problem(static_cast<std::int64_t>(repeat),
                                 static_cast<std::int64_t>(original), bonds[repeat].i,
                                 bonds[repeat].j);
  return first_description_problem(s);
}

std::string repeated_bond_problem(std::int64_t row, std::int64_t original, std::int64_t i,
                                  std::int64_t j) {
  return ("/bonds/connectivity row " + std::to_string(row) + " repeats row " +
          std::to_string(original) + " (nodes " + std::to_string(i) + " and " + std::to_string(j) +
          ")");
}

}  // namespace lem
