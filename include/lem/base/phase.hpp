// Bond phases of the paper (sect. 2.2): particle, matrix, void, and the
// particle-particle and particle-matrix interfaces.  The one list of their
// codes, names and default properties; the codes are stored in sample files
// and field files (/bonds/phase), so they never change.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>

namespace lem {

enum class Phase : std::uint8_t { p = 0, m = 1, v = 2, pp = 3, pm = 4 };
inline constexpr int kPhaseCount = 5;

/// Short names, in code order (option suffixes: -phase_E_<name>, and the
/// column names of results: bonds_<name>, broken_<name>).
inline constexpr std::array<const char*, kPhaseCount> kPhaseNames{"p", "m", "v", "pp", "pm"};

inline const char* phase_name(Phase phase) { return kPhaseNames[static_cast<int>(phase)]; }

/// The phase called `name`, or nothing.
inline std::optional<Phase> parse_phase(std::string_view name) {
  for (int k = 0; k < kPhaseCount; ++k)
    if (name == kPhaseNames[k]) return static_cast<Phase>(k);
  return std::nullopt;
}

/// Defaults in the paper's stress units (E = k/a, sigma = f/a^2): E^p = 3 E^m
/// = 3 E^pm, sigma^p = sigma^m, sigma^pp = 0 (bare contacts).  The breaking
/// strain sigma/E of a particle bond is 1/300: the paper's peak at a strain
/// of ~4e-3 with increments of 3e-4 a (sect. 3) needs thresholds of this
/// order; the paper gives only ratios (sigma^pm from 0.2 to 1.4 sigma^p), so
/// 0.6 sigma^p is our middle default.
inline constexpr std::array<double, kPhaseCount> kDefaultPhaseModulus{3.0, 1.0, 0.0, 1.0, 1.0};
inline constexpr std::array<double, kPhaseCount> kDefaultPhaseStrength{0.01, 0.01, 0.0, 0.0, 0.006};

}  // namespace lem
