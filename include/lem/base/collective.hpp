// Collective helpers of the ground floor: every rank of the communicator
// calls them, every rank gets the same answer (and the point-to-point byte
// transfers that go with them).  T must be trivially copyable (the values
// travel as bytes); any byte count that fits in 64 bits is fine.
#pragma once

#include <mpi.h>

#include <algorithm>
#include <climits>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace lem {

/// MPI counts are int: larger transfers go in pieces of at most this many
/// bytes, so that byte counts above 2^31 neither overflow nor throw.
inline constexpr std::uint64_t kMpiPieceBytes = std::uint64_t(1) << 30;

/// f(offset, count) for consecutive pieces of [0, n), each of at most
/// `piece_bytes` (so `count` fits in an int).
template <class F>
void in_pieces(std::uint64_t n, std::uint64_t piece_bytes, F&& f) {
  for (std::uint64_t done = 0; done < n;) {
    const int count = static_cast<int>(std::min(n - done, piece_bytes));
    f(done, count);
    done += static_cast<std::uint64_t>(count);
  }
}

/// `n` bytes from `root` to every rank.
inline void broadcast_bytes(MPI_Comm comm, void* data, std::uint64_t n, int root,
                            std::uint64_t piece_bytes = kMpiPieceBytes) {
  in_pieces(n, piece_bytes, [&](std::uint64_t at, int count) {
    MPI_Bcast(static_cast<char*>(data) + at, count, MPI_BYTE, root, comm);
  });
}

/// Point to point; the receiver must know `n`.
inline void send_bytes(MPI_Comm comm, const void* data, std::uint64_t n, int to, int tag,
                       std::uint64_t piece_bytes = kMpiPieceBytes) {
  in_pieces(n, piece_bytes, [&](std::uint64_t at, int count) {
    MPI_Send(static_cast<const char*>(data) + at, count, MPI_BYTE, to, tag, comm);
  });
}
inline void receive_bytes(MPI_Comm comm, void* data, std::uint64_t n, int from, int tag,
                          std::uint64_t piece_bytes = kMpiPieceBytes) {
  in_pieces(n, piece_bytes, [&](std::uint64_t at, int count) {
    MPI_Recv(static_cast<char*>(data) + at, count, MPI_BYTE, from, tag, comm, MPI_STATUS_IGNORE);
  });
}

/// While one is alive, an allgather or a vector broadcast of more than
/// `bytes` is a logic error: the check that a run moves only O(events)
/// through whole-communicator collectives, never a per-node or per-bond
/// array (the test hook LEM_COLLECTIVE_LIMIT, docs/developer/testing.md).
class CollectiveByteLimit {
 public:
  explicit CollectiveByteLimit(std::uint64_t bytes) : before_(current()) { current() = bytes; }
  ~CollectiveByteLimit() { current() = before_; }
  CollectiveByteLimit(const CollectiveByteLimit&) = delete;
  CollectiveByteLimit& operator=(const CollectiveByteLimit&) = delete;

  /// The limit in force (0: none).
  static std::uint64_t& current() {
    static std::uint64_t bytes = 0;
    return bytes;
  }
  /// Every rank sees the same total, so every rank throws together.
  static void check(std::uint64_t total, const char* what) {
    if (current() != 0 && total > current())
      throw std::logic_error(std::string(what) + " of " + std::to_string(total) +
                             " bytes, above the limit of " + std::to_string(current()) +
                             " bytes set by LEM_COLLECTIVE_LIMIT");
  }

 private:
  std::uint64_t before_;
};

/// Every rank's vector, concatenated in rank order, on every rank.
/// (`gatherv_bytes`: the largest total sent with one MPI_Allgatherv, whose
/// displacements are int; tests lower it.)
template <class T>
std::vector<T> allgather(MPI_Comm comm, const std::vector<T>& mine,
                         std::uint64_t gatherv_bytes = INT_MAX) {
  static_assert(std::is_trivially_copyable_v<T>);
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  const std::uint64_t bytes = mine.size() * sizeof(T);
  std::vector<std::uint64_t> counts(ranks), offsets(ranks + 1, 0);
  MPI_Allgather(&bytes, 1, MPI_UINT64_T, counts.data(), 1, MPI_UINT64_T, comm);
  for (int r = 0; r < ranks; ++r) offsets[r + 1] = offsets[r] + counts[r];
  CollectiveByteLimit::check(offsets[ranks], "an allgather");
  std::vector<T> all(offsets[ranks] / sizeof(T));
  if (offsets[ranks] <= gatherv_bytes) {
    const std::vector<int> n(counts.begin(), counts.end()), at(offsets.begin(), offsets.end());
    MPI_Allgatherv(mine.data(), static_cast<int>(bytes), MPI_BYTE, all.data(), n.data(), at.data(),
                   MPI_BYTE, comm);
    return all;
  }
  // Too large for int displacements: each rank broadcasts its part.
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  char* out = reinterpret_cast<char*>(all.data());
  std::copy_n(reinterpret_cast<const char*>(mine.data()), bytes, out + offsets[rank]);
  for (int r = 0; r < ranks; ++r) broadcast_bytes(comm, out + offsets[r], counts[r], r);
  return all;
}

/// Root's vector (size and contents) on every rank.
template <class T>
void broadcast(MPI_Comm comm, std::vector<T>& values, int root = 0,
               std::uint64_t piece_bytes = kMpiPieceBytes) {
  static_assert(std::is_trivially_copyable_v<T>);
  std::uint64_t n = values.size();
  MPI_Bcast(&n, 1, MPI_UINT64_T, root, comm);
  CollectiveByteLimit::check(n * sizeof(T), "a broadcast");
  values.resize(n);
  broadcast_bytes(comm, values.data(), n * sizeof(T), root, piece_bytes);
}

/// Root's string on every rank (the argument is ignored elsewhere).
inline std::string broadcast_string(MPI_Comm comm, const std::string& value, int root = 0) {
  std::vector<char> chars(value.begin(), value.end());
  broadcast(comm, chars, root);
  return std::string(chars.begin(), chars.end());
}

/// The sum of `mine` over the ranks, on every rank.
inline std::int64_t sum_over_ranks(MPI_Comm comm, std::int64_t mine) {
  std::int64_t total = 0;
  MPI_Allreduce(&mine, &total, 1, MPI_INT64_T, MPI_SUM, comm);
  return total;
}

/// The sum of `mine` over the ranks, on every rank.
inline double sum_over_ranks(MPI_Comm comm, double mine) {
  double total = 0;
  MPI_Allreduce(&mine, &total, 1, MPI_DOUBLE, MPI_SUM, comm);
  return total;
}

/// The largest `mine` over the ranks, on every rank (a time: the slowest
/// rank's).
inline double max_over_ranks(MPI_Comm comm, double mine) {
  double most = 0;
  MPI_Allreduce(&mine, &most, 1, MPI_DOUBLE, MPI_MAX, comm);
  return most;
}

/// Root's trivially copyable value on every rank.
template <class T>
void broadcast_value(MPI_Comm comm, T& value, int root = 0) {
  static_assert(std::is_trivially_copyable_v<T>);
  broadcast_bytes(comm, &value, sizeof(T), root);
}

}  // namespace lem
