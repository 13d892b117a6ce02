#include "lem/protocol/state.hpp"

namespace lem {

std::int64_t FractureTally::broken_total() const {
  std::int64_t n = 0;
  for (auto b : broken) n += b;
  return n;
}

double FractureTally::particle_damage() const {
  const auto total = broken_total();
  return total > 0 ? static_cast<double>(broken[0]) / static_cast<double>(total) : 0.0;
}

}  // namespace lem
