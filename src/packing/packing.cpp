// Jammed packing of polydisperse frictionless spheres by isotropic compaction
// in a periodic box (see packing.hpp and docs/model/packing.md); the soft-sphere
// system it compresses is in compactor.hpp.
//
// Internally lengths are in units of d_min and the contact stiffness and the
// masses are 1, so the FIRE time step does not depend on the user's units.
#include "lem/packing/packing.hpp"

#include "compactor.hpp"
#include "lem/base/error.hpp"
#include "pair_search.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <numeric>
#include <random>
#include <sstream>
#include <string>

namespace lem {

using packing_detail::Compactor;
using packing_detail::for_each_close_pair;
using packing_detail::kPi;
using packing_detail::min_image;
using packing_detail::sphere_volume;

namespace {

constexpr std::int64_t kMaxCount = 50'000'000;  // 32-bit pair indices, memory
constexpr int kMaxAttempts = 400;
constexpr double kDensest = 0.75;  // no random packing gets beyond this

// Uniform double in [0, 1) from the top 53 bits: unlike
// std::uniform_real_distribution this is the same with every standard library.
double uniform01(std::mt19937_64& g) { return static_cast<double>(g() >> 11) * 0x1.0p-53; }

template <class T>
std::string str(const T& v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// Diameters in units of d_min.
std::vector<double> draw_diameters(const PackingSpec& spec, std::mt19937_64& g) {
  const double ratio = spec.d_max / spec.d_min;
  std::vector<double> d(static_cast<std::size_t>(spec.count));
  for (double& di : d) {
    const double u = uniform01(g);
    if (spec.distribution == SizeDistribution::uniform_diameter)
      di = 1.0 + u * (ratio - 1.0);
    else
      di = std::cbrt(1.0 + u * (ratio * ratio * ratio - 1.0));
  }
  return d;
}

// Order of the spheres along a serpentine walk through cells of ~2 d_min.
std::vector<std::int64_t> spatial_order(const std::vector<double>& x, double L) {
  const auto n = static_cast<std::int64_t>(x.size() / 3);
  const auto m = std::max<std::int64_t>(1, static_cast<std::int64_t>(L / 2.0));
  std::vector<std::int64_t> keys(n), order(n);
  for (std::int64_t i = 0; i < n; ++i) {
    std::array<std::int64_t, 3> k{};
    for (int a = 0; a < 3; ++a)
      k[a] = std::min(m - 1, static_cast<std::int64_t>(x[3 * i + a] / L * static_cast<double>(m)));
    const std::int64_t ky = (k[2] % 2) ? m - 1 - k[1] : k[1];
    const std::int64_t kx = ((k[2] * m + ky) % 2) ? m - 1 - k[0] : k[0];
    keys[i] = (k[2] * m + ky) * m + kx;
  }
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::int64_t a, std::int64_t b) {
    return keys[a] != keys[b] ? keys[a] < keys[b] : a < b;
  });
  return order;
}

// Expected d^3 (units of d_min^3) of the distribution.
double mean_cube(const PackingSpec& spec) {
  const double q = spec.d_max / spec.d_min;
  if (spec.distribution == SizeDistribution::uniform_volume) return 0.5 * (1.0 + q * q * q);
  if (q == 1.0) return 1.0;
  return (q * q * q * q - 1.0) / (4.0 * (q - 1.0));
}

}  // namespace

void validate(const PackingSpec& spec) {
  auto fail = [](const std::string& what) { throw InputError("packing: " + what); };
  if (spec.count < 20 || spec.count > kMaxCount)
    fail("count = " + str(spec.count) + " is out of range: allowed 20 to " + str(kMaxCount) +
         " spheres");
  if (!(spec.d_min > 0) || !std::isfinite(spec.d_min))
    fail("d_min = " + str(spec.d_min) + " is not allowed: the smallest diameter must be > 0");
  if (!(spec.d_max >= spec.d_min) || !std::isfinite(spec.d_max))
    fail("d_max = " + str(spec.d_max) +
         " is not allowed: the largest diameter must be >= d_min = " + str(spec.d_min));
  if (spec.d_max > 4.0 * spec.d_min)
    fail("d_max / d_min = " + str(spec.d_max / spec.d_min) +
         " is out of range: allowed 1 to 4 (cell lists are sized by the largest sphere)");
  if (!(spec.initial_fraction >= 0.05 && spec.initial_fraction <= 0.72))
    fail("initial_fraction = " + str(spec.initial_fraction) +
         " is out of range: allowed 0.05 to 0.72");
  if (!(spec.initial_step > 0 && spec.initial_step <= 0.1))
    fail("initial_step = " + str(spec.initial_step) + " is out of range: allowed (0, 0.1]");
  if (!(spec.fraction_tolerance >= 1e-9 && spec.fraction_tolerance <= spec.initial_step))
    fail("fraction_tolerance = " + str(spec.fraction_tolerance) +
         " is out of range: allowed 1e-9 to initial_step = " + str(spec.initial_step));
  if (!(spec.contact_gap >= 0 && spec.contact_gap <= 0.5))
    fail("contact_gap = " + str(spec.contact_gap) + " is out of range: allowed 0 to 0.5");
  if (!(spec.force_tolerance > 0 && spec.force_tolerance <= 0.1))
    fail("force_tolerance = " + str(spec.force_tolerance) + " is out of range: allowed (0, 0.1]");
  if (spec.max_relaxation_steps < 100)
    fail("max_relaxation_steps = " + str(spec.max_relaxation_steps) +
         " is too small: allowed >= 100");
  // The densest box of the compaction (the start or just above jamming) must
  // still hold the largest sphere twice across its half side (one image per
  // contact, and room for the pair list skin).
  const double q = spec.d_max / spec.d_min;
  const double densest = std::max(spec.initial_fraction, 0.66) + spec.initial_step;
  const double side =
      std::cbrt(static_cast<double>(spec.count) * kPi / 6.0 * mean_cube(spec) / densest);
  if (0.49 * side - q <= 0.01)
    fail("count = " + str(spec.count) + " is too few spheres for d_max / d_min = " + str(q) +
         ": the periodic box would be narrower than four largest radii");
}

namespace {

// The random start: sphere centres uniform in a box of side `side` at the
// initial volume fraction, sorted along a coarse grid so that neighbours
// are close in memory (the order a function of the seed only); radii in
// units of d_min.
struct RandomStart {
  std::vector<std::int64_t> order;  // the k-th sphere is the order[k]-th drawn
  std::vector<double> x, r;
  double side = 0;
};

RandomStart random_start(const PackingSpec& spec, const std::vector<double>& d,
                         std::mt19937_64& g) {
  const std::int64_t n = spec.count;
  double solid = 0;
  for (double di : d) solid += sphere_volume(0.5 * di);
  RandomStart out;
  out.side = std::cbrt(solid / spec.initial_fraction);
  std::vector<double> x(3 * n);
  for (double& c : x) c = uniform01(g) * out.side;
  out.order = spatial_order(x, out.side);
  out.x.resize(3 * n);
  out.r.resize(n);
  for (std::int64_t k = 0; k < n; ++k) {
    for (int a = 0; a < 3; ++a) out.x[3 * k + a] = x[3 * out.order[k] + a];
    out.r[k] = 0.5 * d[out.order[k]];
  }
  return out;
}

// What the progress callback is told of an attempt.
JammingAttempt attempt_report(const Compactor& sys, const Compactor::Relaxation& relaxed,
                              int attempt, double step, std::int64_t n, double seconds) {
  JammingAttempt a;
  a.attempt = attempt;
  a.volume_fraction = sys.fraction();
  a.jammed = relaxed.jammed;
  a.step = step;
  a.energy_per_particle = relaxed.energy / static_cast<double>(n);
  const auto o = sys.overlaps();
  a.mean_overlap = o.mean;
  a.max_overlap = o.max;
  a.relaxation_steps = relaxed.steps;
  a.settled = relaxed.settled;
  a.seconds = seconds;
  return a;
}

// The spheres of the compactor's state in the user's units, folded into
// the box, with the packing's statistics.
Packing packing_of(const Compactor& sys, const PackingSpec& spec, const std::vector<double>& d,
                   const std::vector<std::int64_t>& order) {
  const std::int64_t n = spec.count;
  Packing p;
  p.box_side = sys.box() * spec.d_min;
  p.spheres.resize(static_cast<std::size_t>(n));
  const auto& pos = sys.positions();
  for (std::int64_t i = 0; i < n; ++i) {
    Sphere& s = p.spheres[i];
    for (int a = 0; a < 3; ++a) {
      double c = pos[3 * i + a] * spec.d_min;
      if (c >= p.box_side) c -= p.box_side;
      if (c < 0) c = 0;
      s.centre[a] = c;
    }
    s.radius = 0.5 * d[order[i]] * spec.d_min;
  }
  p.stats = measure_packing(p.spheres, p.box_side, spec.contact_gap);
  p.stats.neighbour_builds = sys.builds();
  return p;
}

}  // namespace

Packing make_packing(const PackingSpec& spec, const JammingProgress& progress) {
  validate(spec);
  const auto t0 = std::chrono::steady_clock::now();
  auto seconds = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  std::mt19937_64 g(spec.seed);
  const std::vector<double> d = draw_diameters(spec, g);
  RandomStart start = random_start(spec, d, g);
  Compactor sys(std::move(start.r), std::move(start.x), start.side, spec.law);

  // Phase 1: relax the random start; if it is not jammed (a start below
  // jamming), compress in steps until it is.
  // Phase 2: decompress from the last jammed state: a smaller volume
  // fraction that is still jammed replaces it; one that unjams halves the
  // step, and the next try starts again from the last jammed state.  Every
  // relaxation of phase 2 starts near a jammed minimum; relaxing an unjammed
  // state into a jammed one close to the jamming point is the slowest case
  // (slow coarsening, many times longer for large counts) and is avoided.
  double phi = spec.initial_fraction;
  double step = spec.initial_step;
  std::int64_t total_steps = 0;
  int attempt = 0, unsettled = 0;
  bool have_jammed = false;
  Compactor::State jammed_state;
  double jammed_phi = 0;
  for (;;) {
    if (attempt >= kMaxAttempts)
      throw NumericalError("packing: no jamming point found in " + str(kMaxAttempts) +
                           " attempts (last volume fraction " + str(phi) + ")");
    const auto relaxed = sys.relax(spec.max_relaxation_steps, spec.force_tolerance);
    ++attempt;
    total_steps += relaxed.steps;
    unsettled += relaxed.settled ? 0 : 1;
    if (progress) progress(attempt_report(sys, relaxed, attempt, step, spec.count, seconds()));
    if (relaxed.jammed) {
      jammed_state = sys.snapshot();
      jammed_phi = phi;
      have_jammed = true;
      phi -= step;
    } else if (!have_jammed) {
      phi += step;
    } else {
      if (step <= spec.fraction_tolerance * (1 + 1e-9)) break;
      step *= 0.5;
      sys.restore(jammed_state);
      phi = jammed_phi - step;
    }
    if (!(phi > 0.05 && phi < kDensest))
      throw NumericalError("packing: the compaction left the range of random packings "
                           "(volume fraction " +
                           str(phi) + ")");
    sys.set_fraction(phi);
  }
  sys.restore(jammed_state);

  Packing p = packing_of(sys, spec, d, start.order);
  p.stats.attempts = attempt;
  p.stats.relaxation_steps = total_steps;
  p.stats.unsettled_attempts = unsettled;
  p.stats.seconds = seconds();
  return p;
}

namespace {

struct Backbone {
  double rattler_fraction = 0, coordination = 0;
};

// Remove spheres with fewer than 4 contacts (they cannot be in frictionless
// equilibrium under load: rattlers) until none is left; mean coordination of
// the rest.
Backbone backbone(const std::vector<std::array<std::int64_t, 2>>& contacts, std::int64_t n) {
  std::vector<std::int64_t> start(n + 1, 0), adj(2 * contacts.size());
  for (const auto& [i, j] : contacts) {
    ++start[i + 1];
    ++start[j + 1];
  }
  for (std::int64_t i = 0; i < n; ++i) start[i + 1] += start[i];
  {
    std::vector<std::int64_t> fill(start.begin(), start.end() - 1);
    for (const auto& [i, j] : contacts) {
      adj[fill[i]++] = j;
      adj[fill[j]++] = i;
    }
  }
  std::vector<std::int64_t> degree(n), stack;
  std::vector<char> removed(n, 0);
  for (std::int64_t i = 0; i < n; ++i) {
    degree[i] = start[i + 1] - start[i];
    if (degree[i] < 4) {
      removed[i] = 1;
      stack.push_back(i);
    }
  }
  while (!stack.empty()) {
    const std::int64_t i = stack.back();
    stack.pop_back();
    for (std::int64_t k = start[i]; k < start[i + 1]; ++k) {
      const std::int64_t j = adj[k];
      if (!removed[j] && --degree[j] < 4) {
        removed[j] = 1;
        stack.push_back(j);
      }
    }
  }
  std::int64_t rattlers = 0, ends = 0;
  for (std::int64_t i = 0; i < n; ++i) {
    if (removed[i]) {
      ++rattlers;
      continue;
    }
    for (std::int64_t k = start[i]; k < start[i + 1]; ++k) ends += removed[adj[k]] ? 0 : 1;
  }
  Backbone b;
  b.rattler_fraction = static_cast<double>(rattlers) / static_cast<double>(n);
  if (rattlers < n) b.coordination = static_cast<double>(ends) / static_cast<double>(n - rattlers);
  return b;
}

}  // namespace

PackingStats measure_packing(const std::vector<Sphere>& spheres, double box_side,
                             double contact_gap) {
  PackingStats st;
  const auto n = static_cast<std::int64_t>(spheres.size());
  st.particles = n;
  if (n == 0) return st;
  std::vector<double> x(3 * n), r(n);
  double rmax = 0, solid = 0, dsum = 0;
  for (std::int64_t i = 0; i < n; ++i) {
    for (int a = 0; a < 3; ++a) {
      double c = spheres[i].centre[a];
      c -= box_side * std::floor(c / box_side);
      x[3 * i + a] = c < box_side ? c : 0.0;
    }
    r[i] = spheres[i].radius;
    rmax = std::max(rmax, r[i]);
    solid += sphere_volume(r[i]);
    dsum += 2.0 * r[i];
  }
  const double volume = box_side * box_side * box_side;
  st.volume_fraction = solid / volume;
  st.mean_diameter = dsum / static_cast<double>(n);
  const double gap = contact_gap * st.mean_diameter;
  if (!(2.0 * rmax + gap < 0.5 * box_side))
    throw InputError("measure_packing: box side " + str(box_side) +
                     " is too small: it must exceed 4 r_max + 2 gap = " + str(4 * rmax + 2 * gap));

  std::vector<std::array<std::int64_t, 2>> contacts, overlapping;
  double overlap_sum = 0, virial = 0;
  const double half = 0.5 * box_side;
  for_each_close_pair(x, r, box_side, rmax, gap, [&](std::int64_t i, std::int64_t j) {
    contacts.push_back({i, j});
    const double dx = min_image(x[3 * j] - x[3 * i], box_side, half);
    const double dy = min_image(x[3 * j + 1] - x[3 * i + 1], box_side, half);
    const double dz = min_image(x[3 * j + 2] - x[3 * i + 2], box_side, half);
    const double dist = std::sqrt(dx * dx + dy * dy + dz * dz);
    const double s = r[i] + r[j];
    if (dist < s) {
      const double rel = (s - dist) / s;
      ++st.overlapping_pairs;
      overlapping.push_back({i, j});
      overlap_sum += rel;
      st.max_overlap = std::max(st.max_overlap, rel);
      virial += (s - dist) * dist;  // unit-stiffness linear law
    }
  });
  st.contacts = static_cast<std::int64_t>(contacts.size());
  st.mean_coordination = 2.0 * static_cast<double>(st.contacts) / static_cast<double>(n);
  if (st.overlapping_pairs)
    st.mean_overlap = overlap_sum / static_cast<double>(st.overlapping_pairs);
  st.pressure = virial / (3.0 * volume);

  const auto all = backbone(contacts, n);
  st.rattler_fraction = all.rattler_fraction;
  st.backbone_coordination = all.coordination;
  st.loaded_coordination = backbone(overlapping, n).coordination;
  return st;
}

}  // namespace lem
