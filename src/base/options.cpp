#include "lem/options.hpp"

#include "lem/error.hpp"

#include <algorithm>
#include <cstring>
#include <sstream>

namespace lem {
namespace {

std::string describe_range(double lo, double hi, bool open_lo, bool open_hi) {
  std::ostringstream s;
  s << (open_lo ? "(" : "[") << lo << ", " << hi << (open_hi ? ")" : "]");
  return s.str();
}

// Prefixes of options that PETSc itself (or MPI start-up) may consume; they
// are checked after the first solve, when PETSc has read them.
const char* const kPetscPrefixes[] = {
    "ksp_", "pc_", "mat_", "vec_", "fallback_", "patch_", "log", "options_", "help", "malloc", "info", "on_error",
    "history", "viewer", "fp_trap", "no_signal_handler", "check_pointer", "memory_view",
    "objects_dump", "skip_petscrc", "start_in_debugger", "debugger", "stop_for_debugger",
    "display", "use_gpu_aware_mpi", "citations", "version", "petsc", "sys", "draw", "nox",
    "mg_", "sub_", "redundant_", "telescope_", "is_", "sf_", "error_output", "saws", "python",
    "get_total_flops", "checkstack"};

bool has_prefix(const std::string& s, const std::string& p) { return s.rfind(p, 0) == 0; }

// Option names ("-x") present in the database.
std::vector<std::string> option_names() {
  char* all = nullptr;
  LEM_PETSC(PetscOptionsGetAll(nullptr, &all));
  std::istringstream in(all ? all : "");
  LEM_PETSC(PetscFree(all));
  std::vector<std::string> names;
  std::string token;
  while (in >> token) {
    // Values may be negative numbers; names start with '-' and a letter.
    if (token.size() > 1 && token[0] == '-' && std::isalpha(static_cast<unsigned char>(token[1])))
      names.push_back(token);
  }
  return names;
}

}  // namespace

OptionGroup::OptionGroup(MPI_Comm comm, const char* title) : comm_(comm) {
  std::memset(&items_, 0, sizeof(items_));
  items_.count = 1;  // a single pass, as PetscOptionsBegin does without SAWs
  LEM_PETSC(PetscOptionsBegin_Private(&items_, comm_, nullptr, title, "lem"));
}

OptionGroup::~OptionGroup() { PetscOptionsEnd_Private(&items_); }

double OptionGroup::real(const char* name, const char* help, double def, double lo, double hi,
                         bool open_lo, bool open_hi) {
  PetscReal value = def;
  PetscBool set = PETSC_FALSE;
  LEM_PETSC(PetscOptionsReal_Private(&items_, name, help, "lem", def, &value, &set));
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
  PetscInt value = static_cast<PetscInt>(def);
  PetscBool set = PETSC_FALSE;
  LEM_PETSC(PetscOptionsInt_Private(&items_, name, help, "lem", value, &value, &set,
                                    PETSC_MIN_INT, PETSC_MAX_INT));
  if (value < lo || value > hi) {
    std::ostringstream s;
    s << "option " << name << " = " << value << " is out of range: allowed [" << lo << ", " << hi
      << "] (" << help << ")";
    throw InputError(s.str());
  }
  return value;
}

bool OptionGroup::flag(const char* name, const char* help, bool def) {
  PetscBool value = def ? PETSC_TRUE : PETSC_FALSE;
  PetscBool set = PETSC_FALSE;
  LEM_PETSC(PetscOptionsBool_Private(&items_, name, help, "lem", value, &value, &set));
  return value == PETSC_TRUE;
}

std::string OptionGroup::string(const char* name, const char* help, const std::string& def) {
  char buffer[PETSC_MAX_PATH_LEN];
  PetscBool set = PETSC_FALSE;
  LEM_PETSC(PetscOptionsString_Private(&items_, name, help, "lem", def.c_str(), buffer,
                                       sizeof(buffer), &set));
  return set ? std::string(buffer) : def;
}

std::string OptionGroup::choice(const char* name, const char* help,
                                const std::vector<std::string>& choices, const std::string& def) {
  std::string all;
  for (const auto& c : choices) all += (all.empty() ? "" : "|") + c;
  const std::string text = std::string(help) + " (" + all + ")";
  std::string value = string(name, text.c_str(), def);
  if (std::find(choices.begin(), choices.end(), value) == choices.end())
    throw InputError("option " + std::string(name) + " = '" + value +
                     "' is not one of: " + all);
  return value;
}

std::vector<double> OptionGroup::positive_reals(const char* name, const char* help,
                                                const std::vector<double>& def, bool any_count) {
  std::vector<PetscReal> values(def.begin(), def.end());
  values.resize(std::max<std::size_t>(values.size(), 64));
  PetscInt n = static_cast<PetscInt>(values.size());
  PetscBool set = PETSC_FALSE;
  LEM_PETSC(PetscOptionsRealArray_Private(&items_, name, help, "lem", values.data(), &n, &set));
  if (!set) return def;
  if (any_count ? n < 1 : static_cast<std::size_t>(n) != def.size()) {
    std::ostringstream s;
    s << "option " << name << " takes " << (any_count ? std::string("1 to 64") : std::to_string(def.size()))
      << " comma-separated values, got " << n;
    throw InputError(s.str());
  }
  values.resize(static_cast<std::size_t>(n));
  for (double v : values)
    if (!(v > 0)) {
      std::ostringstream s;
      s << "option " << name << ": every value must be > 0, got " << v;
      throw InputError(s.str());
    }
  return {values.begin(), values.end()};
}

bool OptionGroup::given(const char* name) const {
  PetscBool set = PETSC_FALSE;
  LEM_PETSC(PetscOptionsHasName(nullptr, nullptr, name, &set));
  return set == PETSC_TRUE;
}

void check_option_names(const std::vector<std::string>& own_prefixes) {
  std::string unknown;
  for (const auto& name : option_names()) {
    const std::string bare = name.substr(1);
    bool own = false;
    for (const auto& p : own_prefixes) own = own || has_prefix(bare, p);
    // Read later, when the elastic system is created.
    static const char* const kReadLater[] = {"lattice_ground_stiffness"};
    bool late = false;
    for (const char* name_read_later : kReadLater) late = late || bare == name_read_later;
    if (late) continue;  // check_unused_options() covers it
    if (own) {
      PetscBool used = PETSC_FALSE;
      LEM_PETSC(PetscOptionsUsed(nullptr, bare.c_str(), &used));  // stored without the dash
      if (!used) unknown += " " + name;
      continue;
    }
    bool petsc = false;
    for (const char* p : kPetscPrefixes) petsc = petsc || has_prefix(bare, p);
    if (!petsc) unknown += " " + name;
  }
  if (!unknown.empty())
    throw InputError("unknown option(s):" + unknown + " (run with -help to list the options)");
  PetscBool help = PETSC_FALSE;
  LEM_PETSC(PetscOptionsHasHelp(nullptr, &help));
  if (help)
    throw HelpShown("-help: these are the program's options; the solver takes PETSc's standard "
                    "-ksp_*, -pc_* and -mat_* options (docs/user-guide.md). Nothing was run.");
}

void check_unused_options() {
  PetscInt n = 0;
  char** names = nullptr;
  char** values = nullptr;
  LEM_PETSC(PetscOptionsLeftGet(nullptr, &n, &names, &values));
  std::string unknown;
  for (PetscInt i = 0; i < n; ++i) {
    const std::string name = names[i];
    // PETSc itself never marks a few start-up options as used.
    if (name == "options_left" || name == "help" || has_prefix(name, "log_view")) continue;
    unknown += " -" + name;
  }
  LEM_PETSC(PetscOptionsLeftRestore(nullptr, &n, &names, &values));
  if (!unknown.empty())
    throw InputError("option(s) given but never used (misspelt, or not valid for the chosen "
                     "solver):" + unknown);
}

std::string options_as_text() {
  char* all = nullptr;
  LEM_PETSC(PetscOptionsGetAll(nullptr, &all));
  std::string text = all ? all : "";
  LEM_PETSC(PetscFree(all));
  return text;
}

}  // namespace lem
