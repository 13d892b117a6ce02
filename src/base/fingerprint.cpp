#include "lem/base/fingerprint.hpp"

#include "lem/base/error.hpp"
#include "lem/base/options.hpp"

#include <petscsys.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <utility>
#include <sstream>
#include <vector>

namespace lem {

namespace {

bool starts_with(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }
bool has(const std::string& s, const char* part) { return s.find(part) != std::string::npos; }

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// Options that say where and how a run is kept, not what it computes.
const char* const kOutsideNames[] = {"-output_dir",
                                     "-output_overwrite",
                                     "-output_write_grace",
                                     "-fracture_strict",
                                     "-fracture_calibration_file",
                                     "-sample_parallel",
                                     "-sample_file",
                                     "-help",
                                     "-version",
                                     "-skip_petscrc",
                                     "-options_file",
                                     "-options_file_yaml",
                                     "-no_signal_handler"};
// (-solver_spectrum_*: the probe's extra solves leave the run as it is.)
const char* const kOutsidePrefixes[] = {"-checkpoint_",
                                        "-solver_spectrum_",
                                        "-fracture_warn_",
                                        "-log",
                                        "-info",
                                        "-malloc",
                                        "-options_",
                                        "-on_error",
                                        "-history",
                                        "-viewer",
                                        "-memory_view",
                                        "-fp_trap",
                                        "-debugger",
                                        "-start_in_debugger",
                                        "-stop_for_debugger",
                                        "-objects_dump",
                                        "-citations",
                                        "-display",
                                        "-nox"};
// What PETSc prints while it solves, not what it solves.
const char* const kOutsideParts[] = {"_monitor", "_view", "_converged_reason",      "_draw",
                                     "_plot_",   "_log",  "_error_if_not_converged"};
const char* const kSolverPrefixes[] = {"-ksp_",       "-pc_",        "-mg_",
                                       "-mat_",       "-fallback_",  "-patch_",
                                       "-sub_",       "-redundant_", "-deflation_coarse_",
                                       "-telescope_", "-solver_"};

// One written form per value: numbers in their shortest exact form, booleans as true/false (a
// bare flag is true), so that "-ksp_rtol 1.0e-8" and the default 1e-8 agree.
std::string canonical(const std::string& value, bool given) {
  if (given && value.empty()) return "true";
  const std::string v = lower(value);
  if (v == "true" || v == "yes" || v == "on") return "true";
  if (v == "false" || v == "no" || v == "off") return "false";
  char* end = nullptr;
  const double x = std::strtod(value.c_str(), &end);
  if (!value.empty() && end == value.c_str() + value.size() && std::isfinite(x)) {
    char text[40];  // the shortest text that reads back as x
    for (int digits = 15; digits <= 17; ++digits) {
      std::snprintf(text, sizeof text, "%.*g", digits, x);
      if (std::strtod(text, nullptr) == x) break;
    }
    return text;
  }
  return value;
}

// The options given to PETSc, name (lower case, with its dash) to value.
std::map<std::string, std::string> petsc_database() {
  std::map<std::string, std::string> out;
  char* all = nullptr;
  if (PetscOptionsGetAll(nullptr, &all) != 0 || !all) return out;
  std::istringstream words(all);
  PetscFree(all);
  std::string name;
  for (std::string w; words >> w;) {
    const bool option =
        w.size() > 1 && w[0] == '-' && std::isalpha(static_cast<unsigned char>(w[1]));
    if (option) {
      name = lower(w);
      out[name] = "";
    } else if (!name.empty()) {
      out[name] = w;
      name.clear();
    }
  }
  return out;
}

// key=value lines by key.
std::map<std::string, std::string> keyed(const std::string& text, std::vector<std::string>& order) {
  std::map<std::string, std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (line.empty()) continue;
    const std::size_t eq = line.find('=');
    const std::string key = line.substr(0, eq);
    if (!out.count(key)) order.push_back(key);
    out[key] = eq == std::string::npos ? "" : line.substr(eq + 1);
  }
  return out;
}

// Sums over the sample that a set-up on other ranks adds in another order.
bool tolerant(const std::string& key) {
  return key == "bond_length_mean" || key == "stiffness_total" || key == "strength_total";
}

// Options removed from the code, with the value they had when unused: a
// result, calibration or checkpoint written before the removal carries
// this line, and is still the same run; one written with another value is
// not.  (-solver_soft_node_deflation: removed, measured and lost;
// docs/notes/slow-modes.md.)
const std::pair<const char*, const char*> kRetiredDefaults[] = {
    {"-solver_soft_node_deflation", "0"}};

bool retired_default(const std::string& key, const std::string& value) {
  for (const auto& [name, unused] : kRetiredDefaults)
    if (key == name && value == unused) return true;
  return false;
}

bool close_enough(const std::string& a, const std::string& b) {
  char* ea = nullptr;
  char* eb = nullptr;
  const double x = std::strtod(a.c_str(), &ea), y = std::strtod(b.c_str(), &eb);
  if (*ea != '\0' || *eb != '\0' || a.empty() || b.empty()) return false;
  return std::fabs(x - y) <= 1e-10 * std::max(std::fabs(x), std::fabs(y));
}

}  // namespace

OptionKind option_kind(const std::string& raw) {
  const std::string name = lower(raw);
  for (const char* n : kOutsideNames)
    if (name == n) return OptionKind::outside;
  for (const char* p : kOutsidePrefixes)
    if (starts_with(name, p)) return OptionKind::outside;
  const bool solver = std::any_of(std::begin(kSolverPrefixes), std::end(kSolverPrefixes),
                                  [&](const char* p) { return starts_with(name, p); });
  if (solver) {
    for (const char* part : kOutsideParts)
      if (has(name, part)) return OptionKind::outside;
    return OptionKind::solver;
  }
  return OptionKind::physics;
}

std::string option_lines(unsigned kinds) {
  const auto wanted = [&](const std::string& name) {
    return (kinds & option_bits(option_kind(name))) != 0;
  };
  const std::map<std::string, std::string> database = petsc_database();
  std::map<std::string, std::string> lines;
  for (const OptionRecord& r : registered_options()) {
    if (!wanted(r.name)) continue;
    const std::string name = lower(r.name);
    // A default the program sets on PETSc's objects: PETSc reads the option.
    const auto given = database.find(name);
    if (r.petsc_default && given != database.end())
      lines[name] = canonical(given->second, true);
    else
      lines[name] = canonical(r.given ? r.value : r.default_value, r.given);
  }
  for (const auto& [name, value] : database)
    if (option_kind(name) == OptionKind::solver && wanted(name) && !lines.count(name))
      lines[name] = canonical(value, true);
  std::string text;
  for (const auto& [name, value] : lines) text += name + "=" + value + "\n";
  return text;
}

FingerprintDifference compare_fingerprints(const std::string& theirs, const std::string& ours,
                                           const char* label, bool solver_may_differ) {
  std::vector<std::string> order_a, order_b;
  const auto a = keyed(theirs, order_a), b = keyed(ours, order_b);
  for (const auto& key : order_a)
    if (!b.count(key)) order_b.push_back(key);
  FingerprintDifference d;
  const auto shown = [](const std::map<std::string, std::string>& m, const std::string& key) {
    const auto it = m.find(key);
    return it == m.end() ? key + " not set" : key + "=" + it->second;
  };
  for (const auto& key : order_b) {
    const auto x = a.find(key), y = b.find(key);
    if (x != a.end() && y != b.end() &&
        (x->second == y->second || (tolerant(key) && close_enough(x->second, y->second))))
      continue;
    if (x != a.end() && y == b.end() && retired_default(key, x->second)) continue;
    if (key == "ranks" && x != a.end() && y != b.end()) {
      d.other_ranks = std::atoi(x->second.c_str());
      continue;
    }
    const std::string line =
        "\n  " + std::string(label) + ": " + shown(a, key) + "   this run: " + shown(b, key);
    if (solver_may_differ && starts_with(key, "-") && option_kind(key) == OptionKind::solver)
      d.solver_changes += line;
    else
      d.differs += line;
  }
  return d;
}

std::string key_text(const std::string& fingerprint) {
  std::istringstream in(fingerprint);
  std::string kept;
  for (std::string line; std::getline(in, line);) {
    if (starts_with(line, "ranks=")) continue;
    const std::size_t eq = line.find('=');
    if (eq != std::string::npos && tolerant(line.substr(0, eq))) {
      char text[40];
      std::snprintf(text, sizeof text, "%.10g", std::strtod(line.c_str() + eq + 1, nullptr));
      line = line.substr(0, eq + 1) + text;
    }
    kept += line + "\n";
  }
  return kept;
}

std::string without_ranks(const std::string& fingerprint) {
  std::istringstream in(fingerprint);
  std::string kept;
  for (std::string line; std::getline(in, line);)
    if (!starts_with(line, "ranks=")) kept += line + "\n";
  return kept;
}

}  // namespace lem
