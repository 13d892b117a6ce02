// Checks of a sample read from a file that go beyond the shapes and ranges
// of its datasets: geometry, volumes, repeated bonds (sample_reader.cpp).
#pragma once

#include "lem/sample/cemented_sample.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace lem {

/// `v` with 10 significant digits, for messages.
std::string value_text(double v);

/// The first problem found, naming the dataset and its row; empty when the
/// sample is sound.  Bond ends must already be known to be 0 <= i < j < N.
std::string first_geometry_problem(const CementedSample& sample);

// Its parts, for a reader that holds a block of the rows (first_row: the
// file row of the block's first entry).  Each returns "" when sound.
std::string first_box_problem(const Box& box);
std::string first_node_problem(const Box& box, const std::vector<Point>& nodes,
                               const std::vector<double>& volume, std::int64_t first_row);
std::string volume_sum_problem(const Box& box, double volume);
std::string zero_length_problem(const Box& box, std::int64_t row, std::int64_t i, std::int64_t j,
                                const Point& p, const Point& q);
std::string repeated_bond_problem(std::int64_t row, std::int64_t original, std::int64_t i,
                                  std::int64_t j);
/// Particles and bridges.
std::string first_description_problem(const CementedSample& sample);

}  // namespace lem
