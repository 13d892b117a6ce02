#include "lem/base/redistribute.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

namespace lem {

std::vector<std::uint64_t> exchange_counts(MPI_Comm comm,
                                           const std::vector<std::uint64_t>& counts) {
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  std::vector<std::uint64_t> received(ranks, 0);
  MPI_Alltoall(counts.data(), 1, MPI_UINT64_T, received.data(), 1, MPI_UINT64_T, comm);
  return received;
}

void move_bytes(MPI_Comm comm, const char* send, const std::vector<std::uint64_t>& counts,
                char* receive, const std::vector<std::uint64_t>& received,
                std::uint64_t round_bytes) {
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  std::vector<std::uint64_t> send_at(ranks + 1, 0), receive_at(ranks + 1, 0);
  for (int r = 0; r < ranks; ++r) {
    send_at[r + 1] = send_at[r] + counts[r];
    receive_at[r + 1] = receive_at[r] + received[r];
  }
  // Each round moves at most `pair` bytes between any two ranks, so that a
  // rank's total per round (its counts and displacements) stays an int.
  const std::uint64_t pair =
      std::max<std::uint64_t>(1, std::min<std::uint64_t>(round_bytes, INT_MAX) /
                                     static_cast<std::uint64_t>(ranks));
  std::uint64_t largest = 0, rounds = 0;
  for (int r = 0; r < ranks; ++r) largest = std::max({largest, counts[r], received[r]});
  const std::uint64_t mine = (largest + pair - 1) / pair;
  MPI_Allreduce(&mine, &rounds, 1, MPI_UINT64_T, MPI_MAX, comm);
  std::vector<int> send_n(ranks), send_d(ranks), receive_n(ranks), receive_d(ranks);
  std::vector<char> out_round, in_round;
  for (std::uint64_t k = 0; k < rounds; ++k) {
    const auto slice = [&](std::uint64_t total) {
      const std::uint64_t start = std::min(total, k * pair);
      return static_cast<int>(std::min(total - start, pair));
    };
    int send_total = 0, receive_total = 0;
    for (int r = 0; r < ranks; ++r) {
      send_n[r] = slice(counts[r]), send_d[r] = send_total, send_total += send_n[r];
      receive_n[r] = slice(received[r]), receive_d[r] = receive_total,
      receive_total += receive_n[r];
    }
    if (rounds == 1) {  // the slices are the whole buffers, laid out alike
      MPI_Alltoallv(send, send_n.data(), send_d.data(), MPI_BYTE, receive, receive_n.data(),
                    receive_d.data(), MPI_BYTE, comm);
      return;
    }
    out_round.resize(static_cast<std::size_t>(send_total));
    in_round.resize(static_cast<std::size_t>(receive_total));
    for (int r = 0; r < ranks; ++r)
      std::copy_n(send + send_at[r] + k * pair, send_n[r], out_round.data() + send_d[r]);
    MPI_Alltoallv(out_round.data(), send_n.data(), send_d.data(), MPI_BYTE, in_round.data(),
                  receive_n.data(), receive_d.data(), MPI_BYTE, comm);
    for (int r = 0; r < ranks; ++r)
      std::copy_n(in_round.data() + receive_d[r], receive_n[r], receive + receive_at[r] + k * pair);
  }
}

RowBlocks::RowBlocks(std::int64_t total_rows, int rank_count)
    : total(total_rows), ranks(rank_count) {
  // row * ranks and total * r must fit in 64 bits.
  if (total < 0 || ranks < 1 || total > std::numeric_limits<std::int64_t>::max() / ranks)
    throw std::logic_error("RowBlocks: " + std::to_string(total) + " rows on " +
                           std::to_string(ranks) + " ranks overflow 64 bits");
}

}  // namespace lem
