// The ground floor at 1 and 2 ranks: an error on some ranks becomes the same
// error, of the same type, on every rank; the elastic system leaks no PETSc
// object and no log stage when its constructor throws.
#include "lem/base/collective.hpp"
#include "lem/system/elastic_system.hpp"
#include "lem/base/error.hpp"
#include "lem/base/log.hpp"
#include "lem/setup/setup.hpp"

#include "../world.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

using namespace lem;

namespace {

/// Runs `work` collectively and returns the exit status and message of the
/// error every rank ends up with (0 and "" without one).
template <class Work>
std::pair<int, std::string> agreed(Work&& work) {
  try {
    run_collectively(PETSC_COMM_WORLD, work);
  } catch (const std::exception& e) {
    return {exit_status(e), e.what()};
  }
  return {0, ""};
}

class OwnError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace

TEST(Agreement, NoErrorReturnsEverywhere) {
  EXPECT_EQ(agreed([] {}), std::make_pair(0, std::string()));
}

TEST(Agreement, ErrorOfTheLastRankReachesEveryRankWithItsType) {
  const int last = world_size() - 1;
  EXPECT_EQ(agreed([&] {
              if (world_rank() == last)
                throw NumericalError("diverged on rank " + std::to_string(last));
            }),
            std::make_pair(2, "diverged on rank " + std::to_string(last)));
  EXPECT_EQ(agreed([&] {
              if (world_rank() == last) throw Interrupted("stopped");
            }).first,
            4);
  EXPECT_THROW(run_collectively(PETSC_COMM_WORLD,
                                [&] {
                                  if (world_rank() == last) throw IoError("disk full");
                                }),
               IoError);
  EXPECT_THROW(run_collectively(PETSC_COMM_WORLD,
                                [&] {
                                  if (world_rank() == last)
                                    throw std::invalid_argument("bad slice");
                                }),
               std::invalid_argument);
}

TEST(Agreement, LowestFailingRankWins) {
  // Rank 0 has bad input, the others something else: all report the input.
  EXPECT_EQ(agreed([] {
              if (world_rank() == 0) throw InputError("-x = 3 is out of range");
              throw std::runtime_error("other");
            }),
            std::make_pair(1, std::string("-x = 3 is out of range")));
}

TEST(Agreement, FailingRankKeepsItsOwnExceptionOthersGetItsKind) {
  try {
    run_collectively(PETSC_COMM_WORLD, [] {
      if (world_rank() == 0) throw OwnError("own");
    });
    ADD_FAILURE() << "no exception";
  } catch (const OwnError& e) {
    EXPECT_EQ(world_rank(), 0);
  } catch (const std::runtime_error& e) {
    EXPECT_NE(world_rank(), 0);
    EXPECT_STREQ(e.what(), "own");
    EXPECT_EQ(exit_status(e), 3);
  }
}

TEST(Agreement, RunOnRootKeepsANumericalFailure) {
  // It used to become a generic error (exit status 3 instead of 2).
  int calls = 0;
  EXPECT_EQ(agreed([&] {
              run_on_root(PETSC_COMM_WORLD, [&] {
                ++calls;
                throw NumericalError("NaN in the serial stage");
              });
            }),
            std::make_pair(2, std::string("NaN in the serial stage")));
  EXPECT_EQ(calls, world_rank() == 0 ? 1 : 0);
  EXPECT_THROW(run_on_root(PETSC_COMM_WORLD, [] { throw PetscFailure("KSPSolve", 77); }),
               PetscFailure);
}

namespace {

int current_stage() {
  PetscStageLog log = nullptr;
  int stage = -1;
  PetscLogGetStageLog(&log);
  PetscStageLogGetCurrent(log, &stage);
  return stage;
}

/// PETSc objects created and not destroyed on this rank, over every stage
/// and class (counted once default logging is on).
long live_objects() {
  PetscStageLog log = nullptr;
  PetscLogGetStageLog(&log);
  long live = 0;
  for (int s = 0; s < log->numStages; ++s) {
    const PetscClassPerfLog classes = log->stageInfo[s].classLog;
    for (int c = 0; c < classes->numClasses; ++c)
      live += classes->classInfo[c].creations - classes->classInfo[c].destructions;
  }
  return live;
}

DistributedLattice small_lattice() {
  SetupReport report;
  return setup_tension_lattice(
      PETSC_COMM_WORLD,
      [](SampleInfo& info) {
        Lattice l = make_fcc_lattice({3, 3, 3}, 1.0, 1.0);
        info.stats = lattice_stats(l);
        info.affine = affine_moduli(l);
        return l;
      },
      report);
}

}  // namespace

TEST(Raii, LogStageScopePopsWhenLeftByAnException) {
  const int before = current_stage();
  try {
    LogStageScope stage("Ground floor test");
    EXPECT_NE(current_stage(), before);
    throw std::runtime_error("leave");
  } catch (const std::runtime_error&) {
  }
  EXPECT_EQ(current_stage(), before);
}

TEST(Raii, ElasticSystemConstructorThrowingLeaksNothing) {
  ASSERT_EQ(PetscLogDefaultBegin(), 0);
  DistributedLattice lattice = small_lattice();
  { ElasticSystem warm_up(lattice, SolverOptions{}); }  // PETSc's own first-use objects
  const long live = live_objects();
  const int stage = current_stage();
  { ElasticSystem fine(lattice, SolverOptions{}); }
  EXPECT_EQ(live_objects(), live);

  // An unknown matrix type makes MatSetFromOptions fail (an InputError
  // naming the option) after the vectors and the matrix exist, inside the
  // "Assembly" log stage.
  ASSERT_EQ(PetscOptionsSetValue(nullptr, "-mat_type", "no_such_type"), 0);
  ASSERT_EQ(PetscPushErrorHandler(PetscReturnErrorHandler, nullptr), 0);  // no trace printed
  EXPECT_THROW(ElasticSystem broken(lattice, SolverOptions{}), InputError);
  PetscPopErrorHandler();
  ASSERT_EQ(PetscOptionsClearValue(nullptr, "-mat_type"), 0);
  EXPECT_EQ(live_objects(), live);
  EXPECT_EQ(current_stage(), stage);
}

// Transfers go in pieces, so that byte counts beyond int fit: the same
// values with pieces of 7 bytes and with one broadcast per rank instead of
// one MPI_Allgatherv.
TEST(Transfers, PiecesGiveTheSameValues) {
  std::vector<double> mine(5 + 3 * world_rank());
  for (std::size_t i = 0; i < mine.size(); ++i)
    mine[i] = 100.0 * world_rank() + static_cast<double>(i);
  EXPECT_EQ(allgather(PETSC_COMM_WORLD, mine, 0), allgather(PETSC_COMM_WORLD, mine));
  std::vector<double> values = mine;
  broadcast(PETSC_COMM_WORLD, values, world_size() - 1, 7);
  std::vector<double> expected(5 + 3 * (world_size() - 1));
  for (std::size_t i = 0; i < expected.size(); ++i)
    expected[i] = 100.0 * (world_size() - 1) + static_cast<double>(i);
  EXPECT_EQ(values, expected);
  if (world_size() < 2) return;
  std::vector<char> text(1000);
  for (std::size_t i = 0; i < text.size(); ++i) text[i] = static_cast<char>('a' + i % 26);
  if (world_rank() == 0) send_bytes(PETSC_COMM_WORLD, text.data(), text.size(), 1, 5, 7);
  if (world_rank() == 1) {
    std::vector<char> got(text.size());
    receive_bytes(PETSC_COMM_WORLD, got.data(), got.size(), 0, 5, 7);
    EXPECT_EQ(got, text);
  }
}

// Rank 0 fails while building the pieces: the others, waiting for theirs,
// get the same error instead of waiting for ever.
TEST(Transfers, ScatterFailingOnRootEndsEveryRank) {
  Lattice lattice;
  TensionConstraints constraints;
  Partition partition;
  std::vector<std::uint8_t> faces;
  if (world_rank() == 0) {
    lattice = make_fcc_lattice({2, 2, 2}, 1.0, 1.0);
    faces = face_flags(lattice);
    constraints = make_tension_constraints(lattice, faces);
    partition = partition_lattice(lattice, constraints.bond_active, world_size());
    partition.parts = world_size() + 1;  // not this communicator's
  }
  EXPECT_THROW(distribute_lattice(PETSC_COMM_WORLD, lattice, constraints, partition, faces),
               std::logic_error);
}
