// The recipe of the small cemented sample of the sample tests: 27 particles
// on a 2e4-bond lattice, built in a second or two.
#pragma once

#include "lem/sample/cemented_sample.hpp"

inline lem::CementedSampleSpec little_sample_spec() {
  lem::CementedSampleSpec spec;
  spec.packing.count = 100;
  spec.packing.seed = 5;
  spec.sample_particles = 27;
  spec.lattice.bonds = 20000;
  return spec;
}
