// What the writer and the reader of the sample file (lem/sample/sample_reader.hpp,
// lem/sample/sample_writer.hpp) share: the lists of its scalar attributes, the HDF5 types of its
// datasets and the names of its choices.
#pragma once

#include "lem/sample/cemented_sample.hpp"

#include <hdf5.h>

#include <string>
#include <type_traits>
#include <utility>

namespace lem::sample_layout {

// ---------------------------------------------------------------------------
// Scalar attributes: one list, used by the writer and the reader
// ---------------------------------------------------------------------------

// Every statistic must be stored: a new field changes the size (all fields
// are 8 bytes) and must be added to visit_statistics below.
static_assert(sizeof(CementedSampleStats) == 31 * 8,
              "CementedSampleStats changed: store the new field in visit_statistics()");

/// Calls visit(name, value&) for the numeric attributes a reader needs: the
/// sizes (checked against the datasets) and the recipe (value:
/// std::int64_t, std::uint64_t or double).
template <class Visit>
void visit_structure(CementedSampleStats& st, CementedSampleSpec& sp, Visit&& visit) {
  visit("particles", st.particles);
  visit("nodes", st.nodes);
  visit("bonds", st.bonds);
  PackingSpec& p = sp.packing;
  visit("packing_count", p.count);
  visit("packing_d_min", p.d_min);
  visit("packing_d_max", p.d_max);
  visit("packing_seed", p.seed);
  visit("packing_initial_fraction", p.initial_fraction);
  visit("packing_initial_step", p.initial_step);
  visit("packing_fraction_tolerance", p.fraction_tolerance);
  visit("packing_contact_gap", p.contact_gap);
  visit("packing_force_tolerance", p.force_tolerance);
  visit("packing_max_relaxation_steps", p.max_relaxation_steps);
  visit("sample_particles", sp.sample_particles);
  RandomLatticeSpec& l = sp.lattice;
  visit("lattice_nodes", l.nodes);
  visit("lattice_bonds", l.bonds);
  visit("lattice_Ln", l.mesh_density);
  visit("lattice_min_separation", l.min_separation);
  visit("lattice_seed", l.seed);
  visit("lattice_stiffness", l.stiffness);
  visit("matrix_fraction", sp.bridges.matrix_fraction);
  visit("matrix_max_gap", sp.bridges.max_gap);
  visit("matrix_max_lambda", sp.bridges.max_lambda);
}

/// The other statistics: informative only, so a file written before a
/// statistic existed still loads (the statistic then reads as 0).
template <class Visit>
void visit_statistics(CementedSampleStats& st, Visit&& visit) {
  visit("centres_inside", st.sample_particles);
  visit("side", st.side);
  visit("nodes_per_particle", st.nodes_per_particle);
  visit("rho_p_geometric", st.rho_p_geometric);
  visit("rho_m_requested", st.rho_m_requested);
  visit("rho_p", st.rho_p);
  visit("rho_m", st.rho_m);
  visit("rho_v", st.rho_v);
  for (int k = 0; k < kPhaseCount; ++k) {
    const std::string phase = phase_name(static_cast<Phase>(k));
    visit("bonds_" + phase, st.bonds_per_phase[k]);
    visit("bond_volume_fraction_" + phase, st.bond_volume_fraction[k]);
  }
  visit("bonds_per_particle", st.bonds_per_particle);
  visit("eligible_pairs", st.eligible_pairs);
  visit("bridges", st.bridges);
  visit("eligible_per_particle", st.eligible_per_particle);
  visit("bridges_per_particle", st.bridges_per_particle);
  visit("interface_ratio", st.interface_ratio);
  visit("packing_seconds", st.packing_seconds);
  visit("lattice_seconds", st.lattice_seconds);
  visit("voronoi_seconds", st.voronoi_seconds);
  visit("phases_seconds", st.phases_seconds);
}

template <class T>
std::pair<hid_t, hid_t> hdf5_types() {  // (file type, memory type)
  if constexpr (std::is_same_v<T, double>)
    return {H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE};
  else if constexpr (std::is_same_v<T, std::int64_t>)
    return {H5T_STD_I64LE, H5T_NATIVE_INT64};
  else if constexpr (std::is_same_v<T, std::uint64_t>)
    return {H5T_STD_U64LE, H5T_NATIVE_UINT64};
  else if constexpr (std::is_same_v<T, std::int32_t>)
    return {H5T_STD_I32LE, H5T_NATIVE_INT32};
  else {
    static_assert(std::is_same_v<T, std::uint8_t>);
    return {H5T_STD_U8LE, H5T_NATIVE_UINT8};
  }
}

inline const char* distribution_name(SizeDistribution d) {
  return d == SizeDistribution::uniform_volume ? "uniform_volume" : "uniform_diameter";
}
inline const char* law_name(ContactLaw law) {
  return law == ContactLaw::hertz ? "hertz" : "linear";
}

inline const char* generator_name(LatticeGenerator g) {
  return g == LatticeGenerator::cells ? "cells" : "serial";
}

inline std::uint8_t node_phase_code(const NodePhases& np, std::size_t n) {
  return np.particle[n] >= 0 ? 0 : (np.matrix[n] ? 1 : 2);
}

}  // namespace lem::sample_layout
