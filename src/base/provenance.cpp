#include "lem/base/provenance.hpp"

#include "lem/base/options.hpp"

#include "lem/base/collective.hpp"
#include "lem/base/error.hpp"

#include <petscsys.h>

#include <cctype>
#include <chrono>
#include <ctime>
#include <sstream>

// Only this file sees the version and the hash (made at build time by
// cmake/git_hash.cmake), so a new commit rebuilds one file.
#if __has_include("lem_git_hash.h")
#include "lem_git_hash.h"
#endif
#ifndef LEM_VERSION
#define LEM_VERSION "unknown"
#endif
#ifndef LEM_GIT_HASH
#define LEM_GIT_HASH "unknown"
#endif

namespace lem {

std::string iso8601_utc_now() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm utc{};
  gmtime_r(&now, &utc);
  char buffer[32];
  std::strftime(buffer, sizeof buffer, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return buffer;
}

namespace {

/// options_as_text gives "-a 1 -b -c x "; put one option (with its value) per line.
/// A token starts a new option when it is '-' followed by a letter or '_'
/// (so negative numbers stay values).
std::string options_one_per_line(const std::string& all) {
  std::istringstream in(all);
  std::string token;
  std::string out;
  bool line_open = false;
  while (in >> token) {
    const bool is_name =
        token.size() > 1 && token[0] == '-' &&
        (std::isalpha(static_cast<unsigned char>(token[1])) != 0 || token[1] == '_');
    if (is_name && line_open)
      out += '\n';
    else if (line_open)
      out += ' ';
    out += token;
    line_open = true;
  }
  if (line_open) out += '\n';
  return out;
}

}  // namespace

std::string version_text(const std::string& program) {
  std::ostringstream out;
  out << program << " (lem3d) " << LEM_VERSION << ", git " << LEM_GIT_HASH << "\n"
      << "PETSc " << PETSC_VERSION_MAJOR << "." << PETSC_VERSION_MINOR << "."
      << PETSC_VERSION_SUBMINOR << (PETSC_VERSION_RELEASE ? "" : " (development)") << "\n";
  return out.str();
}

bool version_requested(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string word = argv[i];
    if (word == "-version" || word == "--version") return true;
  }
  return false;
}

Provenance collect_provenance(MPI_Comm comm, const std::string& program) {
  Provenance p;
  p.program = program;
  p.version = LEM_VERSION;
  p.git_hash = LEM_GIT_HASH;
  MPI_Comm_size(comm, &p.ranks);
  std::string options;
  std::string start_time;
  run_on_root(comm, [&] {
    start_time = iso8601_utc_now();
    PetscBool initialized = PETSC_FALSE;
    if (PetscInitialized(&initialized) != 0 || !initialized) return;
    // The options given and the solver defaults that none of them
    // overrides (the defaults are set on the objects, not in the database).
    options = options_one_per_line(options_as_text());
  });
  // Rank 0's view wins, so that every rank writes identical attributes.
  p.start_time = broadcast_string(comm, start_time);
  p.options = broadcast_string(comm, options);
  return p;
}

}  // namespace lem
