// Typed access to the PETSc options database with range checks.
//
// Every tunable is a PETSc option with a help string (shown by -help).  Values
// out of range raise InputError naming the option, the value and the allowed
// range.  check_unused_options() turns misspelt or unknown options into errors.
#pragma once

#include <petscsys.h>

#include <cstdint>
#include <string>
#include <vector>

namespace lem {

/// One titled group of options, as shown by -help.  Wraps
/// PetscOptionsBegin/End so that every query is registered with its help text.
class OptionGroup {
 public:
  OptionGroup(MPI_Comm comm, const char* title);
  ~OptionGroup();
  OptionGroup(const OptionGroup&) = delete;
  OptionGroup& operator=(const OptionGroup&) = delete;

  /// Real option in [lo, hi] (inclusive unless open_lo/open_hi).
  double real(const char* name, const char* help, double def, double lo, double hi,
              bool open_lo = false, bool open_hi = false);
  std::int64_t integer(const char* name, const char* help, std::int64_t def, std::int64_t lo,
                       std::int64_t hi);
  bool flag(const char* name, const char* help, bool def);
  std::string string(const char* name, const char* help, const std::string& def);
  /// String restricted to `choices`.
  std::string choice(const char* name, const char* help, const std::vector<std::string>& choices,
                     const std::string& def);
  /// Comma-separated reals, each > 0: exactly def.size() of them, or any
  /// number from 1 to 64 when `any_count`.
  std::vector<double> positive_reals(const char* name, const char* help,
                                     const std::vector<double>& def, bool any_count = false);
  /// True if the option was given on the command line / options file.
  bool given(const char* name) const;

 private:
  MPI_Comm comm_;
  PetscOptionItems items_;  // PETSc's registration object, so -help lists the option
};

/// Throw InputError listing every option in the database that nothing has
/// queried.  Call after all objects (KSP, PC, Mat) have read their options and
/// one solve has run, so that PETSc's own options are marked as used.
void check_unused_options();

/// Early check, callable before any solver exists: options that nothing can
/// consume (not ours, not a PETSc prefix) are reported immediately, so a typo
/// such as -lattice_node does not cost a long run.  With -help it throws
/// HelpShown: every driver calls it once its options are read, so -help lists
/// them and stops there.
void check_option_names(const std::vector<std::string>& own_prefixes);

/// The whole options database as "-name value" lines (provenance).
std::string options_as_text();

}  // namespace lem
