// An ordered record of named results, written as JSON and as a one-row CSV
// with units in the header.  A list of words is a JSON array and one CSV cell
// with the words separated by ';'.
#pragma once

#include <string>
#include <variant>
#include <vector>

namespace lem {

class Summary {
 public:
  using Value = std::variant<double, long long, std::string, std::vector<std::string>>;
  /// `unit` goes into the CSV header as name[unit]; empty for plain numbers.
  void add(const std::string& name, Value value, const std::string& unit = "");
  std::string json() const;
  std::string csv() const;
  /// The numeric entries (for HDF5 attributes).
  std::vector<std::pair<std::string, double>> numbers() const;

 private:
  struct Entry {
    std::string name, unit;
    Value value;
  };
  std::vector<Entry> entries_;
};

}  // namespace lem
