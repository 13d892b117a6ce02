#include "lem/protocol/fingerprint.hpp"

#include "lem/base/byte_stream.hpp"
#include "lem/base/exact_sum.hpp"
#include "lem/base/fingerprint.hpp"
#include "lem/protocol/registry.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

namespace lem {

namespace {

std::uint64_t bits(double x) {
  std::uint64_t b = 0;
  std::memcpy(&b, &x, 8);
  return b;
}

// Options that do not enter a scope (beyond OptionKind::outside).
bool left_out(const std::string& line, FingerprintScope scope) {
  const auto is = [&](const char* name) { return line.rfind(std::string(name) + "=", 0) == 0; };
  const auto under = [&](const char* prefix) { return line.rfind(prefix, 0) == 0; };
  const bool end = is("-fracture_max_steps") || is("-fracture_stop_fraction") ||
                   is("-fracture_max_strain_ratio");
  if (scope == FingerprintScope::checkpoint) return end;
  if (scope == FingerprintScope::calibration)
    return end || is("-fracture_sigma_unit") || is("-fracture_modulus_unit") ||
           is("-fracture_calibrate") || under("-output_") ||
           (under("-phase_") && !is("-phase_e_p") && !is("-phase_sigma_p"));
  return false;
}

}  // namespace

std::string lattice_fingerprint(const DistributedLattice& l) {
  std::uint64_t content = 0;
  for (int n = 0; n < l.owned; ++n) {
    std::uint64_t h = mix64(static_cast<std::uint64_t>(l.node_id[n]));
    for (int a = 0; a < 3; ++a) h = mix64(h ^ bits(l.coords[n][a]));
    h = mix64(h ^ (std::uint64_t(l.dof_flags[n]) << 8 | l.faces[n]));
    if (!l.node_volume.empty()) h = mix64(h ^ bits(l.node_volume[n]));
    if (!l.node_particle.empty()) h = mix64(h ^ static_cast<std::uint64_t>(l.node_particle[n]));
    content += h;
  }
  // Exact sums (any order gives the same bits) of the values ExactSum takes;
  // absurdly large ones (-lattice_k up to 1e300) summed plainly beside.
  ExactSum stiffness, strength;
  double large[2] = {0, 0}, large_total[2] = {0, 0};
  const auto add = [&](ExactSum& sum, double& beside, double x) {
    if (std::fabs(x) < 1e9)
      sum.add(x);
    else
      beside += x;
  };
  for (int b = 0; b < l.local_bonds(); ++b) {
    if (!l.bond_reported[b]) continue;
    const std::int64_t i = l.node_id[l.bond_ends[b][0]], j = l.node_id[l.bond_ends[b][1]];
    std::uint64_t h = mix64(~static_cast<std::uint64_t>(l.bond_id[b]));
    h = mix64(h ^ static_cast<std::uint64_t>(std::min(i, j)));
    h = mix64(h ^ static_cast<std::uint64_t>(std::max(i, j)));
    if (!l.bond_tag.empty()) h = mix64(h ^ l.bond_tag[b]);
    content += h;
    add(stiffness, large[0], l.bond_stiffness[b]);
    if (!l.bond_strength.empty()) add(strength, large[1], l.bond_strength[b]);
  }
  std::uint64_t total = 0;
  MPI_Allreduce(&content, &total, 1, MPI_UINT64_T, MPI_SUM, l.comm);
  MPI_Allreduce(large, large_total, 2, MPI_DOUBLE, MPI_SUM, l.comm);
  std::ostringstream s;
  s.precision(17);
  s << "nodes=" << l.global_nodes << "\nbonds=" << l.global_bonds << "\nsample_content=" << total
    << "\nbond_length_mean=" << l.mean_bond_length
    << "\nstiffness_total=" << stiffness.all_ranks(l.comm).value() + large_total[0]
    << "\nstrength_total=" << strength.all_ranks(l.comm).value() + large_total[1] << "\n";
  return s.str();
}

std::string fracture_fingerprint(const DistributedLattice& l, const FractureOptions& o,
                                 FingerprintScope scope) {
  int ranks = 1;
  MPI_Comm_size(l.comm, &ranks);
  std::ostringstream s;
  s.precision(17);
  s << "ranks=" << ranks << "\n"
    << lattice_fingerprint(l) << "increment=" << o.increment << "\nbreak_rule=" << o.break_rule
    << "\nskip_idle=" << o.skip_idle << "\npc_rebuild_ruptures=" << o.rebuild_after_ruptures
    << "\npc_rebuild_growth=" << o.rebuild_iteration_growth << "\nrelaxation=" << o.relaxation
    << "\n";
  s << registered_fingerprint(o.break_rule, o.relaxation);  // their own options' lines
  s << "decision_safety=" << o.decision_safety << "\ndecision_interval=" << o.decision_interval
    << "\ndecided_closing=" << o.decided_closing << "\ntie_band=" << o.tie_band
    << "\ntie_rtol=" << o.tie_rtol << "\ntie_solve=continued\n";
  if (scope == FingerprintScope::calibration)
    s << "stop_fraction=" << o.stop_fraction << "\nstop_within_step=" << o.stop_within_step << "\n";
  std::istringstream options(option_lines(kAllOptionKinds));
  for (std::string line; std::getline(options, line);)
    if (!left_out(line, scope)) s << line << "\n";
  return s.str();
}

}  // namespace lem
