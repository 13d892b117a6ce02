// -options_file followed through the files it names, before PETSc reads
// them: a missing file, a file that includes itself and too deep a nesting
// are named here rather than met by PETSc (which recurses without a bound).
#include "lem/base/options.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
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

// The words of an options file as PETSc reads them: '#' starts a comment,
// "alias" lines define aliases.
std::vector<std::string> options_file_words(std::FILE* file) {
  std::vector<std::string> words;
  char buffer[4096];
  std::string line;
  while (std::fgets(buffer, sizeof buffer, file)) {
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
    std::error_code ec;
    const bool directory = std::filesystem::is_directory(path, ec);
    std::FILE* file = directory ? nullptr : std::fopen(path.c_str(), "r");
    if (!file)
      return "option " + name + " = '" + path + "'" + where + ": " +
             (directory ? "a directory, not a file" : "the file cannot be read");
    if (name == "-options_file_yaml") {  // PETSc's YAML reader: not followed
      std::fclose(file);
      continue;
    }
    const std::string key = std::filesystem::weakly_canonical(path, ec).string();
    std::string trail;
    for (const auto& f : chain) trail += f.second + " -> ";
    trail += path;
    const bool loop = std::any_of(chain.begin(), chain.end(),
                                  [&](const auto& f) { return f.first == key; });
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
  return problem;
}

}  // namespace lem
