// An ordered record of named results, written as JSON and as a one-row CSV
// with units in the header.  A list of words is a JSON array and one CSV cell
// with the words separated by ';'.  CSV cells are never quoted: commas,
// quotes and line breaks inside text become blanks (the JSON keeps them), so
// that every CSV reader, numpy's included, splits the row the same way.
#pragma once

#include "lem/base/provenance.hpp"

#include <functional>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace lem {

/// What the documentation shows of a summary entry: its name, the unit of
/// its CSV header (empty for plain numbers and words) and what it means.
struct SummaryField {
  const char *name, *unit, *meaning;
};

template <class Record>
struct SummaryEntry;

/// The entries add_provenance() appends to every summary.
const std::vector<SummaryField>& provenance_summary_fields();

class Summary {
 public:
  using Value = std::variant<double, long long, std::string, std::vector<std::string>>;
  /// `unit` goes into the CSV header as name[unit]; empty for plain numbers.
  /// An entry added so is not described: fine for a sidecar (json(), csv(),
  /// numbers()), refused by write().
  void add(const std::string& name, Value value, const std::string& unit = "");
  /// The entries of `table` in its order, each valued from `record`; an
  /// entry whose value function gives nothing is left out of this summary.
  template <class Record>
  void add_from(const std::vector<SummaryEntry<Record>>& table, const Record& record);
  /// Where the result came from: program, version, git hash, start time,
  /// rank count (unless an entry mpi_ranks exists) and the effective
  /// options, one "-name value" per list word.
  void add_provenance(const Provenance& provenance);
  std::string json() const;
  std::string csv() const;
  /// <stem>.csv and <stem>.json, each written atomically, and both or
  /// neither: when the second write fails, the first file is removed.
  /// Throws IoError naming the file, and std::logic_error before writing
  /// when an entry was not described (added from a table of entries):
  /// every entry of a program's summary is documented.
  void write(const std::string& stem) const;
  /// The names of the entries that no table described.
  std::vector<std::string> undescribed() const;
  /// The names of the entries, in order.
  std::vector<std::string> names() const;
  /// The numeric entries (for HDF5 attributes).
  std::vector<std::pair<std::string, double>> numbers() const;

 private:
  void add_described(const char* name, const char* unit, Value value);
  struct Entry {
    std::string name, unit;
    Value value;
    bool described = false;
  };
  std::vector<Entry> entries_;
};

/// One entry of a summary, declared once: its description and how its
/// value is taken from the program's result record.  `value` returns a
/// Summary::Value (double, long long, text, list of words), or an empty
/// optional when this run has no such entry (its meaning says when).
template <class Record>
struct SummaryEntry {
  const char *name, *unit, *meaning;
  std::function<std::optional<Summary::Value>(const Record&)> value;
};

/// A program's summary: its entries in the order they are written.
template <class Record>
using SummaryTable = std::vector<SummaryEntry<Record>>;

/// The descriptions of a table's entries (for the documentation).
template <class Record>
std::vector<SummaryField> described_fields(const SummaryTable<Record>& table) {
  std::vector<SummaryField> fields;
  fields.reserve(table.size());
  for (const SummaryEntry<Record>& e : table) fields.push_back({e.name, e.unit, e.meaning});
  return fields;
}

/// A count as a summary value: a Value holds long long, not std::int64_t
/// (long) or int.
inline long long summary_count(long long n) { return n; }

template <class Record>
void Summary::add_from(const std::vector<SummaryEntry<Record>>& table, const Record& record) {
  for (const SummaryEntry<Record>& e : table)
    if (std::optional<Value> v = e.value(record)) add_described(e.name, e.unit, std::move(*v));
}

}  // namespace lem
