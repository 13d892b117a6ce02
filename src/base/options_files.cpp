// -options_file followed through the files it names, before PETSc reads
// them: a missing file, a file that includes itself and too deep a nesting
// are named here rather than met by PETSc (which recurses without a bound).
// Every options file is read twice (here, then by PETSc), so only regular
// files of a bounded size are taken: a pipe would be emptied by the first
// reading, and a device such as /dev/zero never ends.
#include "lem/base/options.hpp"

#include "lem/base/files.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace lem {
namespace {

// Options files may include others (-options_file inside a file): PETSc
// follows them without a bound, so a file that includes itself recurses
// until the stack overflows.  Deeper than this is refused as a likely cycle.
constexpr int kOptionsFileDepth = 8;
// Options files are a few lines; a larger one is likely not an options file.
constexpr long long kOptionsFileBytes = 1 << 20;

// The words of an options file as PETSc reads them: '#' starts a comment,
// "alias" lines define aliases.
std::vector<std::string> options_file_words(std::FILE* file) {
  std::vector<std::string> words;
  char buffer[4096];
  std::string line;
  long long bytes = 0;  // a bound also for files whose size stat does not know
  while (bytes <= kOptionsFileBytes && std::fgets(buffer, sizeof buffer, file)) {
    bytes += static_cast<long long>(std::strlen(buffer));
    line += buffer;
    if (line.back() != '\n' && !std::feof(file)) continue;
    line = line.substr(0, line.find('#'));
    std::istringstream in(line);
    std::vector<std::string> here;
    for (std::string w; in >> w;) here.push_back(w);
    if (!here.empty() && here[0] != "alias") words.insert(words.end(), here.begin(), here.end());
    line.clear();
  }
  return words;
}

bool is_option_name(const std::string& word) {
  return word.size() > 1 && word[0] == '-' && std::isalpha(static_cast<unsigned char>(word[1]));
}

// Why `path` cannot be an options file ("" if it can): it must be a
// regular file (stat only: opening a pipe may wait for a writer) of at most
// kOptionsFileBytes.
std::string unusable_options_file(const std::string& path) {
  const std::string what = not_a_regular_file(path);
  if (what == "a directory") return "a directory, not a file";
  if (!what.empty())
    return what + ", not a regular file: options files are read twice (checked, then by "
                  "PETSc), so write the options to a file, or give them on the command line";
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(path, ec);
  if (!ec && static_cast<long long>(bytes) > kOptionsFileBytes)
    return std::to_string(bytes) + " bytes, more than an options file holds (at most " +
           std::to_string(kOptionsFileBytes) + ")";
  return "";
}

// The first problem with the options files named in `words` (given in
// `where`), following the plain ones into the files they name; `chain` holds
// the files being read, outermost first (canonical path, name as given).
using FileChain = std::vector<std::pair<std::string, std::string>>;
std::string options_file_problem(const std::vector<std::string>& words, const std::string& where,
                                 FileChain& chain) {
  for (std::size_t i = 0; i < words.size(); ++i) {
    const std::string& name = words[i];
    if (name != "-options_file" && name != "-options_file_yaml") continue;
    if (i + 1 >= words.size() || words[i + 1].empty() || is_option_name(words[i + 1]))
      return "option " + name + where + " is given without a value (a file of options)";
    const std::string path = words[++i];
    // PETSc expands ${NAME} and a leading ~ in the name after this check: the
    // file it would read is then not the one checked here.
    if (path.find("${") != std::string::npos || path[0] == '~')
      return "option " + name + " = '" + path + "'" + where +
             ": PETSc expands '${...}' and '~' in this name after the program has checked the "
             "file, so give the path written out (on a command line the shell expands $NAME "
             "and ~ before the program starts)";
    const std::string refused = unusable_options_file(path);
    if (!refused.empty()) return "option " + name + " = '" + path + "'" + where + ": " + refused;
    std::FILE* file = std::fopen(path.c_str(), "r");
    if (!file) return "option " + name + " = '" + path + "'" + where + ": the file cannot be read";
    std::error_code ec;
    if (name == "-options_file_yaml") {  // PETSc's YAML reader: not followed
      std::fclose(file);
      continue;
    }
    const std::string key = std::filesystem::weakly_canonical(path, ec).string();
    std::string trail;
    for (const auto& f : chain) trail += f.second + " -> ";
    trail += path;
    const bool loop =
        std::any_of(chain.begin(), chain.end(), [&](const auto& f) { return f.first == key; });
    if (loop || static_cast<int>(chain.size()) >= kOptionsFileDepth) {
      std::fclose(file);
      return "option -options_file = '" + path + "'" + where + ": " +
             (loop ? "the file includes itself (" + trail + ")"
                   : "options files nested more than " + std::to_string(kOptionsFileDepth) +
                         " deep (" + trail + ")");
    }
    const std::vector<std::string> inner = options_file_words(file);
    std::fclose(file);
    chain.emplace_back(key, path);
    const std::string problem = options_file_problem(inner, " in '" + path + "'", chain);
    chain.pop_back();
    if (!problem.empty()) return problem;
  }
  return "";
}

}  // namespace

std::string stray_command_line_word(int argc, char** argv) {
  // PETSc takes one value after an option and drops any other word without a
  // leading dash, so "fracture_max_steps 1" or the 4 of
  // "-fracture_max_steps 3 4" would be ignored without a word.
  const auto first_stray = [](const std::vector<std::string>& words, const char* where) {
    bool value_allowed = false;
    for (std::size_t i = 0; i < words.size(); ++i) {
      if (is_option_name(words[i])) {
        value_allowed = true;
      } else if (value_allowed) {
        value_allowed = false;
      } else {
        const std::string after = i > 0 ? " (after '" + words[i - 1] + "')" : "";
        return "the word '" + words[i] + "'" + after + where +
               " is neither an option nor an option's value: options start with a dash and "
               "take at most one value each";
      }
    }
    return std::string();
  };
  std::string problem = first_stray({argv + 1, argv + argc}, " on the command line");
  // PETSc reads this variable as if it were on the command line.
  if (const char* env = std::getenv("PETSC_OPTIONS"); problem.empty() && env) {
    std::istringstream in(env);
    std::vector<std::string> words;
    for (std::string w; in >> w;) words.push_back(w);
    problem = first_stray(words, " in PETSC_OPTIONS");
  }
  return problem;
}

std::string unreadable_options_file(int argc, char** argv) {
  std::vector<std::string> words(argv + 1, argv + argc);
  FileChain chain;
  std::string problem = options_file_problem(words, "", chain);
  // PETSc reads this variable as if it were on the command line.
  if (const char* env = std::getenv("PETSC_OPTIONS"); problem.empty() && env) {
    std::istringstream in(env);
    words.clear();
    for (std::string w; in >> w;) words.push_back(w);
    problem = options_file_problem(words, " in PETSC_OPTIONS", chain);
  }
  // The files PETSc reads by itself unless -skip_petscrc is given.
  const bool skip = std::find(argv + 1, argv + argc, std::string("-skip_petscrc")) != argv + argc;
  const char* home = std::getenv("HOME");
  std::vector<std::string> defaults = {".petscrc", "petscrc"};
  if (home) defaults.insert(defaults.begin(), std::string(home) + "/.petscrc");
  for (const auto& path : defaults) {
    if (!problem.empty() || skip) break;
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) continue;
    const std::string refused = unusable_options_file(path);
    if (!refused.empty())
      problem =
          "PETSc's default options file '" + path + "' (read unless -skip_petscrc): " + refused;
  }
  return problem;
}

}  // namespace lem
