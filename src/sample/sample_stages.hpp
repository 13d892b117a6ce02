// The stages of a cemented sample that the serial build (cemented_sample.cpp)
// and the build in parallel (parallel_sample.cpp) share.
#pragma once

#include "lem/sample/cemented_sample.hpp"

#include <cstdint>
#include <vector>

namespace lem::sample_stages {

/// The packing and the cube cut from it: s.particles and the statistics of
/// the cube (particles, side, rho_p_geometric, packing_seconds).  Returns the
/// sample's box.  Throws InputError for a sample too small to cut or a
/// resolution below kMinNodesPerParticle.
Box cut_granular_cube(const CementedSampleSpec& spec, CementedSample& s);

/// The statistics that follow from the counts: p bonds and eligible and
/// holding bridges per sample particle, S^pm/S^p (`leaving`: bond ends
/// leaving a particle surface), from st.bonds_per_phase and `holding[k]`
/// (bridge k holds at least one matrix node).
void set_count_statistics(CementedSampleStats& st, const std::vector<Bridge>& bridges,
                          const std::vector<int>& holding, std::int64_t leaving);

/// Bond ends of a bond of `phase` that leave a particle surface (one for a
/// bond from a particle into the matrix or a pore, two for pp).
int ends_leaving_particles(Phase phase, bool first_in_particle, bool second_in_particle);

}  // namespace lem::sample_stages
