#include "lem/base/summary.hpp"

#include "lem/base/files.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

namespace lem {
namespace {

std::string number(double v) {
  if (!std::isfinite(v)) return "null";
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.10g", v);
  return buffer;
}

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    if (c == '\n') {
      out += "\\n";
      continue;
    }
    out += c;
  }
  return out + "\"";
}

// A CSV cell that needs no quoting (see summary.hpp).
std::string plain_cell(std::string s) {
  for (char& c : s)
    if (c == ',' || c == '"' || c == '\n' || c == '\r') c = ' ';
  return s;
}

std::string text(const Summary::Value& v, bool json) {
  if (const auto* d = std::get_if<double>(&v)) return number(*d);
  if (const auto* i = std::get_if<long long>(&v)) return std::to_string(*i);
  if (const auto* list = std::get_if<std::vector<std::string>>(&v)) {
    std::string out = json ? "[" : "";
    for (std::size_t k = 0; k < list->size(); ++k) {
      if (k > 0) out += json ? ", " : ";";
      out += json ? quoted((*list)[k]) : (*list)[k];
    }
    return json ? out + "]" : plain_cell(out);
  }
  const auto& s = std::get<std::string>(v);
  return json ? quoted(s) : plain_cell(s);
}

}  // namespace

namespace {

// What add_provenance() writes from: the provenance, and whether the
// program's own table already has an entry mpi_ranks.
struct ProvenanceRecord {
  const Provenance& provenance;
  bool has_ranks;
};

const SummaryTable<ProvenanceRecord>& provenance_table() {
  static const SummaryTable<ProvenanceRecord> table = {
      {"program", "", "the program that wrote it",
       [](const ProvenanceRecord& r) { return r.provenance.program; }},
      {"version", "", "its version",
       [](const ProvenanceRecord& r) { return r.provenance.version; }},
      {"git_hash", "", "the commit it was built from (`-dirty`: with uncommitted changes)",
       [](const ProvenanceRecord& r) { return r.provenance.git_hash; }},
      {"start_time", "", "when the run started (UTC, `YYYY-MM-DDTHH:MM:SSZ`)",
       [](const ProvenanceRecord& r) { return r.provenance.start_time; }},
      {"mpi_ranks", "", "MPI ranks (only here when the program's table has no such entry)",
       [](const ProvenanceRecord& r) -> std::optional<Summary::Value> {
         if (r.has_ranks) return std::nullopt;
         return summary_count(r.provenance.ranks);
       }},
      {"options", "", "every option in effect, given or not, one `-name value` per word",
       [](const ProvenanceRecord& r) {
         std::vector<std::string> options;
         std::istringstream lines(r.provenance.options);
         for (std::string line; std::getline(lines, line);)
           if (!line.empty()) options.push_back(line);
         return options;
       }},
  };
  return table;
}

}  // namespace

const std::vector<SummaryField>& provenance_summary_fields() {
  static const std::vector<SummaryField> fields = described_fields(provenance_table());
  return fields;
}

void Summary::add(const std::string& name, Value value, const std::string& unit) {
  entries_.push_back({name, unit, std::move(value)});
}

void Summary::add_described(const char* name, const char* unit, Value value) {
  entries_.push_back({name, unit, std::move(value), true});
}

void Summary::add_provenance(const Provenance& p) {
  const bool has_ranks = std::any_of(entries_.begin(), entries_.end(),
                                     [](const Entry& e) { return e.name == "mpi_ranks"; });
  add_from(provenance_table(), ProvenanceRecord{p, has_ranks});
}

std::string Summary::json() const {
  std::ostringstream out;
  out << "{\n";
  for (std::size_t k = 0; k < entries_.size(); ++k)
    out << "  " << quoted(entries_[k].name) << ": " << text(entries_[k].value, true)
        << (k + 1 < entries_.size() ? ",\n" : "\n");
  out << "}\n";
  return out.str();
}

std::string Summary::csv() const {
  std::ostringstream head, row;
  for (std::size_t k = 0; k < entries_.size(); ++k) {
    const char* sep = k ? "," : "";
    const std::string unit = entries_[k].unit.empty() ? "" : "[" + entries_[k].unit + "]";
    head << sep << plain_cell(entries_[k].name + unit);
    row << sep << text(entries_[k].value, false);
  }
  return head.str() + "\n" + row.str() + "\n";
}

std::vector<std::string> Summary::names() const {
  std::vector<std::string> out;
  for (const auto& e : entries_) out.push_back(e.name);
  return out;
}

std::vector<std::pair<std::string, double>> Summary::numbers() const {
  std::vector<std::pair<std::string, double>> out;
  for (const auto& e : entries_) {
    if (const auto* d = std::get_if<double>(&e.value)) out.emplace_back(e.name, *d);
    if (const auto* i = std::get_if<long long>(&e.value))
      out.emplace_back(e.name, static_cast<double>(*i));
  }
  return out;
}

std::vector<std::string> Summary::undescribed() const {
  std::vector<std::string> out;
  for (const auto& e : entries_)
    if (!e.described) out.push_back(e.name);
  return out;
}

void Summary::write(const std::string& stem) const {
  if (const auto names = undescribed(); !names.empty())
    throw std::logic_error("summary entry '" + names.front() + "' of " + stem +
                           " is in no table of fields: describe it (name, unit, meaning)");
  write_text_file_atomically(stem + ".csv", csv());
  try {
    write_text_file_atomically(stem + ".json", json());
  } catch (...) {  // no summary is left without its other half (a full disk)
    std::remove((stem + ".csv").c_str());
    throw;
  }
}

}  // namespace lem
