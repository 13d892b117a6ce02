// An ordered record of named results, written as JSON and as a one-row CSV
// with units in the header.  A list of words is a JSON array and one CSV cell
// with the words separated by ';'.  CSV cells are never quoted: commas,
// quotes and line breaks inside text become blanks (the JSON keeps them), so
// that every CSV reader, numpy's included, splits the row the same way.
#pragma once

#include "lem/base/provenance.hpp"

#include <string>
#include <variant>
#include <vector>

namespace lem {

/// One entry of a summary described by a table: its name, the unit of its
/// CSV header (empty for plain numbers and words) and what it means.
struct SummaryField {
  const char *name, *unit, *meaning;
};

/// The entries add_provenance() appends to every summary.
const std::vector<SummaryField>& provenance_summary_fields();

class Summary {
 public:
  using Value = std::variant<double, long long, std::string, std::vector<std::string>>;
  /// `unit` goes into the CSV header as name[unit]; empty for plain numbers.
  /// An entry added so is not described: fine for a sidecar (json(), csv(),
  /// numbers()), refused by write().
  void add(const std::string& name, Value value, const std::string& unit = "");
  /// Entries in the order of a table of fields: put(name, value) takes the
  /// next field, whose unit it writes, and throws std::logic_error when the
  /// name is not that field's; done() throws when fields are left.
  class Described {
   public:
    Described(Summary& summary, const std::vector<SummaryField>& fields)
        : summary_(summary), fields_(fields) {}
    void put(const std::string& name, Value value);
    /// Pass over the next field, which this run does not have (a field
    /// whose meaning says when it is written); the same check as put().
    void skip(const std::string& name);
    void done() const;

   private:
    Summary& summary_;
    const std::vector<SummaryField>& fields_;
    std::size_t next_ = 0;
  };
  /// Where the result came from: program, version, git hash, start time,
  /// rank count (unless an entry mpi_ranks exists) and the effective
  /// options, one "-name value" per list word.
  void add_provenance(const Provenance& provenance);
  std::string json() const;
  std::string csv() const;
  /// <stem>.csv and <stem>.json, each written atomically, and both or
  /// neither: when the second write fails, the first file is removed.
  /// Throws IoError naming the file, and std::logic_error before writing
  /// when an entry was not described (put by Described or add_provenance):
  /// every entry of a program's summary is documented.
  void write(const std::string& stem) const;
  /// The names of the entries that no table described.
  std::vector<std::string> undescribed() const;
  /// The names of the entries, in order.
  std::vector<std::string> names() const;
  /// The numeric entries (for HDF5 attributes).
  std::vector<std::pair<std::string, double>> numbers() const;

 private:
  struct Entry {
    std::string name, unit;
    Value value;
    bool described = false;
  };
  std::vector<Entry> entries_;
};

}  // namespace lem
