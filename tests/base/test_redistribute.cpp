// Routing by key at 1 to 4 ranks: every item reaches the rank its key names,
// in source order, also when the exchange goes in many small rounds;
// questions get their answers back in the order asked; row blocks cover
// every row once.
#include "lem/base/redistribute.hpp"

#include "../world.hpp"

#include <gtest/gtest.h>
#include <petscsys.h>

#include <cstdint>
#include <vector>

using namespace lem;

namespace {

struct Item {
  std::int64_t id;
  double value;
  std::int32_t source, pad;
};

// Rank r sends 100 + 37 r items; item k goes to rank (k * 7 + r) % ranks.
std::vector<Item> items_of(int r) {
  std::vector<Item> items;
  for (int k = 0; k < 100 + 37 * r; ++k) items.push_back({1000 * r + k, 0.5 * k - r, r, 0});
  return items;
}
int destination(int r, int k) { return (k * 7 + r) % world_size(); }

}  // namespace

TEST(Redistribute, ItemsReachTheirRankInSourceOrderInAnyRoundSize) {
  // 1 GiB rounds (one round), and 40-byte rounds (a part of an item per
  // round and pair: items cross round boundaries).
  for (const std::uint64_t round_bytes : {kRoundBytes, std::uint64_t(40)}) {
    const std::vector<Item> mine = items_of(world_rank());
    std::vector<int> to(mine.size());
    for (std::size_t k = 0; k < mine.size(); ++k)
      to[k] = destination(world_rank(), static_cast<int>(k));
    std::vector<int> from;
    const std::vector<Item> got = route(PETSC_COMM_WORLD, mine, to, &from, round_bytes);
    std::vector<Item> expected;
    std::vector<int> expected_from;
    for (int r = 0; r < world_size(); ++r) {
      const std::vector<Item> theirs = items_of(r);
      for (std::size_t k = 0; k < theirs.size(); ++k)
        if (destination(r, static_cast<int>(k)) == world_rank()) {
          expected.push_back(theirs[k]);
          expected_from.push_back(r);
        }
    }
    ASSERT_EQ(got.size(), expected.size()) << "round of " << round_bytes << " bytes";
    for (std::size_t k = 0; k < got.size(); ++k) {
      EXPECT_EQ(got[k].id, expected[k].id);
      EXPECT_EQ(got[k].value, expected[k].value);
      EXPECT_EQ(got[k].source, expected[k].source);
    }
    EXPECT_EQ(from, expected_from);
  }
}

TEST(Redistribute, QuestionsComeBackInTheOrderAsked) {
  // 1 003 ids dealt out by a rule that is not by block: id owned by
  // (id * 5 + 2) % ranks; every rank asks in its own order, once twice.
  const std::int64_t total = 1003;
  const auto owner_of = [&](std::int64_t id) {
    return static_cast<int>((id * 5 + 2) % world_size());
  };
  std::vector<std::int64_t> asked;
  std::vector<int> owners;
  for (std::int64_t id = world_rank(); id < total; id += 3) asked.push_back((id * 11) % total);
  asked.push_back(asked.front());
  for (const std::int64_t id : asked) owners.push_back(owner_of(id));
  // Each owner answers 3 * id + its rank.
  const std::vector<std::int64_t> values =
      ask<std::int64_t>(PETSC_COMM_WORLD, asked, owners,
                        [&](std::int64_t id) { return 3 * id + world_rank(); });
  ASSERT_EQ(values.size(), asked.size());
  for (std::size_t k = 0; k < asked.size(); ++k)
    EXPECT_EQ(values[k], 3 * asked[k] + owner_of(asked[k])) << asked[k];
  // Blocks of rows: every row in exactly one block, in rank order.
  const RowBlocks blocks(total, world_size());
  for (int r = 0; r < world_size(); ++r)
    for (std::int64_t row = blocks.begin(r); row < blocks.begin(r + 1); ++row)
      EXPECT_EQ(blocks.rank_of(row), r);
  EXPECT_EQ(blocks.begin(world_size()), total);
}
