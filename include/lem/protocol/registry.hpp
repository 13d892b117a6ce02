// Break rules and relaxation schemes, by name (docs/developer/extending.md).
//
// The built-in ones are listed in src/protocol/registry.cpp.  A program adds
// its own with register_break_rule / register_relaxation before it reads its
// options: -fracture_break_rule and -fracture_relaxation then accept the new
// name (and -help lists it), and the fingerprint of checkpoints and results
// and the summary name it like the others.
#pragma once

#include "lem/base/options.hpp"
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
  /// Lines "key=value\n" for the fingerprint of checkpoints and results: the
  /// options of the scheme that change results (none if empty).
  std::function<std::string()> fingerprint = {};
};

/// Every break rule and relaxation scheme, built-in ones first.
const std::vector<BreakRuleEntry>& break_rules();
const std::vector<RelaxationEntry>& relaxation_schemes();

/// Add one (std::invalid_argument if the name is taken or empty).
void register_break_rule(BreakRuleEntry entry);
void register_relaxation(RelaxationEntry entry);

/// The one of that name (std::invalid_argument if there is none: the
/// options accept registered names only).
const BreakRuleEntry& break_rule_named(const std::string& name);
const RelaxationEntry& relaxation_named(const std::string& name);

}  // namespace lem
