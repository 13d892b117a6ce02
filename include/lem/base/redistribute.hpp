// Moving items between ranks by key, for the stages that must not pass
// through one rank (reading a sample, partitioning, generating a lattice):
// each item goes to the rank a key names, in rounds that keep every MPI count
// and displacement below 2^31 whatever the byte counts.
#pragma once

#include "lem/base/collective.hpp"

#include <mpi.h>

#include <cstdint>
#include <cstring>
#include <type_traits>
#include <vector>

namespace lem {

/// The bytes a rank may send in one round of move_bytes (all destinations
/// together), and receive.
inline constexpr std::uint64_t kRoundBytes = std::uint64_t(1) << 30;

/// How many bytes this rank receives from each rank (`[s]` from rank s),
/// when every rank sends `counts[d]` bytes to rank d.  Collective.
std::vector<std::uint64_t> exchange_counts(MPI_Comm comm, const std::vector<std::uint64_t>& counts);

/// `send` holds the bytes for rank 0, then those for rank 1, ... (`counts[d]`
/// for rank d); `receive` gets those from rank 0 first (`received[s]` from
/// rank s, as exchange_counts gave).  Collective.  The exchange goes in
/// rounds of at most `round_bytes` per rank (tests lower it); when one round
/// is enough the bytes go from `send` to `receive` without a copy.
void move_bytes(MPI_Comm comm, const char* send, const std::vector<std::uint64_t>& counts,
                char* receive, const std::vector<std::uint64_t>& received,
                std::uint64_t round_bytes = kRoundBytes);

/// Item k to rank `to[k]`.  Returns the items this rank received, ordered by
/// source rank and, from one source, in the source's order; `from` (if given)
/// gets each one's source rank.  Collective.  Holds the items twice besides
/// `items` (sorted by destination, and received).
template <class T>
std::vector<T> route(MPI_Comm comm, const std::vector<T>& items, const std::vector<int>& to,
                     std::vector<int>* from = nullptr, std::uint64_t round_bytes = kRoundBytes) {
  static_assert(std::is_trivially_copyable_v<T>);
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  std::vector<std::uint64_t> counts(ranks, 0), at(ranks + 1, 0);
  for (const int d : to) counts[d] += sizeof(T);
  for (int d = 0; d < ranks; ++d) at[d + 1] = at[d] + counts[d];
  std::vector<char> send(at[ranks]);
  for (std::size_t k = 0; k < items.size(); ++k) {
    std::memcpy(send.data() + at[to[k]], &items[k], sizeof(T));
    at[to[k]] += sizeof(T);
  }
  const std::vector<std::uint64_t> received = exchange_counts(comm, counts);
  std::uint64_t bytes = 0;
  for (const std::uint64_t n : received) bytes += n;
  std::vector<T> out(bytes / sizeof(T));
  move_bytes(comm, send.data(), counts, reinterpret_cast<char*>(out.data()), received, round_bytes);
  if (from) {
    from->clear();
    for (int s = 0; s < ranks; ++s) from->insert(from->end(), received[s] / sizeof(T), s);
  }
  return out;
}

/// Answers to questions asked of other ranks: question k goes to rank
/// `to[k]`, which answers it with `answer(question)`; returns the answers in
/// the order of the questions.  Collective.
template <class Answer, class Question, class F>
std::vector<Answer> ask(MPI_Comm comm, const std::vector<Question>& questions,
                        const std::vector<int>& to, F&& answer,
                        std::uint64_t round_bytes = kRoundBytes) {
  std::vector<int> from;
  const std::vector<Question> asked = route(comm, questions, to, &from, round_bytes);
  std::vector<Answer> answers;
  answers.reserve(asked.size());
  for (const Question& q : asked) answers.push_back(answer(q));
  // Back to the askers: each receives its answers grouped by the rank that
  // gave them, in the order it asked that rank.
  const std::vector<Answer> back = route(comm, answers, from, nullptr, round_bytes);
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  std::vector<std::size_t> next(ranks + 1, 0);
  for (const int d : to) ++next[d + 1];
  for (int d = 0; d < ranks; ++d) next[d + 1] += next[d];
  std::vector<Answer> out(questions.size());
  for (std::size_t k = 0; k < questions.size(); ++k) out[k] = back[next[to[k]]++];
  return out;
}

/// Rows 0 .. total-1 dealt out in contiguous blocks, rank r the rows
/// [begin(r), begin(r + 1)) with begin(r) = ceil(total r / ranks): how a
/// file's rows and a lattice's ids are dealt out.
struct RowBlocks {
  std::int64_t total = 0;
  int ranks = 1;
  RowBlocks(std::int64_t total_rows, int rank_count);
  std::int64_t begin(int r) const { return (total * r + ranks - 1) / ranks; }
  /// The rank whose block holds `row` (0 <= row < total).
  int rank_of(std::int64_t row) const { return static_cast<int>(row * ranks / total); }
};

}  // namespace lem
