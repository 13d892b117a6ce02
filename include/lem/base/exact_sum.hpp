// Sums whose bits do not depend on the order of the terms, so that a value
// summed over the ranks of any partition (the mean bond length that sets
// every bond's stiffness) is the same on 1 rank and on 1 000.
//
// Each term is rounded once to a multiple of 2^-64 (5e-20: below a double's
// resolution for the lengths summed, of order 1e-3 and up), then added
// exactly as a 128-bit integer; integer addition is associative, so any
// grouping of the terms gives the same total, to the bit.
#pragma once

#include <mpi.h>

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace lem {

class ExactSum {
 public:
  static constexpr int kFractionBits = 64;
  /// Terms below 2^31 in magnitude (the high part, x 2^32, fits in 63 bits).
  static constexpr int kLargestExponent = 31;

  void add(double x) {
    if (!std::isfinite(x) || std::fabs(x) >= std::ldexp(1.0, kLargestExponent))
      throw std::domain_error("ExactSum: term " + std::to_string(x) + " is out of range");
    // x = high * 2^32 + low, each part rounded to an integer multiple of
    // 2^-kFractionBits; both fit in 64 bits.
    const double scaled_high = std::ldexp(x, kFractionBits - 32);
    const double high = std::trunc(scaled_high);
    const double low = std::nearbyint(std::ldexp(scaled_high - high, 32));
    add_parts(static_cast<std::int64_t>(high), static_cast<std::int64_t>(low));
  }
  /// The sum over the ranks of `comm`, on every rank.  Collective.
  ExactSum all_ranks(MPI_Comm comm) const {
    int ranks = 1;
    MPI_Comm_size(comm, &ranks);
    const std::uint64_t mine[2] = {lo_, hi_};
    std::vector<std::uint64_t> words(2 * static_cast<std::size_t>(ranks));
    MPI_Allgather(mine, 2, MPI_UINT64_T, words.data(), 2, MPI_UINT64_T, comm);
    ExactSum total;
    for (int r = 0; r < ranks; ++r) total.add_words(words[2 * r], words[2 * r + 1]);
    return total;
  }
  /// The sum, rounded to a double.
  double value() const {
    // hi_:lo_ is a signed 128-bit integer in units of 2^-kFractionBits.
    const bool negative = static_cast<std::int64_t>(hi_) < 0;
    std::uint64_t lo = lo_, hi = hi_;
    if (negative) {  // magnitude: two's complement negation
      lo = ~lo + 1;
      hi = ~hi + (lo == 0 ? 1 : 0);
    }
    const double magnitude = std::ldexp(static_cast<double>(hi), 64 - kFractionBits) +
                             std::ldexp(static_cast<double>(lo), -kFractionBits);
    return negative ? -magnitude : magnitude;
  }

 private:
  void add_parts(std::int64_t high, std::int64_t low) {
    // high * 2^32 + low as a 128-bit two's complement pair of words.
    const auto sign = [](std::int64_t v) { return v < 0 ? ~std::uint64_t(0) : std::uint64_t(0); };
    const std::uint64_t h = static_cast<std::uint64_t>(high);
    add_words(h << 32, (sign(high) << 32) | (h >> 32));
    add_words(static_cast<std::uint64_t>(low), sign(low));
  }
  void add_words(std::uint64_t lo, std::uint64_t hi) {
    const std::uint64_t sum = lo_ + lo;
    hi_ += hi + (sum < lo_ ? 1 : 0);
    lo_ = sum;
  }
  std::uint64_t lo_ = 0, hi_ = 0;
};

}  // namespace lem
