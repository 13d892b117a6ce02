// The fingerprints of a fracture run: what identifies its checkpoint, its
// result and the calibration of its lattice (the rule: lem/base/fingerprint.hpp).
//
// Each is, one "key=value" per line:
//   ranks        the rank count (allowed to differ: the same to the tolerance);
//   the lattice  by content: nodes, bonds, sample_content (an order-free hash
//                of every node's id, coordinates, constraints, volume and
//                particle, and every bond's id, end nodes and phase), and the
//                sums that the bonds' stiffnesses and thresholds come from
//                (bond_length_mean, stiffness_total, strength_total, compared
//                to 1e-10: another set-up sums them in another order);
//   the protocol the options as the protocol uses them (increment, rules,
//                and the lines the entries of the break rule and the
//                relaxation scheme give: registry.hpp);
//   the options  every option read ("-name=value"), but those of
//                OptionKind::outside and, by scope: a checkpoint leaves out
//                where the run ends (it may be resumed to go further); a
//                calibration, which breaks the homogeneous lattice to its
//                peak, leaves out the other phases, the end and the units of
//                the sample run, and its output options.
#pragma once

#include "lem/protocol/options.hpp"
#include "lem/system/distributed_lattice.hpp"

#include <string>

namespace lem {

enum class FingerprintScope { checkpoint, calibration, result };

/// The lattice lines (nodes, bonds, sample_content and the sums).  Collective.
std::string lattice_fingerprint(const DistributedLattice& lattice);

/// The fingerprint of a run on `lattice` with `options`, for `scope`.
/// Collective (the same text on every rank).
std::string fracture_fingerprint(const DistributedLattice& lattice, const FractureOptions& options,
                                 FingerprintScope scope);

}  // namespace lem
