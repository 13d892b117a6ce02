#include "lem/setup/units.hpp"

namespace lem {

StressUnit stress_unit(const SampleOptions& sample, double mean_bond_length) {
  StressUnit unit;
  if (!sample.sample_file.empty()) return unit;
  const double k = sample.random.stiffness;
  unit.value = k / mean_bond_length;
  unit.per_lattice_stress = mean_bond_length / k;
  return unit;
}

}  // namespace lem
