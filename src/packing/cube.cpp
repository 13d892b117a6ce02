// Cubic sample cut out of a periodic packing, and the exact volume of a
// sphere clipped by a box (see packing.hpp).
#include "lem/base/error.hpp"
#include "lem/packing/packing.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

namespace lem {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Area of the part x > a of a disc of radius rho centred at the origin.
double segment_area(double rho, double a) {
  if (a >= rho) return 0.0;
  if (a <= -rho) return kPi * rho * rho;
  return rho * rho * std::acos(a / rho) - a * std::sqrt(rho * rho - a * a);
}

// Area of the part x > a, y > b of a disc of radius rho centred at the origin.
// For b >= 0 the chord at height b spans |x| < xb and the area is
// int_{max(a,-xb)}^{xb} (sqrt(rho^2 - x^2) - b) dx; for b < 0 it is the
// part x > a minus the (mirrored) part x > a, y > -b.
double quadrant_area(double rho, double a, double b) {
  if (rho <= 0.0) return 0.0;
  if (b < 0.0) return segment_area(rho, a) - quadrant_area(rho, a, -b);
  if (b >= rho) return 0.0;
  const double xb = std::sqrt(rho * rho - b * b);
  const double lo = std::max(a, -xb);
  if (lo >= xb) return 0.0;
  // Antiderivative of sqrt(rho^2 - x^2).
  auto G = [rho](double x) {
    const double s = std::sqrt(std::max(0.0, rho * rho - x * x));
    return 0.5 * (x * s + rho * rho * std::asin(std::clamp(x / rho, -1.0, 1.0)));
  };
  return G(xb) - G(lo) - b * (xb - lo);
}

// Tanh-sinh rule on [-1, 1]: nodes and weights for step h = 1/16, |t| <= 3.5
// (the weights beyond are below 1e-17).  Integrands with algebraic endpoint
// singularities such as (z - z0)^(3/2) converge to ~1e-13.
struct TanhSinh {
  std::vector<double> node, weight;
  TanhSinh() {
    const double h = 1.0 / 16.0;
    for (int k = -56; k <= 56; ++k) {
      const double t = h * k;
      const double u = 0.5 * kPi * std::sinh(t);
      const double ch = std::cosh(u);
      node.push_back(std::tanh(u));
      weight.push_back(h * 0.5 * kPi * std::cosh(t) / (ch * ch));
    }
  }
};

double integrate(double lo, double hi, double rho_r, double a, double b) {
  static const TanhSinh rule;
  const double mid = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
  double sum = 0;
  for (std::size_t k = 0; k < rule.node.size(); ++k) {
    const double z = mid + half * rule.node[k];
    const double rho = std::sqrt(std::max(0.0, rho_r * rho_r - z * z));
    sum += rule.weight[k] * quadrant_area(rho, a, b);
  }
  return sum * half;
}

// Volume of the part x > a, y > b, z > c of a ball of radius r centred at
// the origin: the disc area at height z integrated over z, split where the
// disc radius equals |a|, |b| or the corner distance (the integrand is not
// smooth there).
double orthant_volume(double r, double a, double b, double c) {
  if (a >= r || b >= r || c >= r) return 0.0;
  const double lo = std::max(c, -r);
  double cuts[8];
  int n = 0;
  cuts[n++] = lo;
  cuts[n++] = r;
  for (double t : {std::fabs(a), std::fabs(b), std::hypot(a, b)}) {
    if (t >= r) continue;
    const double z = std::sqrt(r * r - t * t);
    for (double zz : {z, -z})
      if (zz > lo && zz < r) cuts[n++] = zz;
  }
  std::sort(cuts, cuts + n);
  double v = 0;
  for (int k = 0; k + 1 < n; ++k)
    if (cuts[k + 1] > cuts[k]) v += integrate(cuts[k], cuts[k + 1], r, a, b);
  return v;
}

template <class T>
std::string str(const T& v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

double wrap_signed(double d, double L) {
  d -= L * std::floor(d / L + 0.5);  // into [-L/2, L/2)
  return d;
}

}  // namespace

double sphere_box_volume(const Point& centre, double radius, const Box& box) {
  if (!(radius > 0)) return 0.0;
  bool inside = true;
  for (int k = 0; k < 3; ++k) {
    if (centre[k] + radius <= box.lo[k] || centre[k] - radius >= box.hi[k]) return 0.0;
    inside = inside && centre[k] - radius >= box.lo[k] && centre[k] + radius <= box.hi[k];
  }
  if (inside) return 4.0 / 3.0 * kPi * radius * radius * radius;
  // The box is the intersection of three slabs lo < x < hi; each slab is
  // {x > lo} minus {x > hi}, so the volume is a signed sum of 8 orthants.
  double v = 0;
  for (int s = 0; s < 8; ++s) {
    double cut[3];
    int sign = 1;
    bool trivial_zero = false;
    for (int k = 0; k < 3; ++k) {
      const bool upper = (s >> k) & 1;
      cut[k] = (upper ? box.hi[k] : box.lo[k]) - centre[k];
      if (upper) sign = -sign;
      if (cut[k] >= radius) trivial_zero = true;
    }
    if (!trivial_zero) v += sign * orthant_volume(radius, cut[0], cut[1], cut[2]);
  }
  return std::max(0.0, v);
}

CubeSample cut_cube(const Packing& packing, std::int64_t target_count, CubeCut cut) {
  const double h = 0.5 * packing.box_side;
  return cut_cube(packing, target_count, Point{h, h, h}, cut);
}

CubeSample cut_cube(const Packing& packing, std::int64_t target_count, const Point& centre,
                    CubeCut cut) {
  const auto n = static_cast<std::int64_t>(packing.spheres.size());
  const double L = packing.box_side;
  if (!(L > 0) || n == 0) throw InputError("cut_cube: the packing is empty");
  if (target_count < 1 || target_count > n)
    throw InputError("cut_cube: target count = " + str(target_count) +
                     " is out of range: allowed 1 to the packing's " + str(n) + " spheres");
  // Periodic max-norm distance of every centre from the cube centre.
  std::vector<double> dist(n);
  std::vector<Point> rel(n);
  for (std::int64_t i = 0; i < n; ++i) {
    double m = 0;
    for (int k = 0; k < 3; ++k) {
      rel[i][k] = wrap_signed(packing.spheres[i].centre[k] - centre[k], L);
      m = std::max(m, std::fabs(rel[i][k]));
    }
    dist[i] = m;
  }
  std::vector<double> sorted = dist;
  std::sort(sorted.begin(), sorted.end());
  CubeSample cube;
  // Half side halfway between the target_count-th and the next distance.
  const double half =
      target_count < n ? 0.5 * (sorted[target_count - 1] + sorted[target_count]) : 0.5 * L;
  cube.side = 2.0 * half;
  cube.centre_in_box = centre;
  std::vector<char> inside(n, 0);
  for (std::int64_t i = 0; i < n; ++i) {
    if (target_count < n && dist[i] >= half) continue;
    inside[i] = 1;
    Sphere s;
    // Centres in [0, side) also after round-off.
    for (int k = 0; k < 3; ++k)
      s.centre[k] = std::clamp(rel[i][k] + half, 0.0, std::nextafter(cube.side, 0.0));
    s.radius = packing.spheres[i].radius;
    cube.spheres.push_back(s);
  }
  cube.centres_inside = static_cast<std::int64_t>(cube.spheres.size());
  Box box;
  box.lo = {0.0, 0.0, 0.0};
  box.hi = {cube.side, cube.side, cube.side};
  const double volume = box.volume();
  double own = 0;
  for (const auto& s : cube.spheres) own += sphere_box_volume(s.centre, s.radius, box);
  // Every periodic image of every sphere reaching in (the images of the
  // inside spheres other than themselves too, when the cube is nearly the
  // whole box).
  double all = own;
  for (std::int64_t i = 0; i < n; ++i) {
    const double r = packing.spheres[i].radius;
    for (int sx = -1; sx <= 1; ++sx)
      for (int sy = -1; sy <= 1; ++sy)
        for (int sz = -1; sz <= 1; ++sz) {
          if (inside[i] && sx == 0 && sy == 0 && sz == 0) continue;
          const Point c{rel[i][0] + half + sx * L, rel[i][1] + half + sy * L,
                        rel[i][2] + half + sz * L};
          double gap2 = 0;  // squared distance from the centre to the cube
          for (int k = 0; k < 3; ++k) {
            const double g = std::max({0.0, -c[k], c[k] - cube.side});
            gap2 += g * g;
          }
          if (gap2 >= r * r) continue;
          const double v = sphere_box_volume(c, r, box);
          all += v;
          if (cut == CubeCut::reaching_in) {
            cube.spheres.push_back({c, r});
            own += v;
          }
        }
  }
  cube.volume_fraction = own / volume;
  cube.region_volume_fraction = all / volume;
  return cube;
}

}  // namespace lem
