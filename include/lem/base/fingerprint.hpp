// What identifies a result, a checkpoint and a calibration: one rule, one
// place (docs/reference/result-folder.md, "manifest.txt and the commit").
//
// A fingerprint is text, one "key=value" line per thing the product depends
// on.  The rule: every option the program read, and every input datum,
// changes the product, unless the option is one of those that say only
// where and how a run is kept, not what it computes (option_kind(): the
// output folder, checkpoints, warning thresholds, the set-up and the name of
// the sample file (-sample_parallel, -sample_file: the sample enters by its
// content), PETSc's monitors and viewers).  The options enter by name and value (the default
// when not given); the inputs by content (the lattice lines of
// lem/protocol/fingerprint.hpp).
//
// Two fingerprints are compared key by key, and a refusal names each key
// that differs, is missing or is new.  Solver options (OptionKind::solver)
// change results to the solver's tolerance: they identify results and
// calibrations, while a checkpoint may be resumed under others (the
// recovery from a failed solve), which the run then says.
#pragma once

#include <string>

namespace lem {

enum class OptionKind {
  outside,  // where and how the run is kept: not part of any fingerprint
  solver,   // the linear solver: results equal to its tolerance
  physics,  // everything else: what is computed
};

/// The kind of option `name` (with its dash: "-ksp_rtol").
OptionKind option_kind(const std::string& name);

/// The options that identify a product, as sorted "-name=value" lines (the
/// name as typed, lower case; numbers written in one canonical form): every option
/// the program has read (given or default) whose kind is in `kinds`, and
/// every solver option given to PETSc that the program does not read itself
/// (-pc_gamg_threshold ...).  `kinds` is a set of bits (1 << OptionKind).
/// The same on every rank.
std::string option_lines(unsigned kinds);
constexpr unsigned option_bits(OptionKind k) { return 1u << static_cast<unsigned>(k); }
constexpr unsigned kAllOptionKinds =
    option_bits(OptionKind::solver) | option_bits(OptionKind::physics);

/// How two fingerprints may differ.
struct FingerprintDifference {
  std::string differs;         // "\n  <label>: key=... this run: key=..." lines ("" if none)
  std::string solver_changes;  // the same for solver lines, when allowed to differ
  int other_ranks = 0;         // theirs when the rank count differs (0 otherwise)
};

/// Compare `theirs` (stored) with `ours` key by key.  The rank count may
/// always differ; a few derived sums (mean bond length, stiffness and
/// strength totals) agree to 1e-10 relative (a set-up on other ranks sums in
/// another order); the lines of solver options ("-ksp_rtol=...") go to
/// `solver_changes` instead of `differs` when `solver_may_differ`.
FingerprintDifference compare_fingerprints(const std::string& theirs, const std::string& ours,
                                           const char* label, bool solver_may_differ = false);

/// The fingerprint without its "ranks=" line (a calibration holds on any
/// rank count).
std::string without_ranks(const std::string& fingerprint);
/// The text a key (a file name) is made from: without the rank count, the
/// sums compared to a tolerance rounded to 10 digits, so that another
/// set-up of the same sample finds the same key (and a rounding that falls
/// apart only misses the file: the file's own fingerprint is compared).
std::string key_text(const std::string& fingerprint);

}  // namespace lem
