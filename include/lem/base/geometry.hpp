// Points and axis-aligned boxes, shared by the packing and the lattice.
#pragma once

#include <array>

namespace lem {

using Point = std::array<double, 3>;

struct Box {
  Point lo{0.0, 0.0, 0.0};
  Point hi{1.0, 1.0, 1.0};
  double length(int axis) const { return hi[axis] - lo[axis]; }
  double volume() const { return length(0) * length(1) * length(2); }
};

}  // namespace lem
