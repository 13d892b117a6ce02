// Checks of a sample read from a file that go beyond the shapes and ranges
// of its datasets: geometry, volumes, repeated bonds (sample_file.cpp).
#pragma once

#include "lem/cemented_sample.hpp"

#include <string>

namespace lem {

/// `v` with 10 significant digits, for messages.
std::string value_text(double v);

/// The first problem found, naming the dataset and its row; empty when the
/// sample is sound.  Bond ends must already be known to be 0 <= i < j < N.
std::string first_geometry_problem(const CementedSample& sample);

}  // namespace lem
