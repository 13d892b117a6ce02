// The unit in which the programs report stresses and moduli (paper sect.
// 2.2), decided here and nowhere else.  A generated lattice's bonds have the
// stiffness k = -lattice_k, so its stresses are reported in units of k/a (a
// the mean bond length).  A sample file's bonds have k = E^phase a and
// f = sigma^phase a^2 in the sample's own length unit, so its stresses come
// out of the lattice in the units of the phase moduli already: unit 1.
#pragma once

#include "lem/setup/setup.hpp"

namespace lem {

struct StressUnit {
  /// One reported unit in the lattice's stress (force per area): k/a, or 1.
  double value = 1;
  /// The reported value per lattice stress, computed as a/k (not as
  /// 1/value, which may differ in the last bit): the factor the fracture
  /// protocol multiplies its stresses by.
  double per_lattice_stress = 1;
  /// A lattice stress or modulus in this unit.
  double of(double lattice_stress) const { return lattice_stress / value; }
};

/// The unit of the sample these options describe, whose lattice has the
/// mean bond length `mean_bond_length`.
StressUnit stress_unit(const SampleOptions& sample, double mean_bond_length);

}  // namespace lem
