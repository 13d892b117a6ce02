#include "lem/protocol/disorder.hpp"

#include "lem/base/byte_stream.hpp"

#include <cmath>

namespace lem {

namespace {

double unit_uniform(std::uint64_t seed, std::int64_t id) {  // in (0, 1)
  const std::uint64_t h = mix64(mix64(seed) ^ static_cast<std::uint64_t>(id));
  return (static_cast<double>(h >> 11) + 0.5) * 0x1.0p-53;
}

}  // namespace

double threshold_factor(const FractureOptions& o, std::int64_t bond_id) {
  if (o.disorder == ThresholdDisorder::none) return 1.0;
  const double u = unit_uniform(o.disorder_seed, bond_id);
  if (o.disorder == ThresholdDisorder::uniform) return 1.0 + o.disorder_width * (2.0 * u - 1.0);
  const double weibull_mean = std::tgamma(1.0 + 1.0 / o.weibull_modulus);
  return std::pow(-std::log1p(-u), 1.0 / o.weibull_modulus) / weibull_mean;
}

void apply_strength_disorder(DistributedLattice& l, const FractureOptions& o) {
  if (o.disorder == ThresholdDisorder::none) return;
  for (int b = 0; b < l.local_bonds(); ++b) {
    const int phase = l.bond_tag.empty() ? 0 : static_cast<int>(l.bond_tag[b]);
    if (o.disorder_phases[phase]) l.bond_strength[b] *= threshold_factor(o, l.bond_id[b]);
  }
}

}  // namespace lem
