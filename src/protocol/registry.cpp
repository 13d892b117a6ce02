#include "lem/protocol/registry.hpp"

#include "lem/protocol/local_relaxation.hpp"

#include <algorithm>
#include <cstring>
#include <stdexcept>

namespace lem {

namespace {

// The built-in ones; a new one in the code base is its file and a line here.
std::vector<BreakRuleEntry>& rule_table() {
  static std::vector<BreakRuleEntry> table = {
      {"all", "every critical bond (the paper)", make_all_critical_rule},
      {"most_critical", "the most critical bond only (largest force over threshold)",
       make_most_critical_rule}};
  return table;
}

std::vector<RelaxationEntry>& scheme_table() {
  static std::vector<RelaxationEntry> table = {
      {"global", "every relaxation cycle is a global solve (the reference)",
       [](const RelaxationParts& parts) -> std::unique_ptr<Relaxation> {
         return std::make_unique<GlobalRelaxation>(parts);
       }},
      local_relaxation_entry()};
  return table;
}

// A summary field of `entry` that some registered entry already declares
// (nullptr if none).
const char* taken_field(const std::vector<SummaryField>& fields) {
  const std::vector<SummaryField> all = registered_summary_fields();
  for (const SummaryField& f : fields)
    for (const SummaryField& g : all)
      if (std::strcmp(f.name, g.name) == 0) return f.name;
  return nullptr;
}

template <class Entry>
void add(std::vector<Entry>& table, Entry entry, const char* kind) {
  const bool taken =
      std::any_of(table.begin(), table.end(), [&](const Entry& e) { return e.name == entry.name; });
  if (entry.name.empty() || taken || !entry.make)
    throw std::invalid_argument(std::string(kind) + " '" + entry.name +
                                "': " + (taken ? "the name is taken" : "no name or no factory"));
  if (const char* field = taken_field(entry.summary))
    throw std::invalid_argument(std::string(kind) + " '" + entry.name + "': the summary field '" +
                                field + "' is declared by another entry");
  table.push_back(std::move(entry));
}

template <class Entry>
const Entry& named(const std::vector<Entry>& table, const std::string& name, const char* kind) {
  for (const Entry& e : table)
    if (e.name == name) return e;
  throw std::invalid_argument(std::string("no ") + kind + " named '" + name + "'");
}

}  // namespace

const std::vector<BreakRuleEntry>& break_rules() { return rule_table(); }
const std::vector<RelaxationEntry>& relaxation_schemes() { return scheme_table(); }

void register_break_rule(BreakRuleEntry entry) {
  add(rule_table(), std::move(entry), "break rule");
}
void register_relaxation(RelaxationEntry entry) {
  add(scheme_table(), std::move(entry), "relaxation scheme");
}

const BreakRuleEntry& break_rule_named(const std::string& name) {
  return named(rule_table(), name, "break rule");
}
const RelaxationEntry& relaxation_named(const std::string& name) {
  return named(scheme_table(), name, "relaxation scheme");
}

std::string registered_fingerprint(const std::string& break_rule, const std::string& relaxation) {
  const BreakRuleEntry& rule = break_rule_named(break_rule);
  const RelaxationEntry& scheme = relaxation_named(relaxation);
  return (rule.fingerprint ? rule.fingerprint() : std::string()) +
         (scheme.fingerprint ? scheme.fingerprint() : std::string());
}

std::vector<SummaryField> registered_summary_fields() {
  std::vector<SummaryField> fields;
  for (const BreakRuleEntry& e : rule_table())
    fields.insert(fields.end(), e.summary.begin(), e.summary.end());
  for (const RelaxationEntry& e : scheme_table())
    fields.insert(fields.end(), e.summary.begin(), e.summary.end());
  return fields;
}

}  // namespace lem
