// Threshold disorder: a seeded random factor on the breaking thresholds that
// depends only on (seed, bond id), so it is the same on every rank count.
#pragma once

#include "lem/system/distributed_lattice.hpp"
#include "lem/protocol/options.hpp"

#include <cstdint>

namespace lem {

/// The factor of one bond (mean one for weibull; 1 for none).
double threshold_factor(const FractureOptions& options, std::int64_t bond_id);

/// Multiply the thresholds of the phases in options.disorder_phases.
void apply_strength_disorder(DistributedLattice& lattice, const FractureOptions& options);

}  // namespace lem
