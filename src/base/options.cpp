#include "lem/base/options.hpp"

#include "lem/base/error.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <sstream>

namespace lem {
namespace {

std::vector<OptionRecord>& registry() {
  static std::vector<OptionRecord> records;
  return records;
}

// PETSc compares option names without regard to case; so do we.
std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

OptionRecord* find_record(const std::string& name) {
  const std::string key = lower(name);
  for (auto& r : registry())
    if (lower(r.name) == key) return &r;
  return nullptr;
}

template <class T>
std::string text_of(const T& value) {
  std::ostringstream s;
  s << value;
  return s.str();
}

std::string describe_range(double lo, double hi, bool open_lo, bool open_hi) {
  std::ostringstream s;
  s << (open_lo ? "(" : "[") << lo << ", " << hi << (open_hi ? ")" : "]");
  return s.str();
}

// std::from_chars over the whole of `text`: decimal digits (reals also in
// scientific notation, inf, nan), one optional sign, nothing else — no hex,
// no blanks, no trailing characters.
template <class T>
bool parse_whole(const std::string& text, T& value, std::errc& error) {
  const char* first = text.data();
  const char* const last = first + text.size();
  if (first != last && *first == '+' && ++first != last && *first == '-') return false;
  const auto result = std::from_chars(first, last, value);
  error = result.ec;
  return first != last && result.ptr == last;
}

// A whole string as a real number (inf and nan parse; range checks reject
// them).  Beyond the range of a double it reads as +-inf or 0, as strtod has it.
bool parse_real(const std::string& text, double& value) {
  std::errc error{};
  if (!parse_whole(text, value, error)) return false;
  if (error == std::errc::result_out_of_range) value = std::strtod(text.c_str(), nullptr);
  return error == std::errc() || error == std::errc::result_out_of_range;
}

// Prefixes of options that PETSc itself (or MPI start-up) may consume; they
// are checked by check_unused_options(), once PETSc has read them.
const char* const kPetscPrefixes[] = {"ksp_",
                                      "pc_",
                                      "mat_",
                                      "vec_",
                                      "fallback_",
                                      "patch_",
                                      "deflation_coarse_",
                                      "log",
                                      "options_",
                                      "help",
                                      "malloc",
                                      "info",
                                      "on_error",
                                      "history",
                                      "viewer",
                                      "fp_trap",
                                      "no_signal_handler",
                                      "check_pointer",
                                      "memory_view",
                                      "objects_dump",
                                      "skip_petscrc",
                                      "start_in_debugger",
                                      "debugger",
                                      "stop_for_debugger",
                                      "display",
                                      "use_gpu_aware_mpi",
                                      "citations",
                                      "version",
                                      "petsc",
                                      "sys",
                                      "draw",
                                      "nox",
                                      "mg_",
                                      "sub_",
                                      "redundant_",
                                      "telescope_",
                                      "is_",
                                      "sf_",
                                      "error_output",
                                      "saws",
                                      "python",
                                      "get_total_flops",
                                      "checkstack"};

// Options that the objects of ElasticSystem read when they are created
// (KSPSetFromOptions, PCSetFromOptions, including -fallback_*): these can be
// checked before the first solve ...
const char* const kReadAtCreation[] = {"ksp_", "pc_", "fallback_"};
// ... except the ones PETSc reads later.  GAMG builds its levels in PCSetUp:
// only then does it read -pc_mg_* (PCSetFromOptions_MG cannot run before the
// levels exist) and the level smoothers' and coarse solver's -mg_levels_*
// and -mg_coarse_* (outside kReadAtCreation anyway); some PCs define their
// parts at set-up too (fieldsplit, BDDC, patch, HPDDM, and the -sub_*
// solvers of block Jacobi and ASM).  -mat_* options are left to the later
// check as a whole: the coarsening, repartitioning, Galerkin products and
// factorisation packages (-mat_mumps_* ...) read theirs at set-up.  Viewers
// (-ksp_view, ...) and convergence reports are read when a solve ends.
const char* const kReadLater[] = {"pc_mg_",   "pc_gamg_esteig_", "pc_fieldsplit_",
                                  "pc_bddc_", "pc_patch_",       "pc_hpddm_"};
bool read_later(const std::string& bare) {
  for (const char* p : kReadLater)
    if (bare.rfind(p, 0) == 0) return true;
  for (const char* part : {"view", "converged_", "compute_", "plot_"})
    if (bare.find(part) != std::string::npos) return true;
  return false;
}

bool has_prefix(const std::string& s, const std::string& p) { return s.rfind(p, 0) == 0; }

template <std::size_t N>
bool has_any_prefix(const std::string& s, const char* const (&prefixes)[N]) {
  return std::any_of(std::begin(prefixes), std::end(prefixes),
                     [&](const char* p) { return has_prefix(s, p); });
}

// The database as (name, value) pairs, names with the dash; read without
// marking anything used.
std::vector<std::pair<std::string, std::string>> database() {
  char* all = nullptr;
  LEM_PETSC(PetscOptionsGetAll(nullptr, &all));
  std::istringstream in(all ? all : "");
  LEM_PETSC(PetscFree(all));
  std::vector<std::pair<std::string, std::string>> options;
  std::string token;
  while (in >> token) {
    // Values may be negative numbers; names start with '-' and a letter.
    if (token.size() > 1 && token[0] == '-' && std::isalpha(static_cast<unsigned char>(token[1])))
      options.emplace_back(token, "");
    else if (!options.empty())
      options.back().second += (options.back().second.empty() ? "" : " ") + token;
  }
  return options;
}

std::vector<std::string> option_names() {
  std::vector<std::string> names;
  for (const auto& option : database()) names.push_back(option.first);
  return names;
}

// Edits (insert, delete, substitute, swap two neighbours) from a to b.
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i)
    for (std::size_t j = 1; j <= b.size(); ++j) {
      d[i][j] =
          std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] != b[j - 1])});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[a.size()][b.size()];
}

// The candidate closest to `word`, if it is close enough to be a typo.
const std::string* nearest(const std::string& word, const std::vector<std::string>& candidates) {
  const std::string* best = nullptr;
  std::size_t best_distance = 4;  // more edits than this is not a typo
  for (const auto& c : candidates) {
    const std::size_t d = edit_distance(lower(word), lower(c));
    if (d < best_distance) best_distance = d, best = &c;
  }
  return best;
}

// " (did you mean -x?)" for the closest registered name, if it is close.
std::string suggestion(const std::string& name) {
  std::vector<std::string> names;
  for (const auto& r : registry()) names.push_back(r.name);
  const std::string* best = nearest(name, names);
  return best ? " (did you mean " + *best + "?)" : "";
}

// Words of `text` in lines of at most `width` characters, each indented.
std::string wrapped(const std::string& text, std::size_t indent, std::size_t width) {
  std::istringstream in(text);
  std::string out, line, word;
  while (in >> word) {
    if (!line.empty() && line.size() + 1 + word.size() > width - indent) {
      out += std::string(indent, ' ') + line + "\n";
      line.clear();
    }
    if (!line.empty()) line += ' ';
    line += word;
  }
  if (!line.empty()) out += std::string(indent, ' ') + line + "\n";
  return out;
}

// The registry as -help shows it: by group, in reading order.
std::string registry_as_help() {
  std::vector<std::string> groups;
  for (const auto& r : registry())
    if (std::find(groups.begin(), groups.end(), r.group) == groups.end()) groups.push_back(r.group);
  std::string text = "\nOptions of this program (value now, and the default if it differs):\n";
  for (const auto& group : groups) {
    text += '\n';
    text += group;
    text += ":\n";
    for (const auto& r : registry()) {
      if (r.group != group) continue;
      auto shown = [](const std::string& v) { return v.empty() ? std::string("\"\"") : v; };
      std::ostringstream line;
      line << "  " << r.name << " <" << shown(r.given ? r.value : r.default_value) << ">";
      if (r.given && r.value != r.default_value)
        line << " (default " << shown(r.default_value) << ")";
      text += line.str();
      text += '\n';
      text += wrapped(r.help, 6, 96);
    }
  }
  return text;
}

}  // namespace

const std::vector<OptionRecord>& registered_options() { return registry(); }

OptionGroup::OptionGroup(MPI_Comm comm, const char* title) : comm_(comm), title_(title) {}

bool OptionGroup::lookup(const char* name, std::string& text, const char* help) const {
  // FindPair tells "-name" alone (a null value) from "-name value"; the
  // string getters would give "" for both.
  const char* value = nullptr;
  PetscBool set = PETSC_FALSE;
  LEM_PETSC(PetscOptionsFindPair(nullptr, nullptr, name, &value, &set));
  text = set && value ? value : "";
  if (set && help && text.empty())
    throw InputError("option " + std::string(name) + " is given without a value (" + help + ")");
  return set == PETSC_TRUE;
}

void OptionGroup::record(const char* name, const char* help, std::string def,
                         const std::string& text, bool given, bool petsc_default) {
  if (OptionRecord* r = find_record(name)) {  // read again (e.g. a second system)
    r->value = text;
    r->given = given;
    return;
  }
  registry().push_back({title_, name, help, std::move(def), text, given, petsc_default});
}

double OptionGroup::real(const char* name, const char* help, double def, double lo, double hi,
                         bool open_lo, bool open_hi) {
  std::string text;
  const bool set = lookup(name, text, help);
  record(name, help, text_of(def), text, set);
  double value = def;
  if (set && !parse_real(text, value))
    throw InputError("option " + std::string(name) + " = '" + text + "' is not a number: " +
                     "allowed " + describe_range(lo, hi, open_lo, open_hi) + " (" + help + ")");
  const bool below = open_lo ? !(value > lo) : !(value >= lo);
  const bool above = open_hi ? !(value < hi) : !(value <= hi);
  if (below || above) {
    std::ostringstream s;
    s << "option " << name << " = " << value << " is out of range: allowed "
      << describe_range(lo, hi, open_lo, open_hi) << " (" << help << ")";
    throw InputError(s.str());
  }
  return value;
}

std::int64_t OptionGroup::integer(const char* name, const char* help, std::int64_t def,
                                  std::int64_t lo, std::int64_t hi) {
  std::string text;
  const bool set = lookup(name, text, help);
  record(name, help, std::to_string(def), text, set);
  if (!set) return def;
  const std::string allowed =
      "allowed [" + std::to_string(lo) + ", " + std::to_string(hi) + "] (" + help + ")";
  const std::string given = "option " + std::string(name) + " = ";
  // Plain integers first; failing that, a real with an integer value
  // ("1e6"), so that a huge value is out of range instead of wrapping.
  std::int64_t value = 0;
  std::errc error{};
  if (!parse_whole(text, value, error) || error != std::errc()) {
    double real = 0;
    if (!parse_real(text, real))
      throw InputError(given + "'" + text + "' is not a number: " + allowed);
    if (std::isfinite(real) && real != std::floor(real))
      throw InputError(given + "'" + text + "' is not an integer: " + allowed);
    // 2^63 itself does not fit: compare before converting.
    if (!(real >= static_cast<double>(lo) && real <= static_cast<double>(hi) && real < 0x1p63))
      throw InputError(given + text + " is out of range: " + allowed);
    value = static_cast<std::int64_t>(real);
  }
  if (value < lo || value > hi) throw InputError(given + text + " is out of range: " + allowed);
  return value;
}

bool OptionGroup::flag(const char* name, const char* help, bool def) {
  std::string text;
  const bool set = lookup(name, text, nullptr);  // a bare -name means true
  record(name, help, def ? "true" : "false", text, set);
  if (!set) return def;
  const std::string word = lower(text);
  // The words PETSc takes for a boolean; a bare -name means true.
  for (const char* yes : {"", "true", "yes", "on", "1"})
    if (word == yes) return true;
  for (const char* no : {"false", "no", "off", "0"})
    if (word == no) return false;
  throw InputError("option " + std::string(name) + " = '" + text +
                   "' is not a boolean: allowed "
                   "true or false (also yes/no, on/off, 1/0) (" +
                   help + ")");
}

std::string OptionGroup::string(const char* name, const char* help, const std::string& def) {
  std::string text;
  const bool set = lookup(name, text, help);
  record(name, help, def, text, set);
  return set ? text : def;
}

std::size_t OptionGroup::choice_index(const char* name, const char* help,
                                      const std::vector<std::string>& words,
                                      std::size_t def_index) {
  std::string all;
  for (const auto& w : words) {
    if (!all.empty()) all += '|';
    all += w;
  }
  const std::string described = std::string(help) + " (" + all + ")";
  std::string text;
  const bool set = lookup(name, text, described.c_str());
  record(name, described.c_str(), words[def_index], text, set);
  if (!set) return def_index;
  const auto it = std::find(words.begin(), words.end(), text);
  if (it == words.end())
    throw InputError("option " + std::string(name) + " = '" + text + "' is not one of: " + all);
  return static_cast<std::size_t>(it - words.begin());
}

std::vector<double> OptionGroup::positive_reals(const char* name, const char* help,
                                                const std::vector<double>& def, bool any_count) {
  std::string def_text;
  for (double v : def) {
    if (!def_text.empty()) def_text += ',';
    def_text += text_of(v);
  }
  std::string text;
  const bool set = lookup(name, text, help);
  record(name, help, def_text, text, set);
  if (!set) return def;
  std::vector<double> values;
  std::istringstream list(text);
  for (std::string item; std::getline(list, item, ',');) {
    double v = 0;
    if (!parse_real(item, v))
      throw InputError("option " + std::string(name) + ": '" + item + "' is not a number");
    values.push_back(v);
  }
  const std::size_t n = values.size();
  if (any_count ? (n < 1 || n > 64) : n != def.size()) {
    std::ostringstream s;
    s << "option " << name << " takes "
      << (any_count ? std::string("1 to 64") : std::to_string(def.size()))
      << " comma-separated values, got " << n;
    throw InputError(s.str());
  }
  for (double v : values)
    if (!(v > 0)) {
      std::ostringstream s;
      s << "option " << name << ": every value must be > 0, got " << v;
      throw InputError(s.str());
    }
  return values;
}

void OptionGroup::petsc_default(const char* name, const char* help, const char* value) {
  // Looking it up marks it used: a default that the chosen solver ignores
  // (e.g. -pc_gamg_* with -pc_type jacobi) is not a user typo.
  std::string text;
  const bool set = lookup(name, text, nullptr);  // PETSc parses it (check_type_option for types)
  record(name, help, value, text, set, true);
}

bool OptionGroup::given(const char* name) const {
  PetscBool set = PETSC_FALSE;
  LEM_PETSC(PetscOptionsHasName(nullptr, nullptr, name, &set));
  return set == PETSC_TRUE;
}

void check_type_option(const char* name, PetscFunctionList types, const char* kind) {
  for (const auto& [option, value] : database()) {
    if (lower(option) != lower(name)) continue;
    if (value.empty())
      throw InputError("option " + option + " is given without a value (a " + kind +
                       " type known to PETSc)");
    void (*create)(void) = nullptr;
    LEM_PETSC(PetscFunctionListFind(types, value.c_str(), &create));
    if (create) continue;
    const char** names = nullptr;
    int n = 0;
    LEM_PETSC(PetscFunctionListGet(types, &names, &n));
    std::vector<std::string> known;
    for (int i = 0; i < n; ++i)
      if (names[i]) known.emplace_back(names[i]);
    LEM_PETSC(PetscFree(names));
    const std::string* best = nearest(value, known);
    throw InputError("option " + option + " = '" + value + "' is not a " + kind +
                     " type known "
                     "to PETSc" +
                     (best ? " (did you mean " + *best + "?)" : std::string()));
  }
}

void check_option_names(MPI_Comm comm) {
  std::string unknown;
  for (const auto& name : option_names()) {
    if (find_record(name)) continue;  // ours (or a documented PETSc default)
    if (has_any_prefix(name.substr(1), kPetscPrefixes)) continue;  // checked once PETSc has read it
    unknown += " " + name + suggestion(name);
  }
  if (!unknown.empty())
    throw InputError("unknown option(s):" + unknown + " (run with -help to list the options)");
  PetscBool help = PETSC_FALSE;
  LEM_PETSC(PetscOptionsHasHelp(nullptr, &help));
  if (help) {
    LEM_PETSC(PetscPrintf(comm, "%s", registry_as_help().c_str()));
    const bool solver = std::any_of(registry().begin(), registry().end(),
                                    [](const OptionRecord& r) { return r.petsc_default; });
    throw HelpShown(std::string("-help: these are the program's options") +
                    (solver ? "; the solver also takes PETSc's standard -ksp_*, -pc_* and "
                              "-mat_* options (docs/reference/options.md)"
                            : "") +
                    ". Nothing was run.");
  }
}

void read_petsc_options(const std::function<void()>& read) {
  try {
    read();
  } catch (const PetscFailure& failure) {
    // PETSc quotes the bad value, not the option ("Input string abc has no
    // numeric value"): name every PETSc option given that value.
    const std::string message = failure.what();
    std::vector<std::string> words;
    std::string word;
    for (char c : message + " ") {
      if (std::isspace(static_cast<unsigned char>(c)) || c == ':' || c == '\'' || c == '"') {
        if (!word.empty()) words.push_back(lower(word));
        word.clear();
      } else {
        word += c;
      }
    }
    // Failing that, the options given without a value (-pc_gamg_type alone).
    std::string named, bare;
    int bare_count = 0;
    for (const auto& [option, value] : database()) {
      const OptionRecord* ours = find_record(option);  // parsed by OptionGroup, unless PETSc's
      if (ours && !ours->petsc_default) continue;
      if (value.empty()) {
        bare += (bare.empty() ? "" : ", ") + option;
        ++bare_count;
      } else if (std::find(words.begin(), words.end(), lower(value)) != words.end()) {
        named += (named.empty() ? "option " : ", ") + option + " = '" + value + "'";
      }
    }
    if (named.empty() && bare_count == 1) named = "option " + bare + ", given without a value,";
    if (named.empty() && bare_count > 1)
      named = "one of the options given without a value (" + bare + ")";
    throw InputError((named.empty() ? std::string("a solver option") : named) +
                     " is rejected by PETSc: " + message);
  }
}

void check_petsc_numbers() {
  // PETSc takes nan and inf wherever it reads a real, and some of its
  // setters check a range only at the first solve, or never (-ksp_max_it -5
  // runs): the solver's ranges, checked before any work.
  struct Range {
    const char* suffix;
    double lo, hi;  // [lo, hi)
    bool whole;
    const char* meaning;
  };
  static const Range kRanges[] = {
      {"ksp_rtol", 0, 1, false, "a relative tolerance, at least 0 and below 1"},
      {"ksp_atol", 0, HUGE_VAL, false, "an absolute tolerance, at least 0"},
      {"ksp_divtol", 0, HUGE_VAL, false, "a divergence tolerance, at least 0"},
      {"ksp_max_it", 0, 2147483647.0, true, "an iteration count, a whole number of at least 0"}};
  for (const auto& [option, value] : database()) {
    const OptionRecord* ours = find_record(option);
    if ((ours && !ours->petsc_default) || !has_any_prefix(option.substr(1), kPetscPrefixes))
      continue;
    double x = 0;
    const bool number = parse_real(value, x);
    if (number && !std::isfinite(x))
      throw InputError("option " + option + " = '" + value + "' is not a finite number");
    for (const Range& r : kRanges) {
      const std::size_t n = std::strlen(r.suffix);
      if (option.size() < n || option.compare(option.size() - n, n, r.suffix) != 0) continue;
      // Not a number: PETSc's own reading names it (read_petsc_options).
      if (!number || (x >= r.lo && x < r.hi && (!r.whole || x == std::floor(x)))) continue;
      throw InputError("option " + option + " = '" + value + "' is out of range: " + r.meaning);
    }
  }
}

void check_bare_petsc_options(const std::function<void()>& read) {
  const char* const probe = "lem:no-value";
  for (const auto& [option, value] : database()) {
    const OptionRecord* ours = find_record(option);
    if (!value.empty() || (ours && !ours->petsc_default) ||
        !has_any_prefix(option.substr(1), kReadAtCreation))
      continue;
    LEM_PETSC(PetscOptionsSetValue(nullptr, option.c_str(), probe));
    std::string failure;
    try {
      read();
    } catch (const InputError& e) {
      failure = e.what();
    }
    LEM_PETSC(PetscOptionsSetValue(nullptr, option.c_str(), nullptr));  // bare again
    const std::string quoted = std::string(" ") + probe + " ";
    if (failure.find("Input string" + quoted + "has no") != std::string::npos ||
        failure.find("Unknown option" + quoted + "for") != std::string::npos)
      throw InputError("option " + option +
                       " is given without a value (PETSc reads a number "
                       "or a word there, and would ignore it)");
  }
}

void check_unused_options(SolverStage stage) {
  PetscInt n = 0;
  char** names = nullptr;
  char** values = nullptr;
  LEM_PETSC(PetscOptionsLeftGet(nullptr, &n, &names, &values));
  std::string unknown;
  for (PetscInt i = 0; i < n; ++i) {
    const std::string name = names[i];
    // PETSc itself never marks a few start-up options as used.
    if (name == "options_left" || name == "help" || has_prefix(name, "log_view")) continue;
    if (stage == SolverStage::created &&
        (!has_any_prefix(name, kReadAtCreation) || read_later(name)))
      continue;
    unknown += " -" + name;
  }
  LEM_PETSC(PetscOptionsLeftRestore(nullptr, &n, &names, &values));
  if (!unknown.empty())
    throw InputError("option(s) given but never used (misspelt, or not valid for the chosen "
                     "solver):" +
                     unknown);
}

std::string options_as_text() {
  char* all = nullptr;
  LEM_PETSC(PetscOptionsGetAll(nullptr, &all));
  std::string text = all ? all : "";
  LEM_PETSC(PetscFree(all));
  const std::vector<std::string> present = option_names();
  // Then every option read but not given, at its default (ours and the
  // solver's), so that the record alone reproduces the run.
  for (const auto& r : registry()) {
    // Not given, and not put into the database by the program either.
    const bool in_database = std::any_of(present.begin(), present.end(), [&](const std::string& n) {
      return lower(n) == lower(r.name);
    });
    if (!in_database)
      text += " " + r.name + " " + (r.default_value.empty() ? "\"\"" : r.default_value);
  }
  return text;
}

}  // namespace lem
