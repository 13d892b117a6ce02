// The checkpoint file at 1 and 2 ranks: each rank writes the rows of its own
// nodes and reads those of another partition by node id; a value changed in
// the file or a non-finite one is refused on every rank with the same message.
#include "lem/base/error.hpp"
#include "lem/protocol/checkpoint.hpp"

#include "../world.hpp"

#include <gtest/gtest.h>
#include <petscsys.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

using namespace lem;

namespace {

constexpr std::int64_t kNodes = 1001;

double value_of(std::int64_t id, int a, int field) {
  return 1e-3 * static_cast<double>(id) + 0.25 * a - 7.0 * field;
}

Checkpoint checkpoint_of(const std::vector<std::int64_t>& ids, bool check_field,
                         int learnt_columns = 0) {
  Checkpoint c;
  c.state.tally.steps = 17;
  c.state.batches = 2;
  c.fingerprint =
      "ranks=" + std::to_string(world_size()) + "\nnodes=" + std::to_string(kNodes) + "\n";
  c.damage.bond_events = {4, 9};
  c.damage.bond_batches = {1, 2};
  c.learnt_space.resize(static_cast<std::size_t>(learnt_columns));
  for (const std::int64_t id : ids)
    for (int a = 0; a < 3; ++a) {
      c.displacement.push_back(value_of(id, a, 0));
      if (check_field) c.check_displacement.push_back(value_of(id, a, 1));
      for (int j = 0; j < learnt_columns; ++j)
        c.learnt_space[static_cast<std::size_t>(j)].push_back(value_of(id, a, 2 + j));
    }
  return c;
}

// Written: every world_size()-th node from the last one down, per rank.
std::vector<std::int64_t> strided_ids() {
  std::vector<std::int64_t> ids;
  for (std::int64_t id = kNodes - 1; id >= 0; --id)
    if (id % world_size() == world_rank()) ids.push_back(id);
  return ids;
}

// Read: contiguous blocks in reverse rank order; the last rank gets none
// when there are several.
std::vector<std::int64_t> block_ids() {
  const int readers = world_size() > 1 ? world_size() - 1 : 1;
  const int reader = world_size() - 2 - world_rank() >= 0 ? world_size() - 2 - world_rank()
                                                          : (world_size() == 1 ? 0 : -1);
  std::vector<std::int64_t> ids;
  if (reader < 0) return ids;
  for (std::int64_t id = kNodes * reader / readers; id < kNodes * (reader + 1) / readers; ++id)
    ids.push_back(id);
  return ids;
}

std::string shared_path(const char* name) {
  int pid = ::getpid();
  MPI_Bcast(&pid, 1, MPI_INT, 0, PETSC_COMM_WORLD);
  return (std::filesystem::temp_directory_path() / ("lem_ckpt_" + std::to_string(pid) + "_" + name))
      .string();
}

// Every rank must refuse the file with the same message, naming `why`.
void expect_refused_everywhere(const std::string& path, const std::string& why) {
  std::string message;
  try {
    read_checkpoint_file(PETSC_COMM_WORLD, path, block_ids());
  } catch (const InputError& e) {
    message = e.what();
  }
  EXPECT_NE(message.find(why), std::string::npos) << "rank " << world_rank() << ": " << message;
  std::string first = message;
  int length = static_cast<int>(first.size());
  MPI_Bcast(&length, 1, MPI_INT, 0, PETSC_COMM_WORLD);
  first.resize(static_cast<std::size_t>(length));
  MPI_Bcast(first.data(), length, MPI_CHAR, 0, PETSC_COMM_WORLD);
  EXPECT_EQ(message, first) << "rank " << world_rank();
}

}  // namespace

TEST(CheckpointFile, AnotherPartitionReadsItsNodesById) {
  for (const bool check_field : {false, true}) {
    // A learnt space of two columns with the check field.
    const int columns = check_field ? 2 : 0;
    const std::string path = shared_path("partition.bin");
    write_checkpoint_file(PETSC_COMM_WORLD, path,
                          checkpoint_of(strided_ids(), check_field, columns), strided_ids());
    const auto mine = block_ids();
    const Checkpoint c = read_checkpoint_file(PETSC_COMM_WORLD, path, mine);
    EXPECT_EQ(c.state.tally.steps, 17);
    EXPECT_EQ(c.damage.bond_events, (std::vector<std::int64_t>{4, 9}));
    ASSERT_EQ(c.displacement.size(), 3 * mine.size());
    ASSERT_EQ(c.check_displacement.size(), check_field ? 3 * mine.size() : 0);
    ASSERT_EQ(c.learnt_space.size(), static_cast<std::size_t>(columns));
    for (std::size_t n = 0; n < mine.size(); ++n)
      for (int a = 0; a < 3; ++a) {
        ASSERT_EQ(c.displacement[3 * n + a], value_of(mine[n], a, 0)) << "node " << mine[n];
        if (check_field) {
          ASSERT_EQ(c.check_displacement[3 * n + a], value_of(mine[n], a, 1)) << mine[n];
        }
        for (int j = 0; j < columns; ++j)
          ASSERT_EQ(c.learnt_space[static_cast<std::size_t>(j)][3 * n + a],
                    value_of(mine[n], a, 2 + j))
              << "node " << mine[n] << ", column " << j;
      }
    // Exactly its head, 8 bytes per value and the field checksum: no value twice.
    const auto fields = static_cast<std::uintmax_t>(1 + (check_field ? 1 : 0) + columns);
    const auto size = std::filesystem::file_size(path);
    EXPECT_GT(size, fields * 24 * kNodes + 8);
    EXPECT_LT(size, fields * 24 * kNodes + 8 + 1000);
    MPI_Barrier(PETSC_COMM_WORLD);
    if (world_rank() == 0) std::remove(path.c_str());
  }
}

TEST(CheckpointFile, AChangedOrNonFiniteValueIsRefusedOnEveryRank) {
  const std::string path = shared_path("refused.bin");
  write_checkpoint_file(PETSC_COMM_WORLD, path, checkpoint_of(strided_ids(), true), strided_ids());
  const auto size = std::filesystem::file_size(path);
  MPI_Barrier(PETSC_COMM_WORLD);
  if (world_rank() == 0) {  // one byte of node 500's displacement
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(size - 8 - 2 * 24 * kNodes + 24 * 500 + 3));
    f.put('\x5a');
  }
  MPI_Barrier(PETSC_COMM_WORLD);
  expect_refused_everywhere(path, "checksum mismatch");

  Checkpoint c = checkpoint_of(strided_ids(), true);
  const auto ids = strided_ids();
  for (std::size_t n = 0; n < ids.size(); ++n)
    if (ids[n] == 700) c.check_displacement[3 * n + 1] = std::nan("");
  write_checkpoint_file(PETSC_COMM_WORLD, path, c, ids);
  expect_refused_everywhere(path, "check field value 2101 is not finite");
  MPI_Barrier(PETSC_COMM_WORLD);
  if (world_rank() == 0) std::remove(path.c_str());
}
