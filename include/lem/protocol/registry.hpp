// Break rules and relaxation schemes, by name (docs/developer/extending.md).
//
// The built-in ones are listed in src/protocol/registry.cpp.  A program adds
// its own with register_break_rule / register_relaxation before it reads its
// options.  An entry holds all that its rule or scheme adds to a run:
//   the name    -fracture_break_rule / -fracture_relaxation accept it, -help
//               lists it with its help string;
//   options     read with the protocol's (read_options), listed by -help, a
//               misspelt one an error;
//   fingerprint lines that identify its results: a checkpoint, a result or a
//               calibration of other values is refused, naming the line;
//   summary     fields of lem_fracture's summary (name, unit, meaning), with
//               the values of the object's report() (0 in runs of another
//               rule or scheme), listed in
//               docs/reference/fracture-outputs.md for the built-in ones.
// The run names none of it: a new rule or scheme is its class and its entry.
#pragma once

#include "lem/base/options.hpp"
#include "lem/base/summary.hpp"
#include "lem/protocol/break_rule.hpp"
#include "lem/protocol/relaxation.hpp"

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace lem {

struct BreakRuleEntry {
  std::string name;  // the word of -fracture_break_rule
  std::string help;  // what it breaks, for -help
  std::function<std::unique_ptr<BreakRule>()> make;
  /// Reads the rule's own options into its own storage (which `make`
  /// shares), in the group of -fracture_break_rule.  Called for every
  /// registered rule, whichever is chosen.  None if empty.
  std::function<void(OptionGroup&)> read_options = {};
  /// Lines "key=value\n" for the fingerprint of checkpoints, results and
  /// calibrations when the rule is chosen: its options that change results.
  std::function<std::string()> fingerprint = {};
  /// Its entries of the summary, each given by BreakRule::report.
  std::vector<SummaryField> summary = {};
};

struct RelaxationEntry {
  std::string name;  // the word of -fracture_relaxation
  std::string help;
  std::function<std::unique_ptr<Relaxation>(const RelaxationParts&)> make;
  /// Reads the scheme's own options into its own storage (which `make`
  /// shares), in the group "Relaxation after ruptures".  Called for every
  /// registered scheme, whichever is chosen, so that -help lists them and a
  /// misspelt one is an error.  None if empty.
  std::function<void(OptionGroup&)> read_options = {};
  /// Lines "key=value\n" for the fingerprint of checkpoints, results and
  /// calibrations when the scheme is chosen: its options that change results
  /// (none if empty).
  std::function<std::string()> fingerprint = {};
  /// Its entries of the summary, each given by Relaxation::report.
  std::vector<SummaryField> summary = {};
};

/// Every break rule and relaxation scheme, built-in ones first.
const std::vector<BreakRuleEntry>& break_rules();
const std::vector<RelaxationEntry>& relaxation_schemes();

/// Add one (std::invalid_argument if the name is taken or empty, or one of
/// its summary fields is another entry's).
void register_break_rule(BreakRuleEntry entry);
void register_relaxation(RelaxationEntry entry);

/// The one of that name (std::invalid_argument if there is none: the
/// options accept registered names only).
const BreakRuleEntry& break_rule_named(const std::string& name);
const RelaxationEntry& relaxation_named(const std::string& name);

/// The fingerprint lines of the rule and the scheme of these names.
std::string registered_fingerprint(const std::string& break_rule, const std::string& relaxation);
/// The summary fields of every rule, then of every scheme, in registry
/// order: every summary has them all, so that a study's table holds runs of
/// any rule and scheme.
std::vector<SummaryField> registered_summary_fields();

}  // namespace lem
