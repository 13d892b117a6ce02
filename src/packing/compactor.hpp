// The soft-sphere system that make_packing compresses (packing stage,
// private header): frictionless spheres in a periodic cube, a Verlet pair
// list with an inner list, and FIRE relaxation.  Lengths are in units of
// d_min, the contact stiffness and the masses are 1.
#pragma once

#include "lem/base/error.hpp"
#include "lem/packing/packing.hpp"
#include "pair_search.hpp"

#include <algorithm>
#include <array>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

namespace lem::packing_detail {

constexpr double kPi = 3.14159265358979323846;

inline double sphere_volume(double r) { return 4.0 / 3.0 * kPi * r * r * r; }

// max(a, b) without a branch (GCC compiles std::max of doubles to a compare
// and jump, mispredicted for about half of the pairs of the force loop).
inline double max_of(double a, double b) {
#if defined(__SSE2__)
  return _mm_cvtsd_f64(_mm_max_sd(_mm_set_sd(a), _mm_set_sd(b)));
#else
  return a > b ? a : b;
#endif
}

// Soft-sphere system with a Verlet pair list and FIRE relaxation.
class Compactor {
 public:
  Compactor(std::vector<double> radii, std::vector<double> x, double L, ContactLaw law)
      : r_(std::move(radii)), x_(std::move(x)), L_(L), law_(law) {
    n_ = static_cast<std::int64_t>(r_.size());
    v_.assign(3 * n_, 0.0);
    f_.assign(3 * n_, 0.0);
    rmax_ = *std::max_element(r_.begin(), r_.end());
    solid_ = 0;
    for (double r : r_) solid_ += sphere_volume(r);
    build_list();
  }

  double box() const { return L_; }
  double fraction() const { return solid_ / (L_ * L_ * L_); }
  const std::vector<double>& positions() const { return x_; }
  std::int64_t builds() const { return builds_; }

  struct State {
    std::vector<double> x;
    double L = 0;
  };
  State snapshot() const { return {x_, L_}; }
  void restore(const State& s) {
    x_ = s.x;
    L_ = s.L;
    build_list();
  }

  /// Affine change of the box to volume fraction phi.
  void set_fraction(double phi) {
    const double L = std::cbrt(solid_ / phi);
    const double s = L / L_;
    for (double& c : x_) c *= s;
    L_ = L;
    build_list();
  }

  struct Relaxation {
    bool jammed = false;
    bool settled = true;  // false: stopped by the step limit
    std::int64_t steps = 0;
    double energy = 0;
  };

  /// FIRE 2.0 (Guenole et al., Comput. Mater. Sci. 175, 2020) with
  /// semi-implicit Euler steps.  Ends unjammed when the energy per particle
  /// falls below kZeroEnergy (the overlaps have vanished), jammed when the
  /// largest net force on a particle is a small fraction of the mean contact
  /// force (a mechanically stable state with overlaps).  A state still
  /// overlapping after max_steps counts as jammed (not settled).
  Relaxation relax(std::int64_t max_steps, double force_tolerance) {
    constexpr double kZeroEnergy = 1e-16;  // per particle, overlaps ~1e-8 d_min
    constexpr int kDelay = 20;
    constexpr double kAlphaStart = 0.25, kFAlpha = 0.99, kFInc = 1.1, kFDec = 0.5;
    const double dt_max = max_step(), dt_min = 0.02 * dt_max;
    double dt = 0.1 * dt_max, alpha = kAlphaStart;
    int positive = 0;
    std::fill(v_.begin(), v_.end(), 0.0);
    double energy = forces();
    const double zero = kZeroEnergy * static_cast<double>(n_);
    for (std::int64_t step = 0;; ++step) {
      if (!std::isfinite(energy)) throw NumericalError("packing: the energy is not finite");
      if (energy < zero) return {false, true, step, energy};
      double power = 0, f2 = 0, fmax2 = 0;
      for (std::int64_t i = 0; i < n_; ++i) {
        const double* f = &f_[3 * i];
        const double* v = &v_[3 * i];
        const double fi2 = f[0] * f[0] + f[1] * f[1] + f[2] * f[2];
        power += f[0] * v[0] + f[1] * v[1] + f[2] * v[2];
        f2 += fi2;
        fmax2 = std::max(fmax2, fi2);
      }
      const double tol = force_tolerance * mean_force_;
      if (fmax2 <= tol * tol) return {true, true, step, energy};
      if (step >= max_steps) return {true, false, step, energy};
      if (power > 0) {
        if (++positive > kDelay) {
          dt = std::min(dt * kFInc, dt_max);
          alpha *= kFAlpha;
        }
      } else {
        positive = 0;
        if (step >= kDelay) {
          if (dt * kFDec >= dt_min) dt *= kFDec;
          alpha = kAlphaStart;
        }
        // Went uphill: step back half a step and stop (zero velocities).
        for (std::int64_t k = 0; k < 3 * n_; ++k) x_[k] -= 0.5 * dt * v_[k];
        drift_ += 0.5 * dt * vmax_;
        inner_drift_ += 0.5 * dt * vmax_;
        std::fill(v_.begin(), v_.end(), 0.0);
      }
      double v2 = 0;
      for (std::int64_t k = 0; k < 3 * n_; ++k) {
        v_[k] += dt * f_[k];
        v2 += v_[k] * v_[k];
      }
      const double mix = f2 > 0 ? alpha * std::sqrt(v2 / f2) : 0.0;
      double vmax2 = 0;
      for (std::int64_t i = 0; i < n_; ++i) {
        double vi2 = 0;
        for (int a = 0; a < 3; ++a) {
          const std::int64_t k = 3 * i + a;
          v_[k] = (1.0 - alpha) * v_[k] + mix * f_[k];
          x_[k] += dt * v_[k];
          vi2 += v_[k] * v_[k];
        }
        vmax2 = std::max(vmax2, vi2);
      }
      vmax_ = std::sqrt(vmax2);
      drift_ += dt * vmax_;
      inner_drift_ += dt * vmax_;
      if (2.0 * drift_ > skin_)
        build_list();
      else if (2.0 * inner_drift_ > inner_skin_)
        build_inner();
      energy = forces();
    }
  }

  struct Overlaps {
    double mean = 0, max = 0;
  };
  Overlaps overlaps() const {
    Overlaps o;
    std::int64_t count = 0;
    for (const auto& [i, j] : pairs_) {
      const double dx = min_image(x_[3 * j] - x_[3 * i], L_, 0.5 * L_);
      const double dy = min_image(x_[3 * j + 1] - x_[3 * i + 1], L_, 0.5 * L_);
      const double dz = min_image(x_[3 * j + 2] - x_[3 * i + 2], L_, 0.5 * L_);
      const double s = r_[i] + r_[j];
      const double d = std::sqrt(dx * dx + dy * dy + dz * dz);
      if (d < s) {
        const double rel = (s - d) / s;
        o.mean += rel;
        o.max = std::max(o.max, rel);
        ++count;
      }
    }
    if (count) o.mean /= static_cast<double>(count);
    return o;
  }

 private:
  // Largest FIRE step.  Unit masses and unit springs: the highest
  // vibration frequency is below sqrt(2 z) ~ 3.5-5 for z = 6-12 contacts, and
  // semi-implicit Euler is stable for dt omega < 2; 0.3 was the fastest of
  // 0.2-0.5 in trials (FIRE itself cuts the step when it overshoots).  The
  // Hertz stiffness 1.5 sqrt(delta) softens with the overlap: the step grows
  // with the mean overlap of the state at the start of the relaxation.
  double max_step() const {
    constexpr double kLinear = 0.3;
    if (law_ == ContactLaw::linear) return kLinear;
    const double delta = std::max(overlaps().mean * 2.0 * rmax_, 1e-8);
    return std::min(kLinear / std::sqrt(1.5 * std::sqrt(delta)), 10 * kLinear);
  }

  // Pair list with a skin: valid while no particle has moved more than
  // skin/2 since the build (drift_ bounds the largest displacement).
  void build_list() {
    for (double& c : x_) c -= L_ * std::floor(c / L_);
    for (double& c : x_)
      if (c >= L_) c -= L_;  // floor round-off can leave c == L
    skin_ = std::min(kSkin, 0.49 * L_ - 2.0 * rmax_);
    inner_skin_ = std::min(kInnerSkin, skin_);
    if (skin_ <= 0.0) {
      std::ostringstream side;
      side << L_;
      throw NumericalError("packing: the box (side " + side.str() +
                           " d_min) is too small for the largest sphere");
    }
    pairs_.clear();
    for_each_close_pair(x_, r_, L_, rmax_, skin_, [&](std::int64_t i, std::int64_t j) {
      pairs_.push_back(
          {static_cast<std::int32_t>(std::min(i, j)), static_cast<std::int32_t>(std::max(i, j))});
    });
    // Sorted by the first index (counting sort), so consecutive pairs share
    // a particle and the pair loops walk the positions in order.
    std::vector<std::int64_t> row(n_ + 1, 0);
    for (const auto& pr : pairs_) ++row[pr[0] + 1];
    for (std::int64_t i = 0; i < n_; ++i) row[i + 1] += row[i];
    const std::size_t count = pairs_.size();
    pi_.resize(count);
    pj_.resize(count);
    image_.resize(count);
    ni_.resize(count);
    nj_.resize(count);
    nimage_.resize(count);
    cx_.resize(3 * count);
    cd2_.resize(count + 2);  // room for the padding pair
    cs_.resize(count + 2);
    cc_.resize(count + 2);
    const double half = 0.5 * L_;
    for (const auto& [i, j] : pairs_) {
      // Periodic image of j nearest to i, fixed until the next build
      // (positions are wrapped only here): no minimum-image test per step.
      int code = 0;
      for (int a = 2; a >= 0; --a) {
        const double d = x_[3 * j + a] - x_[3 * i + a];
        code = 3 * code + (d > half ? 0 : (d < -half ? 2 : 1));
      }
      const std::int64_t k = row[i]++;
      pi_[k] = i;
      pj_[k] = j;
      image_[k] = static_cast<std::uint8_t>(code);
    }
    for (int code = 0; code < 27; ++code)
      for (int a = 0, c = code; a < 3; ++a, c /= 3) shift_[3 * code + a] = (c % 3 - 1) * L_;
    drift_ = 0;
    ++builds_;
    build_inner();
  }

  // Inner list: the pairs of the outer list closer than kInnerSkin, valid
  // while no particle has moved more than kInnerSkin/2 since its build.
  // Once the packing is dense particles move little, so it is rebuilt
  // rarely, and the force loop visits ~3.2 pairs per sphere instead of ~4.7.
  void build_inner() {
    const std::int64_t pairs = static_cast<std::int64_t>(pi_.size());
    const double* x = x_.data();
    const double* r = r_.data();
    std::int64_t m = 0;
    for (std::int64_t k = 0; k < pairs; ++k) {  // branch-free compaction
      const std::int64_t i = pi_[k], j = pj_[k];
      const double* shift = shift_ + 3 * image_[k];
      const double dx = x[3 * j] - x[3 * i] + shift[0];
      const double dy = x[3 * j + 1] - x[3 * i + 1] + shift[1];
      const double dz = x[3 * j + 2] - x[3 * i + 2] + shift[2];
      const double reach = r[i] + r[j] + inner_skin_;
      ni_[m] = pi_[k];
      nj_[m] = pj_[k];
      nimage_[m] = image_[k];
      m += dx * dx + dy * dy + dz * dz < reach * reach;
    }
    inner_ = m;
    inner_drift_ = 0;
  }

  // Forces of the soft repulsion; returns the energy and sets mean_force_.
  double forces() { return law_ == ContactLaw::hertz ? forces_of<true>() : forces_of<false>(); }

  // Three flat passes over the inner list: separations, then the square
  // roots and divisions two pairs at a time (SSE2), then the forces.  No
  // branch depends on whether a pair touches (a pair apart gets zero force):
  // a third of the listed pairs do not, and a test would often be
  // mispredicted.
  template <bool kHertz>
  double forces_of() {
    double* f = f_.data();
    const double* x = x_.data();
    const double* r = r_.data();
    const std::int64_t m = inner_;
    for (std::int64_t q = 0; q < m; ++q) {
      const std::int64_t i = ni_[q], j = nj_[q];
      const double* shift = shift_ + 3 * nimage_[q];
      const double dx = x[3 * j] - x[3 * i] + shift[0];
      const double dy = x[3 * j + 1] - x[3 * i + 1] + shift[1];
      const double dz = x[3 * j + 2] - x[3 * i + 2] + shift[2];
      cx_[3 * q] = dx;
      cx_[3 * q + 1] = dy;
      cx_[3 * q + 2] = dz;
      cd2_[q] = max_of(dx * dx + dy * dy + dz * dz, 1e-300);
      cs_[q] = r[i] + r[j];
    }
    // Pad to an even count with a pair apart (d = 1 > s = 0: no force).
    cd2_[m] = 1.0;
    cs_[m] = 0.0;
    double energy = 0, force_sum = 0;
    std::int64_t touching = 0;
#if defined(__SSE2__)
    {
      __m128d e2 = _mm_setzero_pd(), f2 = _mm_setzero_pd();
      const __m128d zero = _mm_setzero_pd();
      const __m128d half = _mm_set1_pd(kHertz ? 0.4 : 0.5);
      for (std::int64_t q = 0; q < m; q += 2) {
        const __m128d d = _mm_sqrt_pd(_mm_loadu_pd(&cd2_[q]));
        const __m128d delta = _mm_max_pd(_mm_sub_pd(_mm_loadu_pd(&cs_[q]), d), zero);
        __m128d fmag = delta;
        if constexpr (kHertz) fmag = _mm_mul_pd(delta, _mm_sqrt_pd(delta));
        e2 = _mm_add_pd(e2, _mm_mul_pd(half, _mm_mul_pd(delta, fmag)));
        f2 = _mm_add_pd(f2, fmag);
        const int mask = _mm_movemask_pd(_mm_cmpgt_pd(delta, zero));
        touching += (mask & 1) + (mask >> 1);
        _mm_storeu_pd(&cc_[q], _mm_div_pd(fmag, d));
      }
      double e[2], fs[2];
      _mm_storeu_pd(e, e2);
      _mm_storeu_pd(fs, f2);
      energy = e[0] + e[1];
      force_sum = fs[0] + fs[1];
    }
#else
    for (std::int64_t q = 0; q < m; ++q) {
      const double d = std::sqrt(cd2_[q]);
      const double delta = max_of(cs_[q] - d, 0.0);
      const double fmag = kHertz ? delta * std::sqrt(delta) : delta;
      energy += (kHertz ? 0.4 : 0.5) * delta * fmag;
      force_sum += fmag;
      touching += delta > 0.0;
      cc_[q] = fmag / d;
    }
#endif
    std::fill(f_.begin(), f_.end(), 0.0);
    for (std::int64_t q = 0; q < m; ++q) {
      const std::int64_t i = ni_[q], j = nj_[q];
      const double c = cc_[q];
      const double fx = c * cx_[3 * q], fy = c * cx_[3 * q + 1], fz = c * cx_[3 * q + 2];
      f[3 * i] -= fx;
      f[3 * i + 1] -= fy;
      f[3 * i + 2] -= fz;
      f[3 * j] += fx;
      f[3 * j + 1] += fy;
      f[3 * j + 2] += fz;
    }
    mean_force_ = touching ? force_sum / static_cast<double>(touching) : 0.0;
    return energy;
  }

  // Pair list skins (d_min units): ~4.7 pairs per sphere in the outer list
  // near jamming, ~3.2 in the inner one, of which ~2.9 touch.
  static constexpr double kSkin = 0.25;
  static constexpr double kInnerSkin = 0.02;

  std::vector<double> r_, x_, v_, f_;
  double L_;
  ContactLaw law_;
  std::int64_t n_ = 0;
  double rmax_ = 0, solid_ = 0, skin_ = 0, drift_ = 0, vmax_ = 0, mean_force_ = 0;
  std::vector<std::array<std::int32_t, 2>> pairs_;  // the list, as found
  std::vector<std::int32_t> pi_, pj_;               // the list, sorted by pi_
  std::vector<std::uint8_t> image_;                 // index into shift_ of each listed pair
  std::vector<std::int32_t> ni_, nj_;               // the inner list (first inner_ entries)
  std::vector<std::uint8_t> nimage_;
  std::int64_t inner_ = 0;
  double inner_drift_ = 0, inner_skin_ = 0;
  std::vector<double> cx_;             // separation vectors of the inner pairs
  std::vector<double> cd2_, cs_, cc_;  // squared distance, r_i + r_j, force / distance
  double shift_[81] = {};
  std::int64_t builds_ = 0;
};

}  // namespace lem::packing_detail
