#include "lem/lattice/inclusions.hpp"

#include "lem/base/error.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <sstream>

namespace lem {
namespace {

// Squared minimum-image distance in the periodic box.
double periodic_distance2(const Point& p, const Point& q, const Box& box) {
  double d2 = 0;
  for (int a = 0; a < 3; ++a) {
    const double L = box.length(a);
    double d = std::fabs(p[a] - q[a]);
    d = std::min(d, L - d);
    d2 += d * d;
  }
  return d2;
}

}  // namespace

bool Inclusions::contains(const Point& p) const {
  const double r2 = radius * radius;
  for (const auto& c : centres)
    if (periodic_distance2(p, c, box) <= r2) return true;
  return false;
}

double Inclusions::volume_fraction() const {
  return static_cast<double>(centres.size()) * 4.0 / 3.0 * std::numbers::pi * radius * radius *
         radius / box.volume();
}

Inclusions place_inclusions(const Box& box, const InclusionSpec& spec) {
  if (!(spec.volume_fraction > 0 && spec.volume_fraction < 1))
    throw InputError("inclusions: volume fraction must be in (0, 1)");
  const double shortest = std::min({box.length(0), box.length(1), box.length(2)});
  Inclusions inc;
  inc.box = box;
  inc.radius = spec.radius * shortest;
  if (!(spec.radius > 0) || inc.radius >= 0.5 * shortest) {
    std::ostringstream s;
    s << "inclusions: radius " << spec.radius
      << " (fraction of the smallest box side) must be in (0, 0.5)";
    throw InputError(s.str());
  }
  const double sphere = 4.0 / 3.0 * std::numbers::pi * std::pow(inc.radius, 3);
  const auto count = std::max<long>(1, std::lround(spec.volume_fraction * box.volume() / sphere));
  // Random sequential addition jams near 0.38 in 3D; stop well before.
  std::mt19937_64 rng(spec.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const long max_tries = 20000 * count;
  long tries = 0;
  const double d2 = 4.0 * inc.radius * inc.radius;
  while (static_cast<long>(inc.centres.size()) < count) {
    if (++tries > max_tries) {
      std::ostringstream s;
      s << "inclusions: could place only " << inc.centres.size() << " of " << count
        << " non-overlapping spheres for a volume fraction of " << spec.volume_fraction
        << " (random packing jams near 0.38; lower the fraction)";
      throw InputError(s.str());
    }
    Point c;
    for (int a = 0; a < 3; ++a) c[a] = box.lo[a] + unit(rng) * box.length(a);
    bool free = true;
    for (const auto& o : inc.centres)
      if (periodic_distance2(c, o, box) < d2) {
        free = false;
        break;
      }
    if (free) inc.centres.push_back(c);
  }
  return inc;
}

namespace {
std::vector<char> nodes_inside(const Lattice& lattice, const Inclusions& inclusions) {
  std::vector<char> inside(lattice.node_count());
  for (std::size_t n = 0; n < lattice.node_count(); ++n)
    inside[n] = inclusions.contains(lattice.nodes[n]) ? 1 : 0;
  return inside;
}
}  // namespace

void stiffen_inclusions(Lattice& lattice, const Inclusions& inclusions, double ratio) {
  const auto inside = nodes_inside(lattice, inclusions);
  for (std::size_t b = 0; b < lattice.bond_count(); ++b)
    if (inside[lattice.bonds[b].i] && inside[lattice.bonds[b].j]) lattice.stiffness[b] *= ratio;
}

void carve_pores(Lattice& lattice, const Inclusions& pores, bool both_ends) {
  const auto inside = nodes_inside(lattice, pores);
  std::size_t kept = 0;
  for (std::size_t b = 0; b < lattice.bond_count(); ++b) {
    const bool in_i = inside[lattice.bonds[b].i], in_j = inside[lattice.bonds[b].j];
    if (both_ends ? (in_i && in_j) : (in_i || in_j)) continue;
    lattice.bonds[kept] = lattice.bonds[b];
    lattice.stiffness[kept] = lattice.stiffness[b];
    ++kept;
  }
  lattice.bonds.resize(kept);
  lattice.stiffness.resize(kept);
}

double node_fraction_inside(const Lattice& lattice, const Inclusions& inclusions) {
  const auto inside = nodes_inside(lattice, inclusions);
  return static_cast<double>(std::count(inside.begin(), inside.end(), 1)) /
         static_cast<double>(lattice.node_count());
}

}  // namespace lem
