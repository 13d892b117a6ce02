// Routing by key at 1 to 4 ranks: every item reaches the rank its key names,
// in source order, also when the exchange goes in many small rounds; the
// owner directory answers for ids it never saw whole; questions get their
// answers back in the order asked.
#include "lem/redistribute.hpp"

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
    for (std::size_t k = 0; k < mine.size(); ++k) to[k] = destination(world_rank(), static_cast<int>(k));
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

TEST(Redistribute, DirectoryKnowsEveryOwnerAndQuestionsComeBackInOrder) {
  // 1 003 ids dealt out in an order that is not by block: id owned by
  // (id * 5 + 2) % ranks.
  const std::int64_t total = 1003;
  const auto owner_of = [&](std::int64_t id) { return static_cast<int>((id * 5 + 2) % world_size()); };
  std::vector<std::int64_t> owned;
  for (std::int64_t id = total - 1; id >= 0; --id)
    if (owner_of(id) == world_rank()) owned.push_back(id);
  const OwnerDirectory directory(PETSC_COMM_WORLD, total, owned);
  std::vector<std::int64_t> asked;
  for (std::int64_t id = world_rank(); id < total; id += 3) asked.push_back((id * 11) % total);
  asked.push_back(asked.front());  // the same id twice
  const std::vector<int> owners = directory.owners(asked);
  ASSERT_EQ(owners.size(), asked.size());
  for (std::size_t k = 0; k < asked.size(); ++k) EXPECT_EQ(owners[k], owner_of(asked[k])) << asked[k];
  // Every rank keeps at most its share of the entries.
  for (std::int64_t id = 0; id < total; ++id) {
    EXPECT_GE(directory.home(id), 0);
    EXPECT_LT(directory.home(id), world_size());
  }

  // Ask each id's owner for 3 * id + (its rank): answers in the order asked.
  const std::vector<std::int64_t> values =
      ask<std::int64_t>(PETSC_COMM_WORLD, asked, owners, [&](std::int64_t id) {
        return 3 * id + world_rank();
      });
  for (std::size_t k = 0; k < asked.size(); ++k)
    EXPECT_EQ(values[k], 3 * asked[k] + owner_of(asked[k]));
}
