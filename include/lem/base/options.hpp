// Typed access to the PETSc options database, read once into plain values.
//
// Every tunable is an option with a help string.  OptionGroup reads it with
// PETSc's public getters, parses and checks it here (a value that is not a
// number, not an integer, not a boolean or out of range raises InputError
// naming the option, the value and what is allowed) and records it in one
// registry: -help prints the registry, the unknown-option check derives the
// program's own names from it, and the provenance of every output lists the
// solver defaults recorded in it.
#pragma once

#include <petscsys.h>

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace lem {

/// One option as the program read it.
struct OptionRecord {
  std::string group;  // title of the group that read it first
  std::string name;   // with the dash: "-lattice_nodes"
  std::string help;
  std::string default_value;  // as text
  std::string value;          // as given (empty when not given)
  bool given = false;
  /// A default that the program sets on a PETSc object (solver, matrix):
  /// PETSc reads the option, the registry only documents it.
  bool petsc_default = false;
};

/// Every option read so far in this process, in reading order, one entry
/// per name.
const std::vector<OptionRecord>& registered_options();

/// One titled group of options, as shown by -help.
class OptionGroup {
 public:
  OptionGroup(MPI_Comm comm, const char* title);
  OptionGroup(const OptionGroup&) = delete;
  OptionGroup& operator=(const OptionGroup&) = delete;

  /// Real option in [lo, hi] (inclusive unless open_lo/open_hi).
  double real(const char* name, const char* help, double def, double lo, double hi,
              bool open_lo = false, bool open_hi = false);
  /// Integer option in [lo, hi]; "1e6" is accepted for 1000000, "1.5" is not.
  std::int64_t integer(const char* name, const char* help, std::int64_t def, std::int64_t lo,
                       std::int64_t hi);
  /// true/false (also yes/no, on/off, 1/0; the bare name means true).
  bool flag(const char* name, const char* help, bool def);
  std::string string(const char* name, const char* help, const std::string& def);
  /// One of a fixed set of words, returned as the value paired with it
  /// (an enum), so that no string is compared beyond this point.
  template <class E>
  E choice(const char* name, const char* help,
           const std::vector<std::pair<const char*, E>>& choices, E def) {
    std::vector<std::string> words;
    std::size_t def_index = 0;
    for (std::size_t i = 0; i < choices.size(); ++i) {
      words.emplace_back(choices[i].first);
      if (choices[i].second == def) def_index = i;
    }
    return choices[choice_index(name, help, words, def_index)].second;
  }
  /// Comma-separated reals, each > 0: exactly def.size() of them, or any
  /// number from 1 to 64 when `any_count`.
  std::vector<double> positive_reals(const char* name, const char* help,
                                     const std::vector<double>& def, bool any_count = false);
  /// A default that the program applies to a PETSc object itself (e.g.
  /// KSPSetType); listed by -help and in the provenance, read by PETSc.
  void petsc_default(const char* name, const char* help, const char* value);
  /// True if the option was given on the command line / options file.
  bool given(const char* name) const;

 private:
  std::size_t choice_index(const char* name, const char* help,
                           const std::vector<std::string>& words, std::size_t def_index);
  // The option's text if it was given (PETSc marks it used).  With a help
  // string the option needs a value: "-name" alone or an empty value is an
  // InputError naming it; flags pass none (a bare -name means true).
  bool lookup(const char* name, std::string& text, const char* help) const;
  void record(const char* name, const char* help, std::string def, const std::string& text,
              bool given, bool petsc_default = false);

  MPI_Comm comm_;
  std::string title_;
};

/// Before PETSc starts: the first -options_file / -options_file_yaml of the
/// command line or PETSC_OPTIONS, or of an options file they name (followed
/// to any depth), that names no readable file, a file that includes itself
/// or files nested more than 8 deep, as an error message naming it ("" if
/// there is none).  PETSc itself would fail with a trace, or recurse until
/// the stack overflows.
std::string unreadable_options_file(int argc, char** argv);

/// Before PETSc starts: a command-line word that is neither an option (a
/// dash and a letter) nor the one value that follows it, as an error message
/// naming it ("" if there is none).  PETSc would drop it silently.
std::string stray_command_line_word(int argc, char** argv);

/// Before any work: every option in the database must be one the program
/// has read (registered) or one under a prefix that PETSc consumes (-ksp_*,
/// -pc_*, -mat_*, -log_*, -fallback_*, ...).  Others are reported at once,
/// with the nearest registered name, so that a typo such as -lattice_node
/// does not cost a long run.  With -help it prints the registry and throws
/// HelpShown: every driver calls it once its options are read.
void check_option_names(MPI_Comm comm);

/// A PETSc type option (-ksp_type, -pc_type, ...), if given, must name one of
/// `types` (e.g. KSPList): checked before any work instead of failing in
/// KSPSetFromOptions.  Does not mark the option used.
void check_type_option(const char* name, PetscFunctionList types, const char* kind);

/// Run `read`, a call through which PETSc objects read their options
/// (KSPSetFromOptions, MatSetFromOptions, ...).  PETSc fails there only on a
/// value it cannot take (-ksp_rtol abc, -ksp_max_it 1.5): that failure is
/// rethrown as InputError naming the option(s) whose value PETSc's message
/// quotes, with that message.
void read_petsc_options(const std::function<void()>& read);

/// Before any PETSc object reads its options: every PETSc option whose
/// value is a number must be finite, and the solver's tolerances and
/// iteration counts (-ksp_rtol, -ksp_atol, -ksp_divtol, -ksp_max_it, under
/// any prefix) in their ranges; InputError naming the option otherwise.
void check_petsc_numbers();

/// PETSc ignores a numeric option given without its value (-ksp_rtol alone
/// runs with the default).  `read` reads the options as the solver objects
/// do (through read_petsc_options); it is run once more for each -ksp_*,
/// -pc_* or -fallback_* option given bare, with a value that no PETSc
/// parser takes: if PETSc then asks for a number or one of a list of words,
/// the option is an InputError "given without a value".  Flags and viewers
/// (-ksp_monitor, -ksp_view) stay valid bare.
void check_bare_petsc_options(const std::function<void()>& read);

/// When the check of PETSc's options runs.
enum class SolverStage {
  created,  // the KSP, PC and matrix have read their options (before the first solve)
  solved,   // one solve has run: the preconditioner has been set up
};

/// Throw InputError listing the options that nothing has used.  At
/// SolverStage::created, the options that PETSc reads only when the
/// preconditioner is set up or a solve ends are left for the later check.
void check_unused_options(SolverStage stage = SolverStage::solved);

/// The options as "-name value" text for the provenance: the database
/// followed by every registered option that was not given, at its default
/// (the solver defaults of petsc_default included; "" for an empty text).
std::string options_as_text();

}  // namespace lem
