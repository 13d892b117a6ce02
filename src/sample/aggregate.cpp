#include "lem/sample/aggregate.hpp"

#include "lem/base/cell_grid.hpp"
#include "lem/base/error.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

namespace lem {
namespace {

double distance(const Point& a, const Point& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                   (a[2] - b[2]) * (a[2] - b[2]));
}

// Bridge lambda whose volume outside its two particles is `volume`
// (bisection: the volume grows monotonically with lambda).  Returns
// max_lambda (saturated) if even that is too small.
double lambda_for_volume(const Sphere& a, const Sphere& b, double volume, double max_lambda) {
  if (bridge_volume(a, b, max_lambda) <= volume) return max_lambda;
  double lo = 0, hi = max_lambda;
  for (int it = 0; it < 50; ++it) {
    const double mid = 0.5 * (lo + hi);
    (bridge_volume(a, b, mid) < volume ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

std::vector<Bridge> eligible_pairs(const std::vector<Sphere>& particles, double max_gap) {
  std::vector<Bridge> pairs;
  if (particles.empty()) return pairs;
  double rmax = 0;
  Point lo = particles[0].centre, hi = lo;
  for (const auto& s : particles) {
    rmax = std::max(rmax, s.radius);
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], s.centre[a]);
      hi[a] = std::max(hi[a], s.centre[a]);
    }
  }
  // Cell side >= the largest centre distance of an eligible pair.
  const CellGrid grid(Box{lo, hi}, 2 * rmax + max_gap);
  std::vector<std::vector<std::int32_t>> cells(grid.cell_count());
  for (std::size_t k = 0; k < particles.size(); ++k)
    cells[grid.cell_of(particles[k].centre)].push_back(static_cast<std::int32_t>(k));
  for (std::size_t k = 0; k < particles.size(); ++k) {
    const Point& c = particles[k].centre;
    grid.for_each_cell_near(c, [&](std::size_t cell) {
      for (std::int32_t m : cells[cell]) {
        if (m <= static_cast<std::int32_t>(k)) continue;
        const double gap =
            distance(c, particles[m].centre) - particles[k].radius - particles[m].radius;
        if (gap <= max_gap) pairs.push_back(Bridge{static_cast<std::int32_t>(k), m, 0.0});
      }
      return true;
    });
  }
  std::sort(pairs.begin(), pairs.end(), [](const Bridge& x, const Bridge& y) {
    return x.i < y.i || (x.i == y.i && x.j < y.j);
  });
  return pairs;
}

double bridge_volume(const Sphere& a, const Sphere& b, double lambda) {
  // Cross-sections normal to the axis are concentric disks: the frustum's of
  // radius R(s) minus the larger particle cap.  R(s)^2 and the caps' squared
  // radii are quadratics in s, so the area is piecewise quadratic: split the
  // axis at every kink and integrate each piece exactly with Simpson's rule.
  const double length = distance(a.centre, b.centre);
  const double ra = a.radius, rb = b.radius, k = (rb - ra) / length;
  auto area = [&](double s) {
    const double R = lambda * (ra + k * s);
    const double t = length - s;
    const double cap2 = std::max({s < ra ? ra * ra - s * s : 0.0, t < rb ? rb * rb - t * t : 0.0});
    return std::max(0.0, R * R - cap2);
  };
  std::vector<double> cuts{0.0, length, ra, length - rb,
                           (ra * ra - rb * rb + length * length) / (2 * length)};
  // Roots of c2 s^2 + c1 s + c0 = 0 (where the frustum meets a cap).
  auto add_roots = [&](double c2, double c1, double c0, bool from_b) {
    const double disc = c1 * c1 - 4 * c2 * c0;
    if (disc < 0) return;
    for (double sign : {-1.0, 1.0}) {
      const double root = (-c1 + sign * std::sqrt(disc)) / (2 * c2);
      cuts.push_back(from_b ? length - root : root);
    }
  };
  const double l2 = lambda * lambda, c2 = l2 * k * k + 1;
  add_roots(c2, 2 * l2 * ra * k, (l2 - 1) * ra * ra, false);  // in s from centre a
  add_roots(c2, -2 * l2 * rb * k, (l2 - 1) * rb * rb, true);  // in t = length - s
  std::sort(cuts.begin(), cuts.end());
  double volume = 0;
  for (std::size_t c = 0; c + 1 < cuts.size(); ++c) {
    const double s0 = std::max(0.0, cuts[c]), s1 = std::min(length, cuts[c + 1]);
    if (s1 <= s0) continue;
    volume += (s1 - s0) / 6 * (area(s0) + 4 * area(0.5 * (s0 + s1)) + area(s1));
  }
  return std::numbers::pi * volume;
}

namespace {

// Cells of at least a particle diameter (one cell without particles).
double geometry_cell_side(const std::vector<Sphere>& particles) {
  double rmax = 0;
  for (const auto& s : particles) rmax = std::max(rmax, s.radius);
  return rmax > 0 ? 2 * rmax : std::numeric_limits<double>::infinity();
}

}  // namespace

AggregateGeometry::AggregateGeometry(const Box& box, std::vector<Sphere> particles,
                                     std::vector<Bridge> bridges)
    : particles_(std::move(particles)),
      bridges_(std::move(bridges)),
      grid_(box, geometry_cell_side(particles_)) {
  particle_cells_.assign(grid_.cell_count(), {});
  bridge_cells_.assign(grid_.cell_count(), {});
  // Register an item in every cell its bounding box [lo, hi] touches.
  auto insert = [&](std::vector<std::vector<std::int32_t>>& cells, const Point& lo, const Point& hi,
                    std::int32_t item) {
    grid_.for_each_cell_touching(lo, hi, [&](std::size_t cell) { cells[cell].push_back(item); });
  };
  for (std::size_t k = 0; k < particles_.size(); ++k) {
    const auto& s = particles_[k];
    Point lo, hi;
    for (int a = 0; a < 3; ++a) lo[a] = s.centre[a] - s.radius, hi[a] = s.centre[a] + s.radius;
    insert(particle_cells_, lo, hi, static_cast<std::int32_t>(k));
  }
  for (std::size_t k = 0; k < bridges_.size(); ++k) {
    const auto& b = bridges_[k];
    const Sphere& p = particles_[b.i];
    const Sphere& q = particles_[b.j];
    const double reach = b.lambda * std::max(p.radius, q.radius);
    Point lo, hi;
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(p.centre[a], q.centre[a]) - reach;
      hi[a] = std::max(p.centre[a], q.centre[a]) + reach;
    }
    insert(bridge_cells_, lo, hi, static_cast<std::int32_t>(k));
  }
}

const std::vector<std::int32_t>& AggregateGeometry::cell_items(const Point& x, bool bridges) const {
  const std::size_t cell = grid_.cell_of(x);
  return bridges ? bridge_cells_[cell] : particle_cells_[cell];
}

std::int32_t AggregateGeometry::particle_at(const Point& x) const {
  for (std::int32_t k : cell_items(x, false)) {
    const auto& s = particles_[k];
    const double d2 = (x[0] - s.centre[0]) * (x[0] - s.centre[0]) +
                      (x[1] - s.centre[1]) * (x[1] - s.centre[1]) +
                      (x[2] - s.centre[2]) * (x[2] - s.centre[2]);
    if (d2 <= s.radius * s.radius) return k;
  }
  return -1;
}

bool AggregateGeometry::in_bridge(std::int32_t k, const Point& x) const {
  const auto& b = bridges_[k];
  const Sphere& p = particles_[b.i];
  const Sphere& q = particles_[b.j];
  double axis[3], rel[3], length2 = 0, s = 0, r2 = 0;
  for (int a = 0; a < 3; ++a) {
    axis[a] = q.centre[a] - p.centre[a];
    rel[a] = x[a] - p.centre[a];
    length2 += axis[a] * axis[a];
    s += rel[a] * axis[a];
    r2 += rel[a] * rel[a];
  }
  const double t = s / length2;  // axial position, 0 at p and 1 at q
  if (t < 0 || t > 1) return false;
  const double radius = b.lambda * (p.radius + (q.radius - p.radius) * t);
  return r2 - t * s <= radius * radius;  // r2 - t*s = squared distance to the axis
}

bool AggregateGeometry::matrix_at(const Point& x) const {
  for (std::int32_t k : cell_items(x, true))
    if (in_bridge(k, x)) return true;
  return false;
}

std::vector<std::int32_t> AggregateGeometry::bridges_at(const Point& x) const {
  std::vector<std::int32_t> found;
  for (std::int32_t k : cell_items(x, true))
    if (in_bridge(k, x)) found.push_back(k);
  return found;
}

NodePhases AggregateGeometry::classify(const std::vector<Point>& nodes) const {
  NodePhases np;
  np.particle.resize(nodes.size());
  np.matrix.resize(nodes.size());
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    np.particle[n] = particle_at(nodes[n]);
    np.matrix[n] = np.particle[n] < 0 && matrix_at(nodes[n]) ? 1 : 0;
  }
  return np;
}

const char* void_rule_name(VoidRule rule) {
  return rule == VoidRule::both_ends ? "both_ends" : "any_end";
}

Phase bond_phase(const NodePhases& nodes, std::int32_t a, std::int32_t b, VoidRule rule) {
  return bond_phase(nodes.particle[a], nodes.matrix[a] != 0, nodes.particle[b],
                    nodes.matrix[b] != 0, rule);
}

Phase bond_phase(std::int32_t pa, bool ma, std::int32_t pb, bool mb, VoidRule rule) {
  const bool va = pa < 0 && !ma, vb = pb < 0 && !mb;
  // both_ends: a bond with one end in a pore belongs to its other end.
  if (rule == VoidRule::both_ends && va != vb) return (va ? pb : pa) >= 0 ? Phase::p : Phase::m;
  if (pa >= 0 && pb >= 0) return pa == pb ? Phase::p : Phase::pp;
  if ((pa >= 0 && mb) || (pb >= 0 && ma)) return Phase::pm;
  if (ma && mb) return Phase::m;
  return Phase::v;
}

MatrixCalibration calibrate_bridges(
    const Box& box, const std::vector<Sphere>& particles, const BridgeSpec& spec,
    const std::function<double(const std::vector<Bridge>&)>& measure, double tolerance) {
  if (!(spec.matrix_fraction > 0 && spec.matrix_fraction < 1))
    throw InputError("matrix fraction must be in (0, 1), got " +
                     std::to_string(spec.matrix_fraction));
  MatrixCalibration cal;
  std::vector<Bridge> pairs = eligible_pairs(particles, spec.max_gap);
  if (pairs.empty())
    throw InputError("no particle pair has a gap <= " + std::to_string(spec.max_gap) +
                     ": no matrix bridge can be built");
  std::vector<double> weight(pairs.size());
  double total_weight = 0;
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const double di = 2 * particles[pairs[k].i].radius, dj = 2 * particles[pairs[k].j].radius;
    weight[k] = 0.5 * (di * di + dj * dj);
    total_weight += weight[k];
  }
  const double requested = spec.matrix_fraction * box.volume();
  // Bridges for a factor f on the requested total volume.
  auto sized = [&](double f) {
    std::vector<Bridge> b = pairs;
    for (std::size_t k = 0; k < b.size(); ++k)
      b[k].lambda = lambda_for_volume(particles[b[k].i], particles[b[k].j],
                                      f * requested * weight[k] / total_weight, spec.max_lambda);
    return b;
  };
  const double target = spec.matrix_fraction;
  // Widest bridges: the most the pore space can hold with this geometry.
  std::vector<Bridge> widest = pairs;
  for (auto& b : widest) b.lambda = spec.max_lambda;
  const double most = measure(widest);
  if (most < target) {
    std::ostringstream s;
    s << "matrix fraction " << target << " exceeds what the pore space can hold with bridges "
      << "between pairs closer than " << spec.max_gap << ": at most " << most;
    throw InputError(s.str());
  }
  // Bracket then bisect on log f (rho^m grows monotonically with f).
  double lo = 0, hi = 1, rho_hi = measure(sized(hi));
  cal.iterations = 1;
  while (rho_hi < target) {
    lo = hi;
    hi *= 2;
    rho_hi = measure(sized(hi));
    ++cal.iterations;
  }
  double f = hi, rho = rho_hi;
  while (std::fabs(rho - target) > tolerance * target && cal.iterations < 60) {
    f = lo > 0 ? std::sqrt(lo * hi) : 0.5 * hi;
    rho = measure(sized(f));
    ++cal.iterations;
    (rho < target ? lo : hi) = f;
  }
  cal.bridges = sized(f);
  cal.share_factor = f;
  cal.matrix_fraction = rho;
  return cal;
}

}  // namespace lem
