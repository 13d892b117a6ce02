// Collective helpers of the ground floor: every rank of the communicator
// calls them, every rank gets the same answer.  T must be trivially copyable
// (the values travel as bytes).
#pragma once

#include <mpi.h>

#include <climits>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace lem {

/// Every rank's vector, concatenated in rank order, on every rank.
template <class T>
std::vector<T> allgather(MPI_Comm comm, const std::vector<T>& mine) {
  static_assert(std::is_trivially_copyable_v<T>);
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  const int bytes = static_cast<int>(mine.size() * sizeof(T));
  std::vector<int> counts(ranks), offsets(ranks + 1, 0);
  MPI_Allgather(&bytes, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
  for (int r = 0; r < ranks; ++r) offsets[r + 1] = offsets[r] + counts[r];
  std::vector<T> all(static_cast<std::size_t>(offsets[ranks]) / sizeof(T));
  MPI_Allgatherv(mine.data(), bytes, MPI_BYTE, all.data(), counts.data(), offsets.data(),
                 MPI_BYTE, comm);
  return all;
}

/// Root's vector (size and contents) on every rank.
template <class T>
void broadcast(MPI_Comm comm, std::vector<T>& values, int root = 0) {
  static_assert(std::is_trivially_copyable_v<T>);
  std::uint64_t n = values.size();
  MPI_Bcast(&n, 1, MPI_UINT64_T, root, comm);
  if (n > INT_MAX / sizeof(T)) throw std::length_error("broadcast: too many bytes for MPI_Bcast");
  values.resize(n);
  MPI_Bcast(values.data(), static_cast<int>(n * sizeof(T)), MPI_BYTE, root, comm);
}

/// Root's string on every rank (the argument is ignored elsewhere).
inline std::string broadcast_string(MPI_Comm comm, const std::string& value, int root = 0) {
  std::vector<char> chars(value.begin(), value.end());
  broadcast(comm, chars, root);
  return std::string(chars.begin(), chars.end());
}

/// Root's trivially copyable value on every rank.
template <class T>
void broadcast_value(MPI_Comm comm, T& value, int root = 0) {
  static_assert(std::is_trivially_copyable_v<T>);
  MPI_Bcast(&value, static_cast<int>(sizeof(T)), MPI_BYTE, root, comm);
}

}  // namespace lem
